"""Linear-FM chirps with a nonlinear sweep, and the dechirped beat of a delayed copy (the
reference channel of seed 002): waveform models used by the simulator and by the corrections."""
from __future__ import annotations

import math

import numpy as np

TWO_PI = 2 * math.pi


def nonlinear_phase(t: np.ndarray, coeffs) -> np.ndarray:
    """Phase error e(t) of a sweep f(t) = f0 + k t + sum_n coeffs[n-2] t^n.

    Parameters
    ----------
    t : ndarray
        Time, s.
    coeffs : sequence of float
        Coefficients of t^2, t^3, ... of the frequency sweep, Hz/s^n.

    Returns
    -------
    ndarray
        rad.
    """
    e = np.zeros_like(t, dtype=np.float64)
    for i, c in enumerate(coeffs):
        n = i + 2
        e += TWO_PI * c * t ** (n + 1) / (n + 1)
    return e


def reference_beat(t: np.ndarray, f0: float, k: float, coeffs, delay: float, table=None) -> np.ndarray:
    """Dechirped reference channel exp(j [Phi(t - D) - Phi(t)]) for delay D, unit amplitude.

    Parameters
    ----------
    t : ndarray
        Fast time, s.
    f0 : float
        Frequency at t = 0, Hz.
    k : float
        Linear chirp rate, Hz/s.
    coeffs : sequence of float
        Nonlinear sweep coefficients (see :func:`nonlinear_phase`).
    delay : float
        Delay D of the reference path, s.
    table : (t_tab, e_tab), optional
        An arbitrary chirp phase error e(t) (s, rad), interpolated linearly.

    Returns
    -------
    complex ndarray
    """
    lin = -(f0 + k * t) * delay + 0.5 * k * delay ** 2
    lin = TWO_PI * (lin - np.floor(lin))
    ph = lin + nonlinear_phase(t - delay, coeffs) - nonlinear_phase(t, coeffs)
    if table is not None:
        ph = ph + np.interp(t - delay, *table) - np.interp(t, *table)
    return np.exp(1j * ph)


__all__ = ["TWO_PI", "nonlinear_phase", "reference_beat"]
