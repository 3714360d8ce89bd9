"""FFBP's leaf kernels: the least-squares interpolation tables against Lagrange on band-limited
signals, their polynomial form against the float64 weights, and the leaves' series for
R - |X - c| against the exact quotient."""
import numpy as np
import pytest

from salkit.focus.ffbp_leaves import interpolation_table, least_squares_weights, polynomial_weights


def _bandlimited(os, n=2048, seed=0):
    """Samples of a random signal flat in |f| < 1/(2 os) cycles/sample, and an exact evaluator."""
    rng = np.random.default_rng(seed)
    f = (np.arange(n) / n - 0.5) / os
    a = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    at = lambda x: np.exp(2j * np.pi * np.outer(x, f)) @ a  # noqa: E731
    return at(np.arange(64, dtype=float)), at


@pytest.mark.parametrize("taps, os, limit_db, gain_db", [(6, 1.75, -47.0, 12.0), (8, 1.75, -60.0, 12.0),
                                                         (4, 4.0, -60.0, 6.0)])
def test_interpolation_table_error_on_band_limited_signals(taps, os, limit_db, gain_db):
    """The least-squares kernel interpolates a band-limited signal to its design accuracy (flat
    spectrum: -50, -64 and -70 dB expected), far better than Lagrange at the same taps."""
    s, at = _bandlimited(os)
    W = interpolation_table(taps, os)
    x = np.random.default_rng(1).uniform(taps, 64 - taps, 400)
    i0 = np.floor(x).astype(int)
    t = x - i0
    offs = np.arange(-(taps // 2 - 1), taps // 2 + 1)
    est = np.sum(W[np.rint(t * (W.shape[0] - 1)).astype(int)] * s[i0[:, None] + offs], axis=1)
    truth = at(x)
    err = 10 * np.log10(np.sum(np.abs(est - truth) ** 2) / np.sum(np.abs(truth) ** 2))
    assert err < limit_db
    lag = np.ones((t.size, taps))
    for i, oi in enumerate(offs):
        for j, oj in enumerate(offs):
            if i != j:
                lag[:, i] *= (t - oj) / (oi - oj)
    err_lag = 10 * np.log10(np.sum(np.abs(np.sum(lag * s[i0[:, None] + offs], axis=1) - truth) ** 2)
                            / np.sum(np.abs(truth) ** 2))
    assert err < err_lag - gain_db


def test_leaf_series_equals_the_exact_quotient(monkeypatch):
    """The leaves' series for R - |X - c| (no square root or division) against the exact
    quotient, on the wide-angle arc where it is used: the same image to -100 dB."""
    import salkit.focus.ffbp as F
    from salkit.focus import phase_history
    from salkit.focus.formers import ImageGrid
    from salkit.simulate.testbeds import wide_angle
    tb = wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.point_targets(64, count=3)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(64))
    P, M = ph.data.shape
    a, _ = F.ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M))
    monkeypatch.setattr(F, "SERIES", False)
    b, _ = F.ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M))
    assert np.sum(np.abs(a - b) ** 2) <= 1e-10 * np.sum(np.abs(b) ** 2)  # -100 dB (often identical in float32)


@pytest.mark.parametrize("os", [1.25, 1.5, 1.75, 2.0, 3.0, 4.0])
def test_polynomial_weights_equal_the_least_squares_weights(os):
    """The weights' polynomials (evaluated in float32, as the kernels do) stay within 2e-5 of
    the float64 least-squares weights at every fraction, closer than the table's nearest entry."""
    t = np.random.default_rng(2).uniform(0.0, 1.0, 5000)
    c = polynomial_weights(8, os)
    s = (2.0 * t - 1.0).astype(np.float32)
    w = np.zeros((t.size, 8), np.float32)
    for d in range(c.shape[1] - 1, -1, -1):  # Horner in float32
        w = w * s[:, None] + c[:, d][None, :]
    exact = least_squares_weights(8, os, t)
    assert np.abs(w - exact).max() < 2e-5
    table = interpolation_table(8, os)
    nearest = table[np.rint(t * (table.shape[0] - 1)).astype(int)]
    assert np.abs(w - exact).max() < np.abs(nearest - exact).max()
