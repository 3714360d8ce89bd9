"""One BLAS thread for the small fits salkit makes right before its parallel kernels.

OpenBLAS (numpy's and scipy's BLAS and LAPACK) runs a call such as ``np.linalg.lstsq`` on every core
and then keeps its threads spinning for about 2^28 cycles (some 0.07 s at 3.6 GHz) before they sleep:
numba's kernels started in that time share the cores with them. FFBP's range and angle kernels were
designed at every call by a Chebyshev fit of their weights at 4097 fractions, just before the leaves
were formed: on the 2-core development VM the arc at 1024^2 took 0.13-0.14 s a call against 0.09 s
with ``OPENBLAS_NUM_THREADS=1``, and 0.09 s with the fit run on one thread. The fits salkit makes
there are small (thousands of rows, a few columns): one thread does them as fast.

Unlike OpenMP's waiting policy (:mod:`salkit._openmp`), OpenBLAS's spin time cannot be set once
numpy is imported, so the fits are run under a thread limit instead (``threadpoolctl``); the user's
own BLAS calls are left as they are.
"""
from __future__ import annotations

import contextlib
import threading

from threadpoolctl import ThreadpoolController

#: One limit at a time: the counts are the process's, and two threads' limits interleaved would
#: restore each other's (the fits it guards take milliseconds).
_lock = threading.Lock()


@contextlib.contextmanager
def serial_blas():
    """A context in which the BLAS libraries loaded in the process run on one thread.

    Returns
    -------
    context manager
        ``with serial_blas(): ...``; the previous thread counts come back on exit. Threads that
        enter it at once take turns.

    Examples
    --------
    >>> import numpy as np
    >>> with serial_blas():
    ...     x = np.linalg.lstsq(np.eye(3), np.ones(3), rcond=None)[0]
    >>> x.tolist()
    [1.0, 1.0, 1.0]
    """
    with _lock:  # the libraries loaded by now (a millisecond's look: one loaded later is limited too)
        with ThreadpoolController().limit(limits=1, user_api="blas"):
            yield
