"""The vector intrinsics: bit for bit the scalar float32 arithmetic, masked lanes untouched."""
import numpy as np
import pytest
from numba import njit

from salkit.signals.vectors import LANES, caxpy16


@njit(cache=False)
def _apply(acc_re, acc_im, w_re, w_im, n, c_re, c_im, m):
    caxpy16(acc_re, acc_im, w_re, w_im, n, c_re, c_im, m)


@pytest.mark.parametrize("m", [0, 1, 7, 15, 16])
def test_caxpy16_is_the_scalar_float32_loop_bit_for_bit(m):
    rng = np.random.default_rng(m)
    N = 53
    acc_re = rng.normal(size=N + LANES).astype(np.float32)
    acc_im = rng.normal(size=N + LANES).astype(np.float32)
    acc_re[::5] = -0.0  # signed zeros stay as they were where a lane is masked
    w_re = rng.normal(size=LANES).astype(np.float32)
    w_im = rng.normal(size=LANES).astype(np.float32)
    c_re, c_im = np.float32(rng.normal()), np.float32(-rng.normal())
    n = 29
    want_re, want_im = acc_re.copy(), acc_im.copy()
    for j in range(m):  # float32 numpy scalars: each product, difference and sum rounded to float32
        want_re[n + j] = want_re[n + j] + (c_re * w_re[j] - c_im * w_im[j])
        want_im[n + j] = want_im[n + j] + (c_re * w_im[j] + c_im * w_re[j])
    _apply(acc_re, acc_im, w_re, w_im, n, c_re, c_im, m)
    assert acc_re.tobytes() == want_re.tobytes() and acc_im.tobytes() == want_im.tobytes()


def test_caxpy16_masked_lanes_are_untouched_even_past_the_data():
    """The simulator pads its accumulators by 16 and lets the last block's masked lanes fall there
    (and on later samples): they must read back exactly, whatever the table holds there."""
    acc_re = np.arange(32, dtype=np.float32)
    acc_im = -np.arange(32, dtype=np.float32)
    w = np.full(LANES, np.float32(3.0e38))  # a masked lane's product would be infinite if it were taken
    _apply(acc_re, acc_im, w, w, 16, np.float32(10.0), np.float32(0.0), 3)
    assert np.isinf(acc_re[16:19]).all()  # the three lanes taken
    assert np.array_equal(acc_re[19:], np.arange(19, 32, dtype=np.float32))
    assert np.array_equal(acc_im[19:], -np.arange(19, 32, dtype=np.float32))
    assert np.array_equal(acc_re[:16], np.arange(16, dtype=np.float32))
