"""Optical turbulence: Cn^2 <-> r0, turbulence classes, layer spacing, Rytov variance, and the
theoretical phase structure function.

Conventions (SAL-NOTES section 0): k = 2 pi / wavelength; plane wave over a path of length Z with
constant Cn^2: r0 = (0.423 k^2 Cn^2 Z)^(-3/5); spherical wave (point source): (0.159 k^2 Cn^2 Z)^(-3/5),
1.80 times larger; layers add as r0^(-5/3) = sum r0_i^(-5/3). Phase structure function
D(r) = 6.88 (r / r0)^(5/3) (Kolmogorov).
"""
from __future__ import annotations

import math

import lazy_loader as _lazy
import numpy as np

from ..errors import ScenarioError

# scipy.special and scipy.integrate load when a Bessel function or a quadrature is first needed (0.4 s
# of every process's start otherwise, Dask workers' and the command line's among them)
_special = _lazy.load("scipy.special", suppress_warning=True)
_integrate = _lazy.load("scipy.integrate", suppress_warning=True)

PLANE = 0.423
SPHERICAL = 0.159
# 2 * (24/5 * Gamma(6/5))^(5/6) * Gamma(11/6) / Gamma(1/6) ... the PSD constant for f in cycles/m:
# Phi(f) = 0.023 r0^(-5/3) f^(-11/3); exactly (Gamma(11/6)^2 / (2 pi^(11/3))) (24/5 Gamma(6/5))^(5/6)
# The constants below are those expressions evaluated with scipy._special.gamma, to the last bit
# (tests/atmosphere/test_turbulence.py evaluates them again): math.gamma differs in the last bit.
PSD_CONST = 0.02289558710855519
SF_CONST = 6.883877182293812  # 2 (24/5 Gamma(6/5))^(5/6)

CLASSES = ((6e-16, "very weak"), (6e-15, "weak"), (6e-14, "medium"), (6e-13, "strong"))


def _positive(name, value):
    v = np.asarray(value, dtype=np.float64)
    if not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise ScenarioError(name, value, "must be finite and > 0")
    return v


def r0_from_cn2(cn2, path_length, wavelength, wave: str = "plane"):
    """Fried parameter (m) of a constant-Cn^2 path.

    Parameters
    ----------
    cn2 : float or array
        Refractive-index structure constant, m^(-2/3).
    path_length : float
        Path length Z, m.
    wavelength : float
        m.
    wave : {"plane", "spherical"}

    Returns
    -------
    float or ndarray
        Fried parameter, m.
    """
    cn2 = _positive("cn2", cn2)
    _positive("path_length", path_length)
    _positive("wavelength", wavelength)
    c = PLANE if wave == "plane" else SPHERICAL
    k = 2 * math.pi / wavelength
    return (c * k ** 2 * cn2 * path_length) ** (-3 / 5)


def cn2_from_r0(r0, path_length, wavelength, wave: str = "plane"):
    """Inverse of :func:`r0_from_cn2`: Cn^2 (m^-2/3) giving Fried parameter ``r0`` (m).

    Parameters
    ----------
    r0 : float or array
        Fried parameter, m.
    path_length : float
        m.
    wavelength : float
        m.
    wave : {"plane", "spherical"}

    Returns
    -------
    float or ndarray
        Cn^2, m^(-2/3).

    Examples
    --------
    >>> round(float(r0_from_cn2(cn2_from_r0(0.05, 1e4, 1.55e-6), 1e4, 1.55e-6)), 6)
    0.05
    """
    r0 = _positive("r0", r0)
    _positive("path_length", path_length)
    c = PLANE if wave == "plane" else SPHERICAL
    k = 2 * math.pi / wavelength
    return r0 ** (-5 / 3) / (c * k ** 2 * path_length)


