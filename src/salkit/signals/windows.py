"""Amplitude weighting windows and their theoretical impulse-response figures."""
from __future__ import annotations

from functools import lru_cache

import numpy as np
import lazy_loader as _lazy

# loaded on first use (scipy.signal costs 0.5 s to import); the parent, scipy, is light
_signal = _lazy.load("scipy.signal", suppress_warning=True)


def window(name: str, n: int, nbar: int = 4, sll: float = 35.0) -> np.ndarray:
    """Amplitude window of length ``n``.

    Parameters
    ----------
    name : {"none", "hamming", "taylor"}
    n : int
    nbar, sll : Taylor parameters (number of equal sidelobes, sidelobe level in dB, positive).
    """
    if n <= 0:
        return np.ones(0)
    if name == "none":
        return np.ones(n)
    if name == "hamming":
        return _signal.windows.hamming(n, sym=True)
    if name == "taylor":
        return _signal.windows.taylor(n, nbar=nbar, sll=sll, norm=True, sym=True)
    raise ValueError(f"unknown window {name!r}")


@lru_cache(maxsize=64)
def window_ipr(name: str, nbar: int = 4, sll: float = 35.0, n: int = 512, up: int = 64) -> dict:
    """Theoretical IRW factor, PSLR and ISLR of a window's impulse response.

    The IRW factor multiplies the unweighted resolution (1/bandwidth): 0.886 for no window.
    ISLR integrates over +-10 resolution cells outside the main lobe (between first nulls),
    the same span that :func:`salkit.metrics.pointtarget.ipr_1d` uses.
    """
    from ..metrics.pointtarget import ipr_1d

    w = window(name, n, nbar, sll)
    spec = np.zeros(n * up, complex)
    spec[:n] = w
    h = np.fft.fftshift(np.fft.ifft(spec))
    x = (np.arange(n * up) - n * up // 2) / up  # in resolution cells (1/bandwidth)
    m = ipr_1d(h, dx=1.0 / up, resolution=1.0)
    del x
    return {"irw_factor": m["irw"], "pslr_db": m["pslr_db"], "islr_db": m["islr_db"]}
