"""The workflow of every shipped example is known, and dispatched by the scenario's kind."""
import pytest

from salkit.params import load_scenario
from salkit.systems import WORKFLOWS

from ..conftest import EXAMPLES


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.yaml")), ids=lambda p: p.stem)
def test_every_example_has_a_workflow(path):
    sc = load_scenario(path)
    assert sc.kind in WORKFLOWS
    __import__(f"salkit.systems.{WORKFLOWS[sc.kind]}")
