"""Amplitude weighting windows and their theoretical impulse-response figures."""
from __future__ import annotations


import numpy as np
import lazy_loader as _lazy
from ..choices import WINDOWS, check_choice

# loaded on first use (scipy.signal costs 0.5 s to import); the parent, scipy, is light
_signal = _lazy.load("scipy.signal", suppress_warning=True)


def window(name: str, n: int, nbar: int = 4, sll: float = 35.0) -> np.ndarray:
    """Amplitude window of length ``n``.

    Parameters
    ----------
    name : {"none", "hamming", "taylor"}
    n : int
    nbar, sll : Taylor parameters (number of equal sidelobes, sidelobe level in dB, positive).

    Returns
    -------
    float64 (n,)
        Peak 1 for ``hamming`` (Taylor normalised to 1 at the centre), all ones for ``none``.
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




class Window:
    """A named amplitude window with its parameters, callable as ``w(n) -> ndarray``.

    Parameters
    ----------
    name : {"none", "hamming", "taylor"}
    nbar : int
        Taylor: number of nearly equal sidelobes.
    sll : float
        Taylor: sidelobe level, dB (positive).

    Examples
    --------
    >>> w = Window("hamming")
    >>> w(5).round(2).tolist()
    [0.08, 0.54, 1.0, 0.54, 0.08]
    >>> Window("none")(3).tolist()
    [1.0, 1.0, 1.0]
    """

    __slots__ = ("name", "nbar", "sll")

    def __init__(self, name: str = "none", nbar: int = 4, sll: float = 35.0):
        check_choice("window", name, WINDOWS)
        self.name, self.nbar, self.sll = name, int(nbar), float(sll)

    def __call__(self, n: int) -> np.ndarray:
        return window(self.name, n, self.nbar, self.sll)

    def __repr__(self) -> str:
        return f"Window({self.name!r}, nbar={self.nbar}, sll={self.sll:g})"
