"""Stripmap backprojection: shift-invariant, its azimuth response the same everywhere in the swath."""
import pytest

from salkit import focus, measure, simulate
from salkit.params import parse_scenario

from ..conftest import STRIP, merge


@pytest.mark.parametrize("x", [-0.2, 0.0, 0.2])
def test_azimuth_irw_independent_of_position(x):
    sc = parse_scenario(merge(STRIP, scene={"points": [{"x": x, "y": 0.0}]}))
    m = measure(focus(simulate(sc), sc.processing, algorithm="bp"))
    assert m["irw_azimuth_m"] == pytest.approx(m["irw_azimuth_theory_m"], rel=0.03)
    assert abs(m["peak_offset_azimuth_m"]) < 0.1 * m["resolution_azimuth_theory_m"]
