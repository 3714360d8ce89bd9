"""GEO relative orbit and sub-aperture geometry (seed 001 eqs 1-4)."""
import math

import numpy as np
import pytest

from salkit import focus, measure, simulate
from salkit.errors import ScenarioError
from salkit.geometry.orbit import (collection_span, max_squint_for, n_subimages, relative_speed,
                                   resolution_vs_squint, straight_line_error, subaperture_length)
from salkit.params import parse_scenario

from ..conftest import GEO, merge

R1, R2 = 41978e3, 42178e3


def test_paper_geometry():
    V = relative_speed(R1, R2)
    assert V == pytest.approx(7.3, abs=0.02)
    D = collection_span(R2 - R1, 5.0)
    assert D == pytest.approx(35e3, rel=0.001)
    L = subaperture_length(1.55e-6, R2 - R1, 0.05)
    assert L == pytest.approx(3.1, rel=1e-9)
    assert n_subimages(D, L) == pytest.approx(11290, abs=5)
    assert resolution_vs_squint(1.55e-6, R2 - R1, L, 0.0) == pytest.approx(0.05)
    th = max_squint_for(1.1)
    assert resolution_vs_squint(1.55e-6, R2 - R1, L, th) == pytest.approx(0.055)
    # the true two-orbit motion bends away from the straight line: differential gravity
    err = straight_line_error(R1, R2, 5.0)
    a = 3.986004418e14 * (1 / R1 ** 2 - 1 / R2 ** 2)
    assert err["max_range_difference_m"] == pytest.approx(0.5 * a * (err["collection_time_s"] / 2) ** 2, rel=0.05)


def test_bad_geometry():
    with pytest.raises(ScenarioError, match="squint_max_deg"):
        collection_span(2e5, 95)
    with pytest.raises(ScenarioError, match="longer than the collection"):
        n_subimages(10.0, 20.0)
    with pytest.raises(ScenarioError, match="R1 < R2"):
        relative_speed(R2, R1)
