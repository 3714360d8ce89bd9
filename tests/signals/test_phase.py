"""Phase wrapping."""
import numpy as np

from salkit.signals.phase import wrap


def test_wrap_range_and_identity():
    x = np.linspace(-20, 20, 4001)
    w = wrap(x)
    assert w.min() >= -np.pi and w.max() < np.pi
    np.testing.assert_allclose(np.exp(1j * w), np.exp(1j * x), atol=1e-12)
