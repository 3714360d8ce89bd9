"""Interferograms, wrapped phase, unwrapping (scikit-image or least squares) and fringe models."""
from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

from ..signals.phase import wrap  # noqa: F401  (part of this package's API)
import lazy_loader as _lazy
_skimage_restoration = _lazy.load("skimage.restoration", suppress_warning=True)


def interferogram(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Complex interferogram ``first * conj(second)`` of two co-registered complex images.

    Parameters
    ----------
    first, second : complex ndarray
        Same shape.

    Returns
    -------
    complex128 ndarray
    """
    a, b = np.asarray(first), np.asarray(second)
    if a.shape != b.shape:
        raise ValueError(f"images differ in shape: {a.shape} and {b.shape}")
    return a * np.conj(b)


def _ls_unwrap(psi: np.ndarray) -> np.ndarray:
    """Unweighted least-squares unwrapping (Ghiglia and Romero 1994): the wrapped phase differences
    define a Poisson equation, solved with Neumann boundaries by the discrete cosine transform."""
    M, N = psi.shape
    dx = wrap(np.diff(psi, axis=1))
    dy = wrap(np.diff(psi, axis=0))
    rho = np.zeros_like(psi)
    rho[:, :-1] += dx
    rho[:, 1:] -= dx
    rho[:-1, :] += dy
    rho[1:, :] -= dy
    R = sfft.dctn(rho, type=2, norm="ortho")
    i = np.arange(M)[:, None]
    j = np.arange(N)[None, :]
    den = 2 * np.cos(np.pi * i / M) + 2 * np.cos(np.pi * j / N) - 4
    den[0, 0] = 1.0
    P = R / den
    P[0, 0] = 0.0
    return sfft.idctn(P, type=2, norm="ortho")


def unwrap_phase(phase: np.ndarray, method: str = "skimage", seed: int = 0) -> np.ndarray:
    """Unwrap a 2-D wrapped phase (rad).

    Parameters
    ----------
    phase : ndarray (M, N)
        Wrapped phase, rad (a masked array is accepted by the scikit-image method).
    method : {"skimage", "least_squares"}
        scikit-image's reliability-sorting unwrapper (Herraez et al. 2002), or the unweighted
        least-squares solution by DCT (Ghiglia and Romero 1994).
    seed : int
        Seed of scikit-image's random tie-breaking, so runs repeat.

    Returns
    -------
    ndarray (M, N)
        Unwrapped phase, rad. Least squares is defined up to a constant: it is offset to agree with
        the wrapped input at the centre pixel modulo 2 pi.

    Examples
    --------
    >>> y, x = np.mgrid[0:64, 0:64]
    >>> true = 0.002 * (x - 20.0) ** 2 + 0.3 * y
    >>> got = unwrap_phase(wrap(true), "least_squares")
    >>> bool(np.allclose(got - got[0, 0], true - true[0, 0], atol=1e-6))
    True
    """
    p = np.asarray(phase, dtype=np.float64)
    if p.ndim != 2:
        raise ValueError(f"phase must be 2-D, got shape {p.shape}")
    if method == "skimage":
        return np.asarray(_skimage_restoration.unwrap_phase(phase, rng=seed), dtype=np.float64)
    if method == "least_squares":
        u = _ls_unwrap(wrap(p))
        c = tuple(s // 2 for s in p.shape)
        return u + wrap(p[c] - u[c])
    raise ValueError(f"unwrap method {method!r}: must be 'skimage' or 'least_squares'")


def carrier_phase(x: np.ndarray, magnification: float, bias_common: float, period: float,
                  factor: float = 2.0) -> np.ndarray:
    """Flat-fringe phase of a DL-SAL interferogram at cross-track image positions x (m), rad.

    The forward image carries exp(+j 2 pi xi S_a / v_x), the backward exp(-j ...), so the
    interferogram forward x conj(backward) has phase 4 pi xi S_a / v_x = 4 pi (x + M S_b) / Delta-X
    (``factor`` = 2); the sum image's fringe cos(2 pi xi S_a / v_x) has ``factor`` = 1.

    Parameters
    ----------
    x : float array
        Cross-track image positions, m.
    magnification : float
    bias_common : float
        S_b, m.
    period : float
        Fringe period Delta-X, m.
    factor : float
        2 for the interferogram, 1 for the sum image.

    Returns
    -------
    float64 ndarray
        rad.
    """
    return factor * 2 * np.pi * (np.asarray(x, np.float64) + magnification * bias_common) / period


def fringe_period(ifg: np.ndarray, x: np.ndarray, factor: float = 2.0, threshold: float = 0.5) -> dict:
    """Measure the cross-track fringe period (m) of an interferogram by a weighted phase-slope fit.

    Along each row the phase differences between neighbouring pixels with enough signal
    (|ifg| above ``threshold`` x its 90th percentile, which keeps the pixel-edge ringing of bright
    regions out) are averaged with weights |ifg|; slope s (rad/m) gives the period
    factor x 2 pi / s of the underlying cos fringe. On speckled scenes the speckle part of the
    interferogram carries no fringe (the fringe belongs to each scatterer's position, not to the
    pixel), which biases this estimate towards long periods: measure on a uniform scene.

    Parameters
    ----------
    ifg : complex (ny, nx)
        Interferogram.
    x : float64 (nx,)
        Cross-track positions, m.
    factor : float
        As :func:`carrier_phase`.
    threshold : float
        Fraction of the 90th percentile of |ifg| a pixel needs.

    Returns
    -------
    dict
        ``period_m``, ``slope_rad_per_m`` and ``pixels`` used.
    """
    z = np.asarray(ifg)
    dx = float(x[1] - x[0])
    w = np.abs(z)
    nz = w[w > 1e-6 * w.max()] if w.max() > 0 else w.ravel()
    good = w > threshold * np.percentile(nz, 90)
    prod = z[:, 1:] * np.conj(z[:, :-1])
    use = good[:, 1:] & good[:, :-1]
    if use.sum() < 4:
        raise ValueError("too few interferogram pixels above the threshold to measure a fringe period")
    mean = np.sum(prod[use] / np.maximum(np.abs(prod[use]), 1e-300) * np.sqrt(w[:, 1:][use] * w[:, :-1][use]))
    slope = float(np.angle(mean)) / dx
    return {"period_m": factor * 2 * np.pi / abs(slope) if slope != 0 else math.inf,
            "slope_rad_per_m": slope, "pixels": int(use.sum())}


def height_from_fringe_shift(phase_shift: np.ndarray, period: float, look_angle_deg: float,
                             factor: float = 2.0) -> np.ndarray:
    """Height (m) from a fringe phase shift under the fringe-projection model the paper implies.

    Flat fringes of period Delta-X across the beam, projected at ``look_angle_deg`` from nadir onto a
    surface and viewed in ground coordinates, shift by Delta-phi = factor 2 pi h sin(theta) / Delta-X
    at height h, so h = Delta-phi Delta-X / (factor 2 pi sin(theta)).

    Parameters
    ----------
    phase_shift : float array
        rad.
    period : float
        m.
    look_angle_deg : float
        deg.
    factor : float

    Returns
    -------
    ndarray
        m.
    """
    s = math.sin(math.radians(look_angle_deg))
    if s <= 0:
        raise ValueError("a fringe shift carries no height at nadir (look angle 0)")
    return np.asarray(phase_shift) * period / (factor * 2 * np.pi * s)
