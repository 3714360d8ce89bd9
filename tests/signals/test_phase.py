"""Phase wrapping."""
import numpy as np

from salkit.signals.phase import wrap


def test_wrap_range_and_identity():
    x = np.linspace(-20, 20, 4001)
    w = wrap(x)
    assert w.min() >= -np.pi and w.max() < np.pi
    np.testing.assert_allclose(np.exp(1j * w), np.exp(1j * x), atol=1e-12)


def test_sincos_cycles_polynomial_accuracy():
    """The float32 sin/cos of 2 pi y on [-0.5, 0.5] cycles, used by every kernel that rotates a
    phase: within 5e-6 of the float64 functions (4.3e-6 measured: minimax half-angle polynomials,
    9.4e-7 relative and 4.7e-8, doubled, and float32 rounding), on a grid fine enough to find the
    ripples' peaks; and small phases to a part in a million of themselves."""
    import numpy as np
    from salkit.signals.phase import sincos_cycles
    y = np.linspace(-0.5, 0.5, 20001)
    s = np.array([sincos_cycles(np.float32(v))[0] for v in y])
    c = np.array([sincos_cycles(np.float32(v))[1] for v in y])
    y = y.astype(np.float32).astype(np.float64)  # the arguments the polynomial saw
    assert np.max(np.abs(s - np.sin(2 * np.pi * y))) < 5e-6
    assert np.max(np.abs(c - np.cos(2 * np.pi * y))) < 5e-6
    small = (np.abs(y) > 1e-4) & (np.abs(y) < 0.05)
    assert np.max(np.abs(s[small] / np.sin(2 * np.pi * y[small]) - 1)) < 2.5e-6


def test_sincos_cycles_scaled_is_the_weighted_sin_and_cos():
    """w sin and w cos from the folded double angle: the unweighted polynomial's values times w,
    to float32 rounding, for weights of any size and zero."""
    from numba import njit

    from salkit.signals.phase import sincos_cycles, sincos_cycles_scaled

    @njit
    def both(y, w):
        s, c = sincos_cycles(y)
        ws, wc = sincos_cycles_scaled(y, w)
        return s * w, c * w, ws, wc

    for v in np.linspace(-0.5, 0.5, 101):
        for w in (0.0, 1.0, 0.37, 250.0):
            s, c, ws, wc = both(np.float32(v), np.float32(w))
            assert abs(ws - s) <= 4e-7 * max(w, 1e-30) and abs(wc - c) <= 4e-7 * max(w, 1e-30)
            assert abs(ws - w * np.sin(2 * np.pi * np.float32(v))) < 6e-6 * max(w, 1e-30)
