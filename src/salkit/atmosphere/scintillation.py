"""Scintillation: the theory wave-optics ensembles are judged against (the Rytov variance in
weak fluctuations, sigma_I^2 = sigma_R^2; the Andrews-Phillips expressions for the scintillation
index from weak to strong fluctuations, 2nd ed., ch. 9, with and without an inner scale; Andrews'
modified spectrum) and the ensemble statistics measured on propagated fields (scintillation index,
wave structure function).
"""
from __future__ import annotations

import math

import numpy as np



def scintillation_theory(rytov: float, wave: str = "plane") -> float:
    """Scintillation index of a point receiver from weak to strong fluctuations (Andrews and
    Phillips, zero inner scale): plane wave exp[0.49 s/(1 + 1.11 s^(6/5))^(7/6) + 0.51 s/(1 +
    0.69 s^(6/5))^(5/6)] - 1 with s = sigma_R^2; spherical wave the same with s = beta_0^2 =
    0.5 Cn2 k^(7/6) L^(11/6) and 0.56 for 1.11. Tends to s in weak fluctuations and, past a peak
    near s = 1-5, falls back towards 1 (saturation).

    Parameters
    ----------
    rytov : float
        sigma_R^2 of the wave (:func:`salkit.atmosphere.rytov_variance` with the same ``wave``).
    wave : {"plane", "spherical"}

    Returns
    -------
    float

    Examples
    --------
    >>> round(scintillation_theory(0.01), 4), round(scintillation_theory(10.0), 2)
    (0.01, 1.24)
    """
    s = float(rytov)
    if wave == "plane":
        a = 0.49 * s / (1 + 1.11 * s ** 1.2) ** (7 / 6)
        b = 0.51 * s / (1 + 0.69 * s ** 1.2) ** (5 / 6)
    elif wave == "spherical":
        b0 = s  # beta_0^2, the spherical wave's Rytov variance 0.5 Cn2 k^(7/6) L^(11/6)
        a = 0.49 * b0 / (1 + 0.56 * b0 ** 1.2) ** (7 / 6)
        b = 0.51 * b0 / (1 + 0.69 * b0 ** 1.2) ** (5 / 6)
    else:
        raise ValueError(f"wave must be plane or spherical, not {wave!r}")
    return math.exp(a + b) - 1.0


def inner_scale_q(wavelength: float, distance: float, inner_scale: float) -> float:
    """Andrews and Phillips' inner-scale parameter Q_l = 10.89 L / (k l0^2) (= L kappa_l^2 / k
    with kappa_l = 3.3 / l0): the square of the Fresnel scale over the inner scale, times 10.89.

    Parameters
    ----------
    wavelength, distance, inner_scale : float
        m.

    Returns
    -------
    float

    Examples
    --------
    >>> round(inner_scale_q(1e-6, 2000.0, 0.005), 1)
    138.7
    """
    return 10.89 * distance / (2 * math.pi / wavelength * inner_scale ** 2)


