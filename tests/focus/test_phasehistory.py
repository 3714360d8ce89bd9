"""The phase history of raw data, and its resolution theory: the same as the scenario's."""
import numpy as np
import pytest

from salkit import simulate
from salkit.focus import default_grid, phase_history, theory_resolution
from salkit.geometry import build_collection, resolution_theory
from salkit.geometry.collection import plane_from
from salkit.params import parse_scenario

from ..conftest import GEO, SPOT, STRIP


@pytest.mark.parametrize("base", [SPOT, STRIP, GEO])
def test_resolution_theory_once(base):
    """From the data alone (frequencies, positions) the same numbers as from the scenario."""
    sc = parse_scenario(base)
    ph = phase_history(simulate(sc))
    data = theory_resolution(ph, plane_from(ph.track, ph.center_position, sc.processing.grid.plane))
    model = resolution_theory(sc, build_collection(sc))
    assert data["range"] == pytest.approx(model["range"], rel=1e-9)
    assert data["azimuth"] == pytest.approx(model["azimuth"], rel=1e-9)


def test_arrays_and_default_grid():
    sc = parse_scenario(SPOT)
    ph = phase_history(simulate(sc))
    assert ph.data.dtype == np.complex64 and ph.positions.dtype == np.float64
    assert np.all(np.diff(ph.freq) > 0)
    g = default_grid(ph, n=64)
    res = theory_resolution(ph, plane_from(ph.track, ph.center_position, "slant"))
    assert g.dx == pytest.approx(0.8 * res["azimuth"]) and g.nx == 64
