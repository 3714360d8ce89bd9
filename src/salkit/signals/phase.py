"""Phase utilities."""
from __future__ import annotations

import math

import numpy as np
from numba import njit


#: sin(pi y) = y (S1 + y^2 (S3 + y^2 (S5 + y^2 S7))) and cos(pi y) = C0 + y^2 (C2 + ...) on
#: |y| <= 1/2: minimax coefficients, float32, found by Lawson's iteratively reweighted least squares
#: on 40001 points; the sine's relative error equal-ripple (9.4e-7), so that small phases stay
#: exact to a part in a million (a field multiplied by 100 layers' phases of 0.1 rad drifts by
#: 9e-6, where an absolute equal-ripple fit drifted by 3.4e-5), the cosine's absolute error (4.7e-8).
#: The Taylor terms to the same degrees err by 1e-4 and 1e-5.
SIN_PI = (3.141589641571045, -5.167367935180664, 2.543605089187622, -0.5583966374397278)
COS_PI = (0.9999999403953552, -4.934792995452881, 4.058412075042725, -1.3318802118301392, 0.21969687938690186)


@njit(cache=True, inline="always", fastmath=True)
def _half_angle(y):
    """sin(pi y) and cos(pi y) for y in [-0.5, 0.5] (float32): the minimax polynomials
    :data:`SIN_PI` and :data:`COS_PI`."""
    y2 = y * y
    s = y * (np.float32(SIN_PI[0]) + y2 * (np.float32(SIN_PI[1]) + y2 * (np.float32(SIN_PI[2])
                                                                          + y2 * np.float32(SIN_PI[3]))))
    c = np.float32(COS_PI[0]) + y2 * (np.float32(COS_PI[1]) + y2 * (np.float32(COS_PI[2]) + y2 * (
        np.float32(COS_PI[3]) + y2 * np.float32(COS_PI[4]))))
    return s, c


@njit(cache=True, inline="always", fastmath=True)
def sincos_cycles(y):
    """sin and cos of 2 pi y for y in [-0.5, 0.5] cycles, float32 polynomial (|error| < 5e-6): the
    argument is reduced to cycles in float64 by the caller, so phases of any size stay exact.

    sin and cos of the half angle pi y from minimax polynomials (:data:`SIN_PI`, :data:`COS_PI`),
    then the double angle: twelve float32 operations.

    Parameters
    ----------
    y : float32
        Cycles, in [-0.5, 0.5].

    Returns
    -------
    (float32, float32)
        sin, cos.
    """
    s, c = _half_angle(y)
    s2 = s + s
    return s2 * c, np.float32(1.0) - s2 * s


@njit(cache=True, inline="always", fastmath=True)
def sincos_cycles_scaled(y, w):
    """``w`` sin(2 pi y) and ``w`` cos(2 pi y) for y in [-0.5, 0.5] cycles: :func:`sincos_cycles`
    with the weight folded into the double angle (2 w sin, times cos and sin: three float32
    operations where the product of each takes four).

    Parameters
    ----------
    y : float32
        Cycles, in [-0.5, 0.5].
    w : float32
        Weight.

    Returns
    -------
    (float32, float32)
        w sin, w cos.
    """
    s, c = _half_angle(y)
    s2 = s * (w + w)
    return s2 * c, w - s2 * s


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
