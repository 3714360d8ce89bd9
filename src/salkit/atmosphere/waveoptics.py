"""Wave-optics propagation through turbulence: split-step angular-spectrum propagation through
frozen phase screens (Schmidt, "Numerical Simulation of Optical Wave Propagation", 2010, ch. 8-9).

A field on an N x N grid of spacing dx is carried over each partial distance dz by the
free-space transfer function exp(-j pi lambda dz (fx^2 + fy^2)) (the Fresnel form of the angular
spectrum, valid for the paraxial fields of a ladar; time convention exp(+j (k z - w t)), carrier
exp(j k dz) left out), and multiplied by a phase screen between steps. Each screen carries the turbulence of its slab: r0 = (0.423 k^2 Cn2 dz)^(-3/5). Plane waves
use periodic (FFT) screens on a periodic grid, so no boundary is needed.

:func:`plan_sampling` chooses the grid and the steps and refuses, with the numbers, a case that
cannot be sampled in memory. Spherical waves (point sources, scaled grids) are in
:mod:`salkit.atmosphere.spherical`; the theory the ensembles are judged against, and their
statistics, in :mod:`salkit.atmosphere.scintillation`; ``salkit propagate``'s experiment in
:mod:`salkit.atmosphere.propagation`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft
from numba import njit, prange

from ..constants import FFT_WORKERS
from ..errors import SamplingError
from ..signals.phase import sincos_cycles
from .scintillation import modified_spectrum
from .turbulence import r0_from_cn2, rytov_variance

#: Largest grid side :func:`plan_sampling` accepts (a 4096^2 complex128 field is 256 MiB).
MAX_N = 4096


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
