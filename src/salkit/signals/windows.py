"""Amplitude weighting windows and their theoretical impulse-response figures."""
from __future__ import annotations


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


