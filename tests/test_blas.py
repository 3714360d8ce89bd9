"""salkit._blas: the fits made before parallel kernels run on one BLAS thread, and the thread
counts come back after."""
import numpy as np
from threadpoolctl import threadpool_info

from salkit._blas import serial_blas


def _blas_threads():
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_blas_runs_on_one_thread_inside_and_as_before_after():
    before = _blas_threads()
    assert before  # numpy's BLAS is loaded
    with serial_blas():
        assert _blas_threads() == [1] * len(before)
        x = np.linalg.lstsq(np.vander(np.linspace(-1, 1, 50), 3), np.ones(50), rcond=None)[0]
    assert _blas_threads() == before
    assert np.allclose(x, [0.0, 0.0, 1.0])


def test_the_kernel_fits_give_the_same_numbers_on_one_thread():
    """The fits under the limit are the fits: FFBP's polynomial weights and the fitted four taps
    against the same computation made without it."""
    from salkit.focus import ffbp_leaves, profiles
    t = np.linspace(0.0, 1.0, 4097)
    w = ffbp_leaves.least_squares_weights(8, 1.9, t)
    cheb = np.polynomial.chebyshev.chebfit(2.0 * t - 1.0, w, 6)
    power = np.stack([np.polynomial.chebyshev.cheb2poly(cheb[:, b]) for b in range(8)]).astype(np.float32)
    assert np.array_equal(ffbp_leaves.polynomial_weights(8, 1.9), power)
    assert profiles.fitted_coefficients(123, 777).shape == (4, 4)
