"""Differential ranges |x - p| - R_ref without the rounding of two long ranges.

At 560 km a range in float64 carries up to 6e-11 m of rounding (half an ulp of 5.6e5), 5e-4 rad
of two-way phase at 1.55 um; |x - p| - R_ref formed from two such numbers is off by that much,
independently for every pixel and pulse, which leaves a floor near -70 dB on a speckled scene.
Here the difference is formed from small quantities only:

    |x - p| - R_ref = (D + x.(x - 2 p)) / (|x - p| + R_ref),   D = |p|^2 - R_ref^2,

with x the pixel relative to the scene centre (small), p the antenna (large) and D computed
exactly (error-free products and one rounding of their sum) once per pulse. The denominator needs no precision.
"""
from __future__ import annotations

import math
import numpy as np
from numba import njit


def _exact_square(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """a^2 as p + e exactly (Dekker's product on Veltkamp's split halves): p the rounded square,
    e its rounding error."""
    c = 134217729.0 * a  # 2^27 + 1
    hi = c - (c - a)
    lo = a - hi
    p = a * a
    return p, ((hi * hi - p) + 2.0 * hi * lo) + lo * lo


def range_offsets(positions: np.ndarray, reference_range: np.ndarray) -> np.ndarray:
    """D = |p|^2 - R_ref^2 per pulse, exact to the last bit of its float64 result, m^2.

    Each square is split exactly into its rounded value and its rounding error (Dekker), and the
    eight terms summed with one rounding (:func:`math.fsum`): the float64 nearest to the exact
    rational value.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre, m.
    reference_range : float64 (P,)
        m.

    Returns
    -------
    float64 (P,)

    Examples
    --------
    >>> range_offsets(np.array([[3.0, 4.0, 0.0]]), np.array([5.0])).tolist()
    [0.0]
    """
    pos = np.asarray(positions, np.float64)
    ref = np.asarray(reference_range, np.float64)
    terms = [t for v in (pos[:, 0], pos[:, 1], pos[:, 2]) for t in _exact_square(v)]
    terms += [-t for t in _exact_square(ref)]
    cols = np.stack(terms, axis=1).tolist()
    return np.array([math.fsum(row) for row in cols], np.float64).reshape(ref.shape[0])


@njit(cache=True, inline="always", error_model="numpy")
def differential_range(x0, x1, x2, p0, p1, p2, ref, D):
    """|x - p| - ref from small quantities (module docstring); x relative to the scene centre, m.

    Parameters
    ----------
    x0, x1, x2 : float
        Pixel or scatterer, m.
    p0, p1, p2 : float
        Antenna, m.
    ref : float
        Reference range, m.
    D : float
        |p|^2 - ref^2 (:func:`range_offsets`), m^2.

    Returns
    -------
    float
        m.
    """
    d0 = x0 - p0
    d1 = x1 - p1
    d2 = x2 - p2
    R = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    return (D + x0 * (x0 - 2.0 * p0) + x1 * (x1 - 2.0 * p1) + x2 * (x2 - 2.0 * p2)) / (R + ref)


__all__ = ["differential_range", "range_offsets"]
