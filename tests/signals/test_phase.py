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
    phase: within 1.5e-5 of the float64 functions (the float32 rounding of 1 - 2 s^2 at y = 0.5)."""
    import numpy as np
    from salkit.signals.phase import sincos_cycles
    y = np.linspace(-0.5, 0.5, 2001)
    s = np.array([sincos_cycles(np.float32(v))[0] for v in y])
    c = np.array([sincos_cycles(np.float32(v))[1] for v in y])
    assert np.max(np.abs(s - np.sin(2 * np.pi * y))) < 1.5e-5
    assert np.max(np.abs(c - np.cos(2 * np.pi * y))) < 1.5e-5
