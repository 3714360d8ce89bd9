"""Backprojection: the image is the sum over pulses of the per-pulse contributions, and a point
focuses at the peak value its normalisation promises, at 200 km where float32 ranges fail."""
import numpy as np

from salkit import simulate
from salkit.focus import phase_history
from salkit.focus.bp_kernel import backproject, pulse_contributions
from salkit.geometry.collection import grid_axes, plane_from
from salkit.params import parse_scenario

from ..conftest import GEO, SPOT, merge


def _setup(base):
    sc = parse_scenario(merge(base, scene={"points": [{"x": 0.0, "y": 0.0}]}))
    ph = phase_history(simulate(sc))
    g = sc.processing.grid.model_copy(update={"nx": 16, "ny": 12})
    plane = plane_from(ph.track, ph.center_position, g.plane)
    az, rg = grid_axes(g)
    return ph, plane, az, rg


def test_image_is_the_sum_of_pulse_contributions():
    ph, plane, az, rg = _setup(SPOT)
    P, M = ph.data.shape
    W = np.ones((az.size, P), np.float32)
    img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, plane.points(az, np.zeros_like(az)),
                      plane.range, rg, W, np.ones(M))
    pts = np.stack([plane.points(np.full(rg.size, a), rg) for a in az]).reshape(-1, 3)
    c = pulse_contributions(ph.data, ph.freq, ph.positions, ph.reference_range, pts, np.ones(M))
    np.testing.assert_allclose(c.sum(axis=0).reshape(img.shape), img, rtol=1e-4, atol=1e-3 * np.abs(img).max())


def test_point_at_200_km_peaks_at_pulses_times_samples():
    ph, plane, az, rg = _setup(GEO)
    P, M = ph.data.shape
    img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, plane.points(az, np.zeros_like(az)),
                      plane.range, rg, np.ones((az.size, P), np.float32), np.ones(M))
    i, j = np.unravel_index(np.argmax(np.abs(img)), img.shape)
    assert (az[i], rg[j]) == (0.0, 0.0)
    assert abs(img[i, j]) / (P * M) > 0.95  # unit point, coherent sum: the phase is right everywhere