def r0_path(cn2_profile, z, wavelength, wave: str = "plane", source_at=None):
    """Path-integrated Fried parameter (m) of a Cn^2 profile sampled at positions z (m).

    Plane wave: r0 = (0.423 k^2 int Cn^2 dz)^(-3/5). Spherical wave from a point source at
    ``source_at`` (default the end z[-1]): the weight ((z - z_obs)/L)^(5/3) applies, with
    0.423 in place of 0.159 for the weighted integral.

    Parameters
    ----------
    cn2_profile : float64 (N,)
        Cn^2 at ``z``, m^(-2/3).
    z : float64 (N,)
        Positions along the path, m (increasing).
    wavelength : float
        m.
    wave : {"plane", "spherical"}
    source_at : float, optional
        Position of the point source (spherical wave), m.

    Returns
    -------
    float
        Fried parameter, m.
    """
    cn2 = np.asarray(cn2_profile, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    if np.any(cn2 < 0):
        raise ScenarioError("cn2", float(cn2.min()), "must be >= 0")
    k = 2 * math.pi / wavelength
    if wave == "plane":
        w = np.ones_like(z)
    else:
        src = z[-1] if source_at is None else source_at
        L = abs(src - z[0])
        w = (np.abs(src - z) / L) ** (5 / 3)
    integral = np.trapezoid(cn2 * w, z) if z.size > 1 else float(cn2[0])
    return (PLANE * k ** 2 * integral) ** (-3 / 5)


def combine_r0(r0s):
    """Fried parameter of independent layers: r0^(-5/3) = sum r0_i^(-5/3).

    Parameters
    ----------
    r0s : sequence of float
        Fried parameters of the layers, m.

    Returns
    -------
    float
        m.

    Examples
    --------
    >>> round(combine_r0([0.1, 0.1]) / 0.1, 4)  # two equal layers: 2^(-3/5)
    0.6598
    """
    r = _positive("r0", r0s)
    return float(np.sum(r ** (-5 / 3)) ** (-3 / 5))


def turbulence_class(cn2: float) -> str:
    """Seed 004 classes: very weak < 6e-16 < weak < 6e-15 < medium < 6e-14 < strong < 6e-13 < very strong.

    Parameters
    ----------
    cn2 : float
        m^(-2/3).

    Returns
    -------
    str
        ``very weak``, ``weak``, ``medium``, ``strong`` or ``very strong``.

    Examples
    --------
    >>> turbulence_class(1e-14)
    'medium'
    """
    c = float(_positive("cn2", cn2))
    for limit, name in CLASSES:
        if c < limit:
            return name
    return "very strong"


def max_layer_spacing(cn2: float, wavelength: float) -> float:
    """Largest screen spacing (m) keeping the Fresnel zone inside r0, seed 004 eq 8:
    Z <= 9.4 lambda_um^(7/11) (1e-16 / Cn^2)^(6/11) km.

    Parameters
    ----------
    cn2 : float
        m^(-2/3).
    wavelength : float
        m.

    Returns
    -------
    float
        m.
    """
    c = float(_positive("cn2", cn2))
    lam_um = float(_positive("wavelength", wavelength)) * 1e6
    return 9.4 * lam_um ** (7 / 11) * (1e-16 / c) ** (6 / 11) * 1e3


def rytov_variance(cn2, path_length, wavelength, wave: str = "plane"):
    """Rytov variance sigma_R^2 = 1.23 Cn^2 k^(7/6) L^(11/6) (plane) or beta_0^2 = 0.5 Cn^2 k^(7/6) L^(11/6)
    (spherical, Andrews and Phillips).

    Phase-only screens describe the field while sigma_R^2 << 1 (weak scintillation); beyond ~0.3
    amplitude effects matter and split-step propagation is needed.

    Parameters
    ----------
    cn2 : float or array
        m^(-2/3).
    path_length : float
        m.
    wavelength : float
        m.
    wave : {"plane", "spherical"}

    Returns
    -------
    float or ndarray
        Dimensionless.
    """
    cn2 = _positive("cn2", cn2)
    k = 2 * math.pi / wavelength
    coef = 1.23 if wave == "plane" else 0.5  # spherical: beta_0^2 = 0.5 Cn2 k^(7/6) L^(11/6) = 0.41 sigma_R^2
    return coef * cn2 * k ** (7 / 6) * path_length ** (11 / 6)


def psd(f, r0: float, outer_scale: float | None = None, inner_scale: float | None = None):
    """Phase PSD (rad^2 m^2) at spatial frequency f in cycles per metre.

    Kolmogorov: 0.02293 r0^(-5/3) f^(-11/3); von Karman: (f^2 + 1/L0^2)^(-11/6); inner scale:
    times exp(-(f/fm)^2), fm = 5.92 / (2 pi l0).

    Parameters
    ----------
    f : array
        Spatial frequency, cycles/m.
    r0 : float
        Fried parameter, m.
    outer_scale, inner_scale : float, optional
        m.

    Returns
    -------
    ndarray
        rad^2 m^2.
    """
    f = np.asarray(f, dtype=np.float64)
    f2 = f * f
    if outer_scale is not None and np.isfinite(outer_scale):
        f2 = f2 + 1.0 / outer_scale ** 2
    with np.errstate(divide="ignore"):
        out = PSD_CONST * r0 ** (-5 / 3) * f2 ** (-11 / 6)
    if inner_scale is not None and inner_scale > 0:
        fm = 5.92 / (2 * math.pi * inner_scale)
        out = out * np.exp(-(f / fm) ** 2)
    return out


#: (Gamma(11/6) / (2^(5/6) pi^(8/3))) (24/5 Gamma(6/5))^(5/6), the von Karman spectrum's constant
VK_CONST = 0.08583068106228546
GAMMA_5_6 = 1.1287870299081262  # Gamma(5/6)


def phase_variance(r0: float, outer_scale: float) -> float:
    """Phase variance (rad^2) of a von Karman screen: (L0/r0)^(5/3) C 2^(-1/6) Gamma(5/6).

    Parameters
    ----------
    r0 : float
        Fried parameter, m.
    outer_scale : float
        L0, m.

    Returns
    -------
    float
        rad^2.
    """
    return (outer_scale / r0) ** (5 / 3) * VK_CONST * 2 ** (-1 / 6) * GAMMA_5_6


def _vk_deficit(x):
    """2^(nu-1) Gamma(nu) - x^nu K_nu(x), nu = 5/6, without cancellation for small x.

    Uses x^nu K_nu = pi 2^nu / (2 sin nu pi) [sum (x/2)^2k / (k! G(k+1-nu)) - sum (x/2)^(2k+2nu) /
    (k! G(k+1+nu))] for x < 2, the Bessel function beyond.
    """
    nu = 5 / 6
    x = np.asarray(x, dtype=np.float64)
    out = np.empty_like(x)
    small = x < 2.0
    xs = x[small] / 2
    pre = math.pi * 2 ** nu / (2 * math.sin(nu * math.pi))
    acc = np.zeros_like(xs)
    for k in range(0, 30):
        if k >= 1:
            acc += xs ** (2 * k) / (math.factorial(k) * _special.gamma(k + 1 - nu))
        acc -= xs ** (2 * k + 2 * nu) / (math.factorial(k) * _special.gamma(k + 1 + nu))
    out[small] = -pre * acc
    xb = x[~small]
    out[~small] = 2 ** (nu - 1) * _special.gamma(nu) - xb ** nu * _special.kv(nu, xb)
    return out


def structure_function(r, r0: float, outer_scale: float | None = None, inner_scale: float | None = None):
    """Theoretical phase structure function D(r) (rad^2) at separations r (m).

    Kolmogorov: 6.88 (r/r0)^(5/3). Von Karman (outer scale L0): 2 (B(0) - B(r)) with the closed-form
    covariance B(r) = (L0/r0)^(5/3) C x^(5/6) K_5/6(x), x = 2 pi r / L0. With an inner scale:
    4 pi int Phi(f) (1 - J0(2 pi f r)) f df on a dense logarithmic grid.

    Parameters
    ----------
    r : array
        Separations, m.
    r0 : float
        Fried parameter, m.
    outer_scale, inner_scale : float, optional
        m.

    Returns
    -------
    ndarray
        rad^2.

    Examples
    --------
    >>> structure_function([0.1], 0.1).round(2).tolist()  # 6.88 at r = r0
    [6.88]
    """
    r = np.atleast_1d(np.asarray(r, dtype=np.float64))
    has_L0 = outer_scale is not None and np.isfinite(outer_scale)
    if not inner_scale:
        if not has_L0:
            return SF_CONST * (r / r0) ** (5 / 3)
        x = 2 * math.pi * r / outer_scale
        return 2 * (outer_scale / r0) ** (5 / 3) * VK_CONST * _vk_deficit(x)
    fm = 5.92 / (2 * math.pi * inner_scale)
    out = np.empty_like(r)
    for i, ri in enumerate(r):
        def g(f):
            return 4 * math.pi * psd(f, r0, outer_scale, inner_scale) * (1 - _special.j0(2 * math.pi * f * ri)) * f
        pts = {0.0, fm / 100, fm / 10, fm / 3, fm, 2 * fm, 4 * fm, 8 * fm, 16 * fm}
        if has_L0:
            pts |= {0.1 / outer_scale, 1 / outer_scale, 10 / outer_scale}
        pts |= {k / ri for k in range(1, 200) if k / ri < 16 * fm}
        edges = sorted(p for p in pts if p <= 16 * fm)
        out[i] = sum(_integrate.quad(g, a, b, limit=200)[0] for a, b in zip(edges[:-1], edges[1:]))
    return out
