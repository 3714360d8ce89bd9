"""The allowed choices, named once."""
import time

import pytest

from salkit.errors import ResourceError, ScenarioError
from salkit.params import parse_scenario
from salkit.resources import available_memory, check_memory, parse_size, set_limit

from .conftest import SPOT, merge


def test_the_papers_tables_load():
    """The papers' tables load, each row as long as its axis (the formers are declared, not listed
    here: tests/focus/test_formers.py)."""
    from salkit.papers import published
    t3 = published()["seed002"]["table3"]
    assert all(len(v) == len(t3["r1"]) for v in t3["rows"].values())
