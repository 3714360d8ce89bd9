"""Analytic phase histories against a direct float64 evaluation, and their dataset."""
import numpy as np
import pytest

from salkit.constants import SPEED_OF_LIGHT as C
from salkit.errors import ScenarioError
from salkit.focus import phase_history
from salkit.simulate.analytic import analytic_phase_history, phase_history_dataset


def test_recurrence_matches_direct_evaluation():
    rng = np.random.default_rng(0)
    pos = np.c_[np.linspace(-200, 200, 7), np.full(7, -7000.0), np.full(7, 7300.0)]
    ref = np.linalg.norm(pos, axis=1) + rng.uniform(-1, 1, 7)
    f = 9.29e9 + 1.47e6 * np.arange(1000)
    pts = rng.uniform(-50, 50, (5, 3))
    amp = rng.standard_normal(5) + 1j * rng.standard_normal(5)
    s = analytic_phase_history(pos, ref, f, pts, amp)
    R = np.linalg.norm(pts[None, :, :] - pos[:, None, :], axis=2) - ref[:, None]  # (P, K), fine at 10 km
    direct = np.einsum("k,pkm->pm", amp, np.exp(-1j * 4 * np.pi * f[None, None, :] * R[:, :, None] / C))
    assert np.max(np.abs(s - direct)) < 1e-8


@pytest.mark.parametrize("method", ["direct", "nufft"])
def test_exact_at_560_km(method):
    """Scatterers near the scene centre seen from 560 km at 1.55 um: the phase agrees with a
    50-digit evaluation of |x - p| - R_ref to 1e-6 rad, where differencing two float64 ranges is
    off by up to 5e-4 rad; by the direct sum and by the non-uniform FFT."""
    from decimal import Decimal, getcontext
    getcontext().prec = 50
    rng = np.random.default_rng(5)
    pos = np.c_[rng.uniform(-4, 4, 40), -560000.0 + rng.uniform(-1, 1, 40), rng.uniform(-1, 1, 40)]
    ref = np.linalg.norm(pos, axis=1) + rng.uniform(-0.01, 0.01, 40)
    x = np.array([[0.37, -1.21, 0.05]])
    f = np.array([1.934e14, 1.935e14])
    s = analytic_phase_history(pos, ref, f, x, method=method)
    exact = np.array([float(sum((Decimal(float(a)) - Decimal(float(b))) ** 2 for a, b in zip(x[0], p)).sqrt()
                            - Decimal(float(r))) for p, r in zip(pos, ref)])
    want = np.exp(-1j * 4 * np.pi * f[None, :] * exact[:, None] / C)
    assert np.max(np.abs(np.angle(s * np.conj(want)))) < 1e-6
    naive = np.linalg.norm(x - pos, axis=1) - ref
    assert np.max(np.abs(4 * np.pi * f[0] * (naive - exact) / C)) > 1e-5  # what the test guards against


@pytest.mark.parametrize("which,limit_db", [("seed_560km", -170.0), ("wide_angle", -230.0)])
def test_nufft_equals_the_direct_sum(which, limit_db):
    """Speckle of 1,843 scatterers (beyond DIRECT_MAX: "auto" takes the non-uniform FFT) at 560 km
    and 1.55 um, and on the X-band wide-angle arc: the two methods' error energy below -170 and
    -230 dB (both round phases of millions of radians in float64; at 1.55 um that is 1e-9 rad)."""
    from salkit.simulate import testbeds
    from salkit.simulate.analytic import DIRECT_MAX
    tb = testbeds.seed("560km") if which == "seed_560km" else testbeds.wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.speckle(128, extent=1.5, density=0.05, seed=1)
    assert pts.shape[0] > DIRECT_MAX
    ref = np.linalg.norm(tb.positions, axis=1)
    a = analytic_phase_history(tb.positions, ref, tb.frequency, pts, amp, method="direct")
    b = analytic_phase_history(tb.positions, ref, tb.frequency, pts, amp)
    assert 10 * np.log10(np.sum(np.abs(a - b) ** 2) / np.sum(np.abs(a) ** 2)) < limit_db
    with pytest.raises(ScenarioError, match="method"):
        analytic_phase_history(tb.positions, ref, tb.frequency, pts, amp, method="fast")


def test_dataset_reads_as_a_phase_history():
    pos = np.c_[np.linspace(-1, 1, 8), np.full(8, -1e3), np.full(8, 1e3)]
    ds = phase_history_dataset(pos, 1e10 + 1e6 * np.arange(16), np.zeros((1, 3)))
    ph = phase_history(ds)
    assert ph.data.shape == (8, 16)
    assert np.allclose(ph.reference_range, np.linalg.norm(pos, axis=1))


@pytest.mark.parametrize("kw,field", [({"frequency": np.array([1.0, 3.0, 4.0])}, "frequency"),
                                      ({"reference_range": np.ones(3)}, "reference_range"),
                                      ({"amplitudes": np.ones(3)}, "amplitudes")])
def test_bad_input_names_the_field(kw, field):
    args = {"positions": np.zeros((2, 3)), "reference_range": np.ones(2), "frequency": np.array([1.0, 2.0]),
            "points": np.zeros((1, 3)), "amplitudes": None}
    args.update(kw)
    with pytest.raises(ScenarioError, match=field):
        analytic_phase_history(**args)
