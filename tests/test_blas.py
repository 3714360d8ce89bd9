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


def test_threads_entering_at_once_take_turns_and_the_counts_come_back():
    """Limits entered from several threads at once do not restore each other's counts: after all
    of them the process's BLAS runs on as many threads as before."""
    import threading
    before = _blas_threads()
    inside = []

    def work():
        for _ in range(20):
            with serial_blas():
                inside.append(_blas_threads())
                np.linalg.lstsq(np.vander(np.linspace(-1, 1, 200), 4), np.ones(200), rcond=None)

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(n == [1] * len(before) for n in inside) and len(inside) == 80
    assert _blas_threads() == before