def scintillation_theory_inner_scale(rytov: float, q_l: float) -> float:
    """Scintillation index of a plane wave from weak to strong fluctuations with a finite inner
    scale (Andrews and Phillips, 2nd ed., ch. 9, for their modified atmospheric spectrum; infinite
    outer scale): exp(sigma_lnX^2 + sigma_lnY^2) - 1 with

    * sigma_lnX^2 = 0.16 s (eta Q/(eta + Q))^(7/6) [1 + 1.75 (eta/(eta + Q))^(1/2)
      - 0.25 (eta/(eta + Q))^(7/12)], 1/eta = 0.38 + 0.47 (1/3)^(6/7) s Q^(1/6),
    * sigma_lnY^2 = 0.51 b / (1 + 0.69 b^(6/5))^(5/6), b the weak-fluctuation index with inner
      scale 3.86 s [(1 + 1/Q^2)^(11/12) (sin(11/6 a) + 1.507 (1 + Q^2)^(-1/4) sin(4/3 a)
      - 0.273 (1 + Q^2)^(-7/24) sin(5/4 a)) - 3.50 Q^(-5/6)], a = atan Q,

    s = sigma_R^2, Q = Q_l (:func:`inner_scale_q`). The inner scale's spectral bump raises the
    focusing peak above the zero-inner-scale expression (:func:`scintillation_theory`).

    Parameters
    ----------
    rytov : float
        Plane-wave sigma_R^2.
    q_l : float
        10.89 L / (k l0^2).

    Returns
    -------
    float

    Examples
    --------
    >>> round(scintillation_theory_inner_scale(2.0, 138.7), 2) > round(scintillation_theory(2.0), 2)
    True
    """
    s, q = float(rytov), float(q_l)
    a = math.atan(q)
    b = 3.86 * s * ((1 + 1 / q ** 2) ** (11 / 12) * (math.sin(11 / 6 * a) + 1.507 / (1 + q * q) ** 0.25
                                                    * math.sin(4 / 3 * a) - 0.273 / (1 + q * q) ** (7 / 24)
                                                    * math.sin(5 / 4 * a)) - 3.50 * q ** (-5 / 6))
    eta = 1.0 / (0.38 + 0.47 * (1 / 3) ** (6 / 7) * s * q ** (1 / 6))
    f = eta / (eta + q)
    x = 0.49 / 3 * s * (eta * q / (eta + q)) ** (7 / 6) * (1 + 1.75 * f ** 0.5 - 0.25 * f ** (7 / 12))
    y = 0.51 * b / (1 + 0.69 * b ** 1.2) ** (5 / 6)
    return math.exp(x + y) - 1.0


def modified_spectrum(kappa: np.ndarray, inner_scale: float | None) -> np.ndarray:
    """Andrews' modified atmospheric spectrum over Kolmogorov's: [1 + 1.802 (kappa/kappa_l) -
    0.254 (kappa/kappa_l)^(7/6)] exp(-kappa^2/kappa_l^2), kappa_l = 3.3 / l0 (1 without an inner
    scale). Its bump near kappa_l is the inner-scale feature measured in air.

    Parameters
    ----------
    kappa : ndarray
        Angular spatial frequency, rad/m.
    inner_scale : float or None
        l0, m.

    Returns
    -------
    ndarray
    """
    if not inner_scale:
        return np.ones_like(kappa, dtype=np.float64)
    t = np.asarray(kappa, np.float64) / (3.3 / inner_scale)
    return (1 + 1.802 * t - 0.254 * t ** (7 / 6)) * np.exp(-t * t)


def scintillation_index(fields: np.ndarray) -> float:
    """<I^2> / <I>^2 - 1 over every sample of an ensemble of statistically homogeneous fields.

    Parameters
    ----------
    fields : complex ndarray (K, N, N), or any shape (pooled)

    Returns
    -------
    float
    """
    inten = np.abs(fields.astype(np.complex128)) ** 2
    return float(np.mean(inten ** 2) / np.mean(inten) ** 2 - 1.0)


def wave_structure_function(fields: np.ndarray, dx: float, max_lag: int | None = None,
                            batches: int = 1):
    """Wave structure function D(r) = -2 ln |MCF(r)| / MCF(0) of an ensemble of homogeneous fields,
    the mutual coherence function averaged over both axes.

    Parameters
    ----------
    fields : complex ndarray (K, N, N)
    dx : float
        m.
    max_lag : int, optional
        Default N // 8.
    batches : int
        With more than 1, the realisations are also split into this many batches and the standard
        error of D across them is returned (the ensemble estimate's error bar).

    Returns
    -------
    (r, D) or (r, D, standard_error) : float64 arrays
        m, rad^2, rad^2.
    """
    u = fields.astype(np.complex128)
    n = u.shape[-1]
    lags = np.arange(1, (max_lag or n // 8) + 1)

    def estimate(v):
        m0 = np.nanmean(np.abs(v) ** 2)
        d = []
        for s in lags:
            g = 0.5 * (np.nanmean(v[..., s:] * np.conj(v[..., :-s])) + np.nanmean(v[..., s:, :] * np.conj(v[..., :-s, :])))
            d.append(-2.0 * math.log(abs(g) / m0))
        return np.asarray(d)

    d = estimate(u)
    if batches <= 1:
        return lags * dx, d
    parts = np.array([estimate(b) for b in np.array_split(u, batches) if len(b)])
    return lags * dx, d, parts.std(axis=0, ddof=1) / math.sqrt(len(parts))
