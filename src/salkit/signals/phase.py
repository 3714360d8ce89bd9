"""Phase utilities."""
from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, inline="always", fastmath=True)
def sincos_cycles(y):
    """sin and cos of 2 pi y for y in [-0.5, 0.5] cycles, float32 polynomial (|error| < 1.5e-5): the
    argument is reduced to cycles in float64 by the caller, so phases of any size stay exact.

    Parameters
    ----------
    y : float32
        Cycles, in [-0.5, 0.5].

    Returns
    -------
    (float32, float32)
        sin, cos.
    """
    t = np.float32(math.pi) * y  # in [-pi/2, pi/2]
    t2 = t * t
    s = t * (np.float32(1.0) + t2 * (np.float32(-1.0 / 6.0) + t2 * (np.float32(1.0 / 120.0) + t2 * (
        np.float32(-1.0 / 5040.0) + t2 * np.float32(1.0 / 362880.0)))))
    c = np.float32(1.0) + t2 * (np.float32(-0.5) + t2 * (np.float32(1.0 / 24.0) + t2 * (
        np.float32(-1.0 / 720.0) + t2 * (np.float32(1.0 / 40320.0) + t2 * np.float32(-1.0 / 3628800.0)))))
    return np.float32(2.0) * s * c, np.float32(1.0) - np.float32(2.0) * s * s


def wrap(phase):
    """Wrap phase (rad) into [-pi, pi).

    Parameters
    ----------
    phase : float or array
        rad.

    Returns
    -------
    ndarray
        rad.

    Examples
    --------
    >>> wrap([3 * np.pi / 2, -np.pi]).round(4).tolist()
    [-1.5708, -3.1416]
    """
    return (np.asarray(phase) + np.pi) % (2 * np.pi) - np.pi
