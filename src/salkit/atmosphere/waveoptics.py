"""Wave-optics propagation through turbulence: split-step angular-spectrum propagation through
frozen phase screens (Schmidt, "Numerical Simulation of Optical Wave Propagation", 2010, ch. 8-9).

A field on an N x N grid of spacing dx is carried over each partial distance dz by the
free-space transfer function exp(-j pi lambda dz (fx^2 + fy^2)) (the Fresnel form of the angular
spectrum, valid for the paraxial fields of a ladar; time convention exp(+j (k z - w t)), carrier
exp(j k dz) left out), and multiplied by a phase screen between steps. Each screen carries the turbulence of its slab: r0 = (0.423 k^2 Cn2 dz)^(-3/5). Plane waves
use periodic (FFT) screens on a periodic grid, so no boundary is needed.

Theory beside it: the Rytov variance (weak scintillation, sigma_I^2 = sigma_R^2), the
Andrews-Phillips expressions for the scintillation index in strong fluctuations (2nd ed., ch. 9),
and the Fried parameters of plane and spherical waves. :func:`plan_sampling` chooses the grid and
the steps and refuses, with the numbers, a case that cannot be sampled in memory.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft
import xarray as xr
from numba import njit, prange

from ..constants import FFT_WORKERS
from ..errors import SamplingError
from ..signals.phase import sincos_cycles
from .screens import phase_screens
from .turbulence import r0_from_cn2, rytov_variance

#: Largest grid side :func:`plan_sampling` accepts (a 4096^2 complex128 field is 256 MiB).
MAX_N = 4096


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


@dataclass(frozen=True)
class Sampling:
    """The grid and steps of a propagation.

    Attributes
    ----------
    n : int
        Grid side, samples.
    dx : float
        Spacing, m.
    layers : int
        Phase screens (one per slab, at each slab's centre).
    dz : float
        Slab thickness, m.
    layer_r0 : float
        Fried parameter of one slab's screen, m.
    """

    n: int
    dx: float
    layers: int
    dz: float
    layer_r0: float


def plan_sampling(wavelength: float, distance: float, cn2: float, *, layers: int | None = None,
                  n: int | None = None, dx: float | None = None, width: float | None = None,
                  inner_scale: float | None = None) -> Sampling:
    """Grid and steps for a plane wave through uniform turbulence.

    The spacing resolves the field: dx <= min(r0_plane, Fresnel scale sqrt(lambda L)) / 4 unless
    given. The grid spans ``width`` (default 32 Fresnel scales or 16 r0, whichever is larger), and
    the slabs are thin enough that each screen is weak: layer Rytov variance <= 0.1 and screen
    r0 >= 4 dx (Schmidt ch. 9), at least 10 slabs.

    Parameters
    ----------
    wavelength, distance : float
        m.
    cn2 : float
        m^(-2/3).
    layers, n : int, optional
        Force the number of slabs or the grid side.
    dx, width : float, optional
        Force the spacing or the grid's width, m.
    inner_scale : float, optional
        l0, m: the spacing also resolves it (dx <= l0 / 3.3, where the modified spectrum has
        fallen by 1e-4).

    Returns
    -------
    Sampling

    Raises
    ------
    SamplingError
        When the grid needs more than :data:`MAX_N` samples a side.
    """
    fresnel = math.sqrt(wavelength * distance)
    r0 = float(r0_from_cn2(cn2, distance, wavelength)) if cn2 > 0 else math.inf
    if dx is None:
        dx = min(r0, fresnel) / 4.0
        if inner_scale:
            dx = min(dx, inner_scale / 3.3)
    if width is None:
        width = max(32 * fresnel, 16 * min(r0, 1e9) if math.isfinite(r0) else 0.0)
    if n is None:
        n = int(sfft.next_fast_len(int(math.ceil(width / dx))))
        n += n % 2
    if n > MAX_N:
        raise SamplingError("propagate grid", n, f"needs {n} x {n} samples (spacing {dx:.3g} m for r0 {r0:.3g} m "
                            f"and Fresnel scale {fresnel:.3g} m, width {width:.3g} m), more than {MAX_N}: "
                            "shorten the path or lower Cn2")
    if layers is None:
        layers = 10
        if cn2 > 0:
            while (rytov_variance(cn2, distance / layers, wavelength) > 0.1
                   or r0_from_cn2(cn2, distance / layers, wavelength) < 4 * dx) and layers < 1000:
                layers += 1
    dz = distance / layers
    layer_r0 = r0_from_cn2(cn2, dz, wavelength) if cn2 > 0 else math.inf
    return Sampling(n=n, dx=float(dx), layers=int(layers), dz=float(dz), layer_r0=float(layer_r0))


def transfer_function(n: int, wavelength: float, dx: float, dz: float) -> np.ndarray:
    """The Fresnel transfer function exp(-j pi lambda dz (fx^2 + fy^2)) on the FFT grid, complex128.

    Parameters
    ----------
    n : int
    wavelength, dx, dz : float
        m.

    Returns
    -------
    complex128 (n, n)
    """
    f = sfft.fftfreq(n, dx)
    a = math.pi * wavelength * dz
    hx = np.exp(-1j * a * f ** 2)
    return hx[:, None] * hx[None, :]  # separable: exp(-j a fx^2) exp(-j a fy^2)


def free_space(field: np.ndarray, wavelength: float, dx: float, dz: float, h: np.ndarray | None = None) -> np.ndarray:
    """Propagate a field (..., N, N) over ``dz`` in vacuum: angular spectrum with the Fresnel
    transfer function exp(-j pi lambda dz (fx^2 + fy^2)) (the carrier exp(j k dz) left out).

    Parameters
    ----------
    field : complex ndarray (..., N, N)
    wavelength, dx, dz : float
        m.
    h : complex ndarray (N, N), optional
        The transfer function, if already made (:func:`transfer_function`).

    Returns
    -------
    complex ndarray, like ``field``
    """
    if h is None:
        h = transfer_function(field.shape[-1], wavelength, dx, dz)
    spec = sfft.fft2(field, workers=FFT_WORKERS)
    spec *= h
    return sfft.ifft2(spec, workers=FFT_WORKERS, overwrite_x=True)


@njit(parallel=True, cache=True, fastmath=True)
def _apply_screen(u, phi):
    """In place: u *= exp(j phi), phi (rad, float64) reduced to cycles in float64 before the
    float32 sin/cos polynomial (screens reach hundreds of radians)."""
    n0, n1 = u.shape
    inv2pi = 1.0 / (2.0 * math.pi)
    for i in prange(n0):
        for j in range(n1):
            cyc = phi[i, j] * inv2pi
            y = np.float32(cyc - np.floor(cyc + 0.5))
            sn, cs = sincos_cycles(y)
            v = u[i, j]
            u[i, j] = complex(v.real * cs - v.imag * sn, v.real * sn + v.imag * cs)


def propagate(field: np.ndarray, wavelength: float, dx: float, distance: float,
              screens: np.ndarray | None = None, dtype=np.complex64) -> np.ndarray:
    """Split-step propagation over ``distance`` through ``screens`` (L, N, N) rad, one at the
    centre of each of L equal slabs (half step, screen, step, ..., screen, half step). The two
    transfer functions are made once (separably), the FFTs run in place on scipy.fft's workers,
    and each screen is applied by a fused kernel.

    Parameters
    ----------
    field : complex ndarray (N, N)
    wavelength, dx, distance : float
        m.
    screens : float ndarray (L, N, N), optional
        None: vacuum.
    dtype : numpy dtype
        complex64 (default: relative error ~1e-6, half the FFT time) or complex128.

    Returns
    -------
    complex ndarray (N, N) of ``dtype``
    """
    u = np.array(field, dtype=dtype)
    n = u.shape[-1]
    if screens is None or len(screens) == 0:
        return free_space(u, wavelength, dx, distance).astype(dtype, copy=False)
    dz = distance / len(screens)
    h_half = transfer_function(n, wavelength, dx, dz / 2).astype(dtype)
    h_full = h_half * h_half
    u = free_space(u, wavelength, dx, dz / 2, h_half)
    for i, phi in enumerate(screens):
        _apply_screen(u, np.asarray(phi, np.float64))
        u = free_space(u, wavelength, dx, dz if i < len(screens) - 1 else dz / 2,
                       h_full if i < len(screens) - 1 else h_half)
    return u


def periodic_screens(n: int, dx: float, r0: float, count: int, rng: np.random.Generator,
                     inner_scale: float | None = None) -> np.ndarray:
    """Kolmogorov phase screens that are exactly periodic on the N x N grid (rad): complex
    Gaussian noise shaped by sqrt(0.023 r0^(-5/3) f^(-11/3)) df on the FFT grid, no DC. A plane wave
    on a periodic grid needs them: a screen with an edge (as the subharmonic screens of
    :func:`salkit.atmosphere.phase_screens` have, to hold the low frequencies) diffracts at the
    wrap and raises the scintillation. The grid's lowest frequency 1/(N dx) bounds the largest
    eddy, which scintillation (set by the Fresnel scale) does not feel when N dx >> sqrt(lambda L).

    Parameters
    ----------
    n : int
    dx, r0 : float
        m.
    count : int
    rng : numpy.random.Generator
    inner_scale : float, optional
        l0, m: the spectrum times :func:`modified_spectrum` (resolve it: dx <= l0 / 3).

    Returns
    -------
    float64 (count, n, n)
    """
    f = sfft.fftfreq(n, dx)
    f2 = f[:, None] ** 2 + f[None, :] ** 2
    f2[0, 0] = 1.0  # no DC: its amplitude is set to 0 below
    amp = np.sqrt(0.023 * r0 ** (-5 / 3) * f2 ** (-11 / 6)
                  * modified_spectrum(2 * np.pi * np.sqrt(f2), inner_scale)) / (n * dx)
    amp[0, 0] = 0.0
    noise = rng.standard_normal((count, n, n)) + 1j * rng.standard_normal((count, n, n))
    # real part of an ifft of Hermitian-free noise: each frequency's variance splits between the
    # real and imaginary outputs, so the real part alone holds the full PSD
    return sfft.ifft2(noise * amp, workers=FFT_WORKERS, norm="forward").real


def plane_wave_ensemble(wavelength: float, distance: float, cn2: float, count: int, seed: int = 0,
                        sampling: Sampling | None = None,
                        inner_scale: float | None = None) -> tuple[np.ndarray, Sampling]:
    """``count`` independent realisations of a unit plane wave after ``distance`` of uniform
    turbulence (periodic FFT screens on a periodic grid).

    Parameters
    ----------
    wavelength, distance : float
        m.
    cn2 : float
        m^(-2/3).
    count : int
    seed : int
    sampling : Sampling, optional
        Default :func:`plan_sampling`.
    inner_scale : float, optional
        l0, m (:func:`modified_spectrum`).

    Returns
    -------
    (complex64 (count, N, N), Sampling)
    """
    s = sampling or plan_sampling(wavelength, distance, cn2, inner_scale=inner_scale)
    rng = np.random.default_rng(seed)
    out = np.empty((count, s.n, s.n), np.complex64)
    for k in range(count):
        scr = periodic_screens(s.n, s.dx, s.layer_r0, s.layers, rng, inner_scale) if cn2 > 0 else None
        out[k] = propagate(np.ones((s.n, s.n), np.complex64), wavelength, s.dx, distance, scr)
    return out, s


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


def propagation_result(wave: str, wavelength: float, cn2: float, distance: float, count: int, seed: int = 0,
                       layers: int | None = None, inner_scale: float | None = None) -> tuple[xr.Dataset, dict]:
    """An ensemble propagated and measured: the received fields as a dataset and the figures
    against theory (what ``salkit propagate`` writes).

    Parameters
    ----------
    wave : {"plane", "spherical"}
        A spherical wave is a point source on a grid whose spacing grows to the receiver, with an
        absorbing boundary; its field is stored divided by the vacuum field over the receiver region.
    wavelength, distance : float
        m.
    cn2 : float
        m^(-2/3).
    count : int
        Realisations.
    seed : int
    layers : int, optional
        Phase screens (default: :func:`plan_sampling`'s).
    inner_scale : float, optional
        l0 of the modified atmospheric spectrum, m (plane waves).

    Returns
    -------
    (xarray.Dataset, dict)
        ``field`` (realisation, y, x) complex64 with coordinates in m, and metrics:
        ``rytov_variance``, ``scintillation_index``, ``scintillation_index_theory`` (Andrews-Phillips,
        with the inner scale where one is given: then also ``inner_scale_q`` and
        ``scintillation_index_theory_zero_inner_scale``), ``r0_plane_m``, ``r0_spherical_m``, the
        sampling.

    Raises
    ------
    SamplingError
        For a case that cannot be sampled (:func:`plan_sampling`, :func:`plan_spherical`).
    """
    if wave == "plane":
        s = plan_sampling(wavelength, distance, cn2, layers=layers, inner_scale=inner_scale)
        fields, s = plane_wave_ensemble(wavelength, distance, cn2, count, seed=seed, sampling=s,
                                        inner_scale=inner_scale)
        x = (np.arange(s.n) - s.n // 2) * s.dx
        grid = {"grid_n": s.n, "grid_dx_m": s.dx, "layers": s.layers, "layer_r0_m": s.layer_r0}
        si = scintillation_index(fields)
    elif wave == "spherical":
        s = plan_spherical(wavelength, distance, cn2, layers=layers)
        fields, s = spherical_wave_ensemble(wavelength, distance, cn2, count, seed=seed, sampling=s)
        half = fields.shape[-1] // 2
        x = np.arange(-half, half + 1) * s.deltan
        grid = {"grid_n": s.n, "grid_dx_m": s.deltan, "source_dx_m": s.delta1, "layers": len(s.z) - 2,
                "layer_r0_m": s.layer_r0, "receiver_m": s.receiver}
        si = scintillation_index(fields[np.isfinite(fields.real)])
    else:
        raise SamplingError("--wave", wave, "must be plane or spherical")
    sig = float(rytov_variance(cn2, distance, wavelength, wave)) if cn2 > 0 else 0.0
    theory = {"scintillation_index_theory": scintillation_theory(sig, wave)}
    if inner_scale and wave == "plane":
        q = inner_scale_q(wavelength, distance, inner_scale)
        theory = {"scintillation_index_theory": scintillation_theory_inner_scale(sig, q), "inner_scale_m": inner_scale,
                  "inner_scale_q": q, "scintillation_index_theory_zero_inner_scale": scintillation_theory(sig, wave)}
    metrics = {"rytov_variance": sig, "scintillation_index": si, **theory,
               "r0_plane_m": float(r0_from_cn2(cn2, distance, wavelength)) if cn2 > 0 else math.inf,
               "r0_spherical_m": float(r0_from_cn2(cn2, distance, wavelength, "spherical")) if cn2 > 0 else math.inf,
               **grid, "realisations": count}
    ds = xr.Dataset({"field": (("realisation", "y", "x"), fields)},
                    coords={"realisation": np.arange(count), "y": x, "x": x},
                    attrs={"salkit_kind": "propagated_field", "wave": wave, "wavelength": wavelength, "cn2": cn2,
                           "distance": distance, "seed": seed, "layers": grid["layers"], "grid_dx": grid["grid_dx_m"],
                           "description": ("complex field at the receiver plane, unit plane wave transmitted, "
                                           "split-step angular spectrum through periodic Kolmogorov screens"
                                           if wave == "plane" else "point source's field over the receiver region "
                                           "divided by the vacuum field (nan outside the region's disc)")})
    ds["x"].attrs["units"] = ds["y"].attrs["units"] = "m"
    return ds, metrics


def _ft2(g: np.ndarray, delta: float) -> np.ndarray:
    return sfft.fftshift(sfft.fft2(sfft.ifftshift(g, axes=(-2, -1)), workers=FFT_WORKERS), axes=(-2, -1)) * delta ** 2


def _ift2(G: np.ndarray, delta_f: float) -> np.ndarray:
    n = G.shape[-1]
    return sfft.fftshift(sfft.ifft2(sfft.ifftshift(G, axes=(-2, -1)), workers=FFT_WORKERS),
                         axes=(-2, -1)) * (n * delta_f) ** 2


def propagate_scaled(field: np.ndarray, wavelength: float, delta1: float, deltan: float, z: np.ndarray,
                     screens: np.ndarray | None = None, absorber: bool = True) -> np.ndarray:
    """Angular-spectrum propagation over partial planes ``z`` (z[0] = 0 the source, z[-1] the
    receiver) with the grid spacing growing linearly from ``delta1`` to ``deltan`` (Schmidt 2010,
    listing 9.1), a phase screen at every plane after the first, and a super-Gaussian absorbing
    boundary exp(-(r/0.47 N)^16) at each (diverging waves leave the grid instead of wrapping).

    Parameters
    ----------
    field : complex ndarray (N, N)
        At z[0], spacing ``delta1``, centred (index N/2 at the axis).
    wavelength, delta1, deltan : float
        m.
    z : float64 (n,)
        Plane positions, m, increasing.
    screens : float ndarray (n - 1, N, N), optional
        Phase (rad) applied at planes 1 .. n-1, each on its own spacing.
    absorber : bool

    Returns
    -------
    complex128 (N, N)
        At z[-1], spacing ``deltan``.
    """
    u = np.array(field, dtype=np.complex128)
    n = u.shape[-1]
    k = 2 * math.pi / wavelength
    idx = np.arange(n) - n // 2
    nsq = idx[:, None] ** 2 + idx[None, :] ** 2
    sg = np.exp(-(nsq / (0.47 * n) ** 2) ** 8) if absorber else 1.0
    z = np.asarray(z, np.float64)
    alpha = z / z[-1]
    delta = (1 - alpha) * delta1 + alpha * deltan
    m = delta[1:] / delta[:-1]
    dz = np.diff(z)
    u = u * np.exp(1j * k / 2 * (1 - m[0]) / dz[0] * (nsq * delta[0] ** 2))
    for i in range(len(dz)):
        df = 1 / (n * delta[i])
        q2 = np.exp(-1j * math.pi ** 2 * 2 * dz[i] / m[i] / k * (nsq * df ** 2))
        u = _ift2(q2 * _ft2(u / m[i], delta[i]), df)
        if screens is not None:
            u = u * np.exp(1j * screens[i])
        u = u * sg
    return u * np.exp(1j * k / 2 * (m[-1] - 1) / (m[-1] * dz[-1]) * (nsq * delta[-1] ** 2))


def point_source(n: int, delta1: float, wavelength: float, distance: float, roi: float) -> np.ndarray:
    """A point source for :func:`propagate_scaled`: a sinc x Gaussian of width D1 = lambda L / roi
    with the converging phase removed (Schmidt 2010, sec. 9.4), whose field at ``distance`` is a
    spherical wave of nearly uniform amplitude over ``roi``.

    Parameters
    ----------
    n : int
    delta1, wavelength, distance, roi : float
        m.

    Returns
    -------
    complex128 (n, n)
    """
    k = 2 * math.pi / wavelength
    d1 = wavelength * distance / roi
    x = (np.arange(n) - n // 2) * delta1
    r2 = x[:, None] ** 2 + x[None, :] ** 2
    return (np.exp(-1j * k / (2 * distance) * r2) / d1 ** 2 * np.sinc(x / d1)[:, None] * np.sinc(x / d1)[None, :]
            * np.exp(-r2 / (4 * d1) ** 2))


@dataclass(frozen=True)
class ScaledSampling:
    """Grid and planes of a point-source propagation (:func:`plan_spherical`).

    Attributes
    ----------
    n : int
        Grid side.
    delta1, deltan : float
        Spacing at the source and at the receiver, m.
    z : tuple of float
        Plane positions, m: the source, the slab centres (one screen each), the receiver.
    layer_r0 : float
        Fried parameter of one slab's screen, m.
    receiver : float
        Diameter of the receiver region where the wave is nearly uniform and measured, m.
    """

    n: int
    delta1: float
    deltan: float
    z: tuple
    layer_r0: float
    receiver: float


def plan_spherical(wavelength: float, distance: float, cn2: float, receiver: float | None = None,
                   layers: int | None = None, receiver_dx: float | None = None) -> ScaledSampling:
    """Sampling of a point source through uniform turbulence on a grid whose spacing grows from the
    source to the receiver (Schmidt 2010, sec. 9.4): the source's sinc width D1 = lambda L / (4 D2);
    D1' and D2' widened by 2 lambda L / r0 for the turbulent spread; delta1 = D1 / 4; deltan within
    the bound -D2'/D1' delta1 + lambda L / D1' and fine enough for r0 and the Fresnel scale;
    N >= D1'/(2 delta1) + D2'/(2 deltan) + lambda L / (2 delta1 deltan); slabs weak (Rytov <= 0.1,
    at least 10) and short enough for the grid (dz <= min(delta)^2 N / lambda).

    Parameters
    ----------
    wavelength, distance : float
        m.
    cn2 : float
        m^(-2/3).
    receiver : float, optional
        Receiver region's diameter, m (default 8 Fresnel scales sqrt(lambda L)).
    layers : int, optional
    receiver_dx : float, optional
        Largest spacing wanted at the receiver, m (to sample an aperture finely).

    Returns
    -------
    ScaledSampling

    Raises
    ------
    SamplingError
        When N exceeds :data:`MAX_N`.
    """
    lam, L = wavelength, distance
    fresnel = math.sqrt(lam * L)
    d2 = receiver or 8 * fresnel
    r0 = float(r0_from_cn2(cn2, L, lam, "spherical")) if cn2 > 0 else math.inf
    d1 = lam * L / (4 * d2)
    spread = 2 * lam * L / r0 if math.isfinite(r0) else 0.0
    d1p, d2p = d1 + spread, d2 + spread
    delta1 = min(d1 / 4, lam * L / (2 * d2p))  # keeps the receiver bound below positive
    deltan = min(fresnel / 8, r0 / 4, -d2p / d1p * delta1 + lam * L / d1p, receiver_dx or math.inf)
    if deltan <= 0:
        raise SamplingError("propagate grid", deltan, "no receiver spacing satisfies the point-source bound")
    need = d1p / (2 * delta1) + d2p / (2 * deltan) + lam * L / (2 * delta1 * deltan)
    n = int(sfft.next_fast_len(int(math.ceil(need))))
    n += n % 2
    if n > MAX_N:
        raise SamplingError("propagate grid", n, f"a point source over {L:.4g} m needs {n} x {n} samples (source "
                            f"{delta1:.3g} m, receiver {deltan:.3g} m spacing, r0 {r0:.3g} m), more than {MAX_N}: "
                            "shorten the path or lower Cn2")
    if layers is None:
        layers = 10
        while cn2 > 0 and rytov_variance(cn2, L / layers, lam, "spherical") > 0.1 and layers < 1000:
            layers += 1
        while L / layers > min(delta1, deltan) ** 2 * n / lam and layers < 1000:
            layers += 1
    z = (0.0, *((np.arange(layers) + 0.5) * L / layers), L)
    layer_r0 = r0_from_cn2(cn2, L / layers, lam) if cn2 > 0 else math.inf
    return ScaledSampling(n=n, delta1=float(delta1), deltan=float(deltan), z=tuple(float(v) for v in z),
                          layer_r0=float(layer_r0), receiver=float(d2))


def spherical_wave_ensemble(wavelength: float, distance: float, cn2: float, count: int, seed: int = 0,
                            sampling: ScaledSampling | None = None) -> tuple[np.ndarray, ScaledSampling]:
    """``count`` realisations of a point source's wave at ``distance``, over the receiver region,
    divided by the vacuum field (so a realisation is 1 without turbulence). Screens with
    subharmonics (:func:`salkit.atmosphere.phase_screens`), one per slab on its plane's spacing.

    Parameters
    ----------
    wavelength, distance : float
        m.
    cn2 : float
        m^(-2/3).
    count : int
    seed : int
    sampling : ScaledSampling, optional

    Returns
    -------
    (complex64 (count, M, M), ScaledSampling)
        M samples of spacing ``deltan`` across the receiver region (outside its disc: nan).
    """
    s = sampling or plan_spherical(wavelength, distance, cn2)
    z = np.asarray(s.z)
    delta = (1 - z / z[-1]) * s.delta1 + z / z[-1] * s.deltan
    src = point_source(s.n, s.delta1, wavelength, distance, 4 * s.receiver)
    vac = propagate_scaled(src, wavelength, s.delta1, s.deltan, z)
    half = int(math.ceil(s.receiver / 2 / s.deltan))
    c = s.n // 2
    sl = slice(c - half, c + half + 1)
    x = (np.arange(-half, half + 1)) * s.deltan
    disc = x[:, None] ** 2 + x[None, :] ** 2 <= (s.receiver / 2) ** 2
    rng = np.random.default_rng(seed)
    out = np.full((count, 2 * half + 1, 2 * half + 1), np.nan + 0j, np.complex64)
    for k in range(count):
        scr = np.zeros((len(z) - 1, s.n, s.n))
        if cn2 > 0:
            for i in range(1, len(z) - 1):
                scr[i - 1] = phase_screens(s.n, delta[i], s.layer_r0, count=1, rng=rng)[0]
        u = propagate_scaled(src, wavelength, s.delta1, s.deltan, z, scr)[sl, sl] / vac[sl, sl]
        out[k][disc] = u[disc]
    return out, s

