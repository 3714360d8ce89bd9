"""The allowed choices, named once."""
import time

import pytest

from salkit.errors import ResourceError, ScenarioError
from salkit.params import parse_scenario
from salkit.resources import available_memory, check_memory, parse_size, set_limit

from .conftest import SPOT, merge


def test_choices_formers_and_papers_are_one_list():
    """The allowed algorithms are exactly the registered formers; the papers' tables load."""
    from salkit.choices import ALGORITHMS
    from salkit.focus import FORMERS
    from salkit.papers import published
    assert sorted(FORMERS) == sorted(ALGORITHMS)
    t3 = published()["seed002"]["table3"]
    assert all(len(v) == len(t3["r1"]) for v in t3["rows"].values())
