"""The test geometries: the collections they claim to be."""
import numpy as np
import pytest

from salkit.constants import SPEED_OF_LIGHT as C
from salkit.errors import ScenarioError
from salkit.simulate.testbeds import curved, seed, wide_angle


def test_wide_angle_is_the_airborne_x_band_arc():
    tb = wide_angle(4.0, climb=0.5)
    assert tb.positions.shape == (469, 3) and tb.frequency.size == 424
    r = np.hypot(tb.positions[:, 0], tb.positions[:, 1])
    assert np.allclose(r, 7000.0)
    arc = np.degrees(np.arctan2(tb.positions[-1, 1], tb.positions[-1, 0]))
    assert arc == pytest.approx(4.0)
    assert tb.positions[-1, 2] - tb.positions[0, 2] == pytest.approx(0.5)
    dep = np.degrees(np.arctan2(tb.positions[:, 2], r))
    assert 45 < dep.mean() < 47
    slant = np.linalg.norm(tb.positions, axis=1)
    assert 10000 < slant.mean() < 10200
    assert tb.frequency[0] == 9.29e9 and tb.frequency[1] - tb.frequency[0] == pytest.approx(1.47e6)


def test_ten_degree_arc_keeps_the_angular_step_and_resolves_its_grid():
    tb = wide_angle(10.0)
    assert tb.positions.shape[0] == round(469 * 2.5)
    lam = C / tb.frequency[212]
    assert tb.dx <= 0.8 * lam / (2 * np.radians(10.0)) + 1e-3


@pytest.mark.parametrize("which,R", [("5km", 5000.0), ("200km", 200000.0), ("560km", 560000.0)])
def test_seed_geometries(which, R):
    tb = seed(which, 96)
    assert np.linalg.norm(tb.center_position) == pytest.approx(R, rel=1e-6)
    assert C / tb.frequency.mean() == pytest.approx(1.55e-6, rel=1e-3)
    # pulses and frequencies sample twice the grid's extent without ambiguity
    P = tb.positions.shape[0]
    L = np.linalg.norm(tb.positions[-1] - tb.positions[0])
    assert 1.55e-6 * R * P / (2 * L) >= 1.9 * 96 * tb.dx
    assert C / (2 * (tb.frequency[1] - tb.frequency[0])) >= 1.9 * 96 * tb.dy


def test_curved_track_deviates_by_its_amount():
    tb = curved(0.5)
    straight = np.linspace(tb.positions[0], tb.positions[-1], tb.positions.shape[0])
    dev = np.linalg.norm(tb.positions - straight, axis=1)
    assert 0.5 <= dev.max() <= 0.75


def test_speckle_is_seeded_and_bright_fraction():
    tb = wide_angle()
    a = tb.speckle(101, seed=3)
    b = tb.speckle(101, seed=3)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    pts, amp = tb.speckle(301, density=0.5, seed=4)
    frac = np.mean(np.abs(amp) > 8)
    assert 0.005 < frac < 0.015


def test_bad_arc_named():
    with pytest.raises(ScenarioError, match="arc_deg"):
        wide_angle(0.0)
    with pytest.raises(ScenarioError, match="which"):
        seed("1km")
