"""Collection geometry: resolution theory, reference range, where targets appear, angles."""
import math

import numpy as np
import pytest

from salkit.errors import SamplingError, ScenarioError
from salkit.geometry import build_collection, check_sampling, resolution_theory, truth_positions
from salkit.geometry.sampling import delay_spread, n_fast_samples
from salkit.params import parse_scenario

from ..conftest import SPOT, STRIP, merge


C = 299792458.0


def test_spotlight_resolution_theory(spot):
    res = resolution_theory(spot)
    col = build_collection(spot)
    du = spot.platform.speed / spot.waveform.prf
    # lambda R / (2 L) with L = N du for N pulses
    assert res["azimuth"] == pytest.approx(1.55e-6 * 5000 / (2 * col.n_pulses * du), rel=1e-6)
    assert res["slant_range"] == pytest.approx(C / (2 * res["bandwidth_eff"]))
    assert res["bandwidth_eff"] == pytest.approx(7.5e9, rel=0.01)


def test_reference_range_tracks_scene_centre(spot):
    col = build_collection(spot)
    np.testing.assert_allclose(col.reference_range, np.linalg.norm(col.positions, axis=1))


def test_truth_positions_slant_plane(spot):
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.3, "y": 0.4, "z": 0.0}]}))
    t = truth_positions(sc)[0]
    # distance from the track is preserved: slant offset = |(0, 0.4, 0) - track| - R0
    d = np.hypot(0.4 + 4000.0, 3000.0) - 5000.0
    assert t[0] == pytest.approx(0.3)
    assert t[1] == pytest.approx(d, abs=1e-9)


def test_angle_between_is_accurate_at_tiny_angles():
    """acos of a dot product returns 0 below ~1e-8 rad (a 0.2 m aperture at 13,000 km)."""
    import math
    from salkit.geometry.collection import angle_between
    for a in (1e-12, 1.5e-8, 1e-3, 1.0, 3.0):
        assert angle_between([1.0, 0, 0], [math.cos(a), math.sin(a), 0]) == pytest.approx(a, rel=1e-12)


def test_beam_gain_matches_the_simulator_kernel():
    """The vectorised lookup (processors) and the compiled one (simulator) agree."""
    from salkit.geometry.collection import beam_gain, beam_gain_table
    from salkit.simulate.kernels import _beam
    table, dsin = beam_gain_table(1.55e-6, 0.05)
    s = np.linspace(0, 0.9 * dsin * (table.size - 1), 57)
    ref = np.array([_beam(math.sin(math.asin(v)), 0.0, math.cos(math.asin(v)), 1.0, 0.0, 0.0, 1.0, table, dsin)
                    for v in s])
    # the kernel takes sin from cos (sqrt(1 - cos^2)), good to ~1e-7 near boresight
    np.testing.assert_allclose(beam_gain(table, dsin, s), ref, rtol=1e-6, atol=1e-9)
