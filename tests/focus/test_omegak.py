"""Omega-k: stripmap only, and its image agrees with backprojection's."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.errors import ScenarioError
from salkit.params import parse_scenario

from ..conftest import SPOT, STRIP, merge


def test_omegak_matches_backprojection_on_stripmap():
    sc = parse_scenario(merge(STRIP, scene={"points": [{"x": 0.05, "y": 0.1}, {"x": -0.1, "y": -0.05, "amplitude": 0.5}]}))
    raw = simulate(sc)
    a = focus(raw, sc.processing, algorithm="omegak")["image"].values
    b = focus(raw, sc.processing, algorithm="bp")["image"].values
    corr = abs(np.vdot(np.abs(a), np.abs(b))) / np.linalg.norm(a) / np.linalg.norm(b)
    assert corr > 0.98


def test_omegak_refuses_spotlight():
    sc = parse_scenario(SPOT)
    with pytest.raises(ScenarioError, match="omegak forms stripmap collections on a straight track"):
        focus(simulate(sc), sc.processing, algorithm="omegak")
