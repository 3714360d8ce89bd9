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


def _circle(arc_deg: float, pulses: int = 720, elev_deg: float = 45.0) -> np.ndarray:
    phi = np.radians(arc_deg) * (np.arange(pulses) / pulses - 0.5)
    e = math.radians(elev_deg)
    return 7000.0 * np.stack([np.cos(e) * np.cos(phi), np.cos(e) * np.sin(phi), np.full_like(phi, np.sin(e))], axis=1)


def test_processed_angle_is_the_angle_swept():
    """A circle's pulses sweep cos(elev) x its arc on the unit sphere; the end-to-end angle of a full
    circle would be one step (before 0.27: a 7 m azimuth resolution for a 2 cm one)."""
    from salkit.geometry.collection import processed_angle
    for arc in (4.0, 120.0, 360.0):
        pos = _circle(arc)
        ang = processed_angle(pos, 0.03)
        assert ang == pytest.approx(math.radians(arc) * math.cos(math.radians(45.0)), rel=1e-3)


def test_support_resolution_of_a_full_circle_is_the_same_on_both_axes():
    """A full circle's support is a disc of diameter 2 x 4 pi f cos(elev)/c on every axis: the
    resolution is lambda / (4 cos(elev)) in range as in azimuth, not c/(2B)."""
    from salkit.geometry.collection import support_resolution
    pos = _circle(360.0)
    a, r = np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
    rho_r, rho_a = support_resolution(pos, 5e8, 0.03, np.array([7000.0, 0.0, 7000.0]), a, r)
    lam4 = 0.03 / (4 * math.cos(math.radians(45.0)))
    assert rho_a == pytest.approx(lam4, rel=2e-3)
    assert rho_r == pytest.approx(lam4 / (1 + 5e8 / (2 * C / 0.03)), rel=2e-3)  # the band adds to the disc's range
    narrow = support_resolution(_circle(4.0), 5e8, 0.03, np.array([7000.0, 0.0, 7000.0]), a, r)
    assert narrow[0] == pytest.approx(C / (2 * 5e8 * math.cos(math.radians(45.0))), rel=0.02)


def test_truth_positions_of_what_is_not_a_scenario_is_refused():
    """truth_positions("x.yaml") raised AttributeError ('str' object has no attribute 'platform')."""
    with pytest.raises(ScenarioError, match=r"scenario = 'x.yaml': must be a Scenario.*salkit.load_scenario"):
        truth_positions("x.yaml")
