"""``salkit info`` on every shipped example, ``salkit examples``."""
import json

import pytest

from ..conftest import EXAMPLES
from .conftest import salkit


@pytest.mark.parametrize("name", sorted(p.stem for p in EXAMPLES.glob("*.yaml")))
def test_info_on_every_shipped_example(name):
    """`salkit info` works where `salkit run` does (an experiment checks its own sampling), and says
    the unit of every quantity it prints."""
    r = salkit("info", EXAMPLES / f"{name}.yaml")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["name"] == name and d["units"]
    from salkit.units import NAMED
    for k, v in d.items():
        if k.endswith("_m") and k not in NAMED and isinstance(v, (int, float)):
            assert d["units"][k] == "m", k


def test_examples_listed():
    r = salkit("examples")
    assert r.returncode == 0
    for f in EXAMPLES.glob("*.yaml"):
        assert f.name in r.stdout
