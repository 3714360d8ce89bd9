"""Wave-optics two-way gains of a monostatic ladar aperture through a frozen turbulent path.

The transmit beam of a uniform circular aperture is propagated, for each pulse, from the aperture
to the scene plane through the path's frozen layers (:class:`~salkit.atmosphere.path.TurbulentPath`)
by split-step angular-spectrum propagation on a grid whose spacing grows from the aperture to the
scene (Schmidt, "Numerical Simulation of Optical Wave Propagation", 2010, listing 9.1). By
reciprocity the heterodyne receive gain of a point scatterer (the overlap of its returned
spherical wave with the aperture's LO mode, the same uniform disc) equals the transmit field at
the scatterer; monostatic and stop-and-go, the two-way complex gain of scatterer t at pulse p is
therefore g_p(t)^2, where g_p(t) = T_p(t) exp(-j k |t|^2 / 2R) / T_vac(0) is the transmit field
with the geometric (paraxial) phase removed, normalised to the vacuum boresight. In vacuum
g^2 is the far-field pattern (2 J1(u)/u)^2 the phase-screen simulator uses; through turbulence it
carries amplitude (scintillation, beam wander and spread) as well as phase.

Sign: salkit's signals follow exp(-j 2 pi f0 tau) for a delay tau, the conjugate of the optics
convention exp(+j k z) used here, and a screen's phi is a phase advance of the echo (the
phase-screen model multiplies by exp(+j 2 phi)). The beam is therefore propagated through
exp(-j phi) and the gains conjugated, so that one screen gives both models the same phase.

Each pulse is propagated in a frame sheared along the line of sight from its antenna to the scene
centre (the paraxial equation is invariant under this shear up to a linear phase, which the
simulator's exact range already holds): the layer at distance z from the scene is sampled around
the ray's crossing, so the frozen screens move across the beam as the platform flies.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft
from numba import njit, prange

from ..constants import FFT_WORKERS
from ..errors import SamplingError
from ..signals.phase import sincos_cycles
from .waveoptics import MAX_N

#: Turbulent spread allowed for on both planes, in lambda L / r0 (Schmidt 2010, sec. 8.3 uses 2-8).
SPREAD = 2.0


@dataclass(frozen=True)
class BeamSampling:
    """Grid and planes of the aperture-to-scene propagation (:func:`plan_beam`).

    Attributes
    ----------
    n : int
        Grid side.
    delta1, deltan : float
        Spacing at the aperture and at the scene, m.
    zeta : tuple of float
        Plane distances from the aperture, m: the aperture, one plane per layer, the scene.
    layer_index : tuple of int
        The path layer at each plane between the first and the last.
    region : float
        Diameter of the scene region where the gains are valid, m.
    """

    n: int
    delta1: float
    deltan: float
    zeta: tuple
    layer_index: tuple
    region: float

    def spacing(self) -> np.ndarray:
        """Spacing of every plane, m (linear from ``delta1`` to ``deltan``)."""
        z = np.asarray(self.zeta)
        a = z / z[-1]
        return (1 - a) * self.delta1 + a * self.deltan

    def extents(self) -> np.ndarray:
        """Width of the grid on every plane, m."""
        return self.n * self.spacing()


def plan_beam(wavelength: float, distance: float, aperture: float, region: float, r0_spherical: float,
              layer_z: np.ndarray, spread: float = SPREAD, max_n: int = MAX_N) -> BeamSampling:
    """Sampling of a beam from an aperture of diameter D1 to a scene region of diameter D2 through
    turbulence of spherical-wave Fried parameter r0 (Schmidt 2010, sec. 8.3 and 9.3): both widened
    by ``spread`` lambda L / r0 (D1', D2'); the scene spacing bounded by
    deltan <= (lambda L - D2' delta1) / D1', by r0 / 3 and by a tenth of the beam's width
    lambda L / D1'; the aperture spacing at most
    D1 / 20 and chosen, with deltan, to minimise
    N >= D1' / (2 delta1) + D2' / (2 deltan) + lambda L / (2 delta1 deltan).

    Parameters
    ----------
    wavelength, distance : float
        m.
    aperture : float
        Aperture diameter D1, m.
    region : float
        Diameter D2 of the scene region to be sampled, m.
    r0_spherical : float
        Spherical-wave Fried parameter of the path, m (inf: vacuum).
    layer_z : float64 (L,)
        Layer distances from the scene, m (one plane each).
    spread : float
        Turbulent spread allowed for, in lambda L / r0.
    max_n : int
        Largest grid side accepted.

    Returns
    -------
    BeamSampling

    Raises
    ------
    SamplingError
        When the grid needs more than ``max_n`` samples a side, with the numbers.
    """
    lam, L = wavelength, distance
    s = spread * lam * L / r0_spherical if math.isfinite(r0_spherical) else 0.0
    d1p, d2p = aperture + s, region + s
    best = None
    for delta1 in aperture / np.arange(20, 49):
        dn = min((lam * L - d2p * delta1) / d1p, r0_spherical / 3, math.sqrt(lam * L) / 8, region / 16)
        if dn <= 0:
            continue
        need = d1p / (2 * delta1) + d2p / (2 * dn) + lam * L / (2 * delta1 * dn)
        if best is None or need < best[0]:
            best = (need, float(delta1), float(dn))
    if best is None:
        raise SamplingError("atmosphere.model", "wave_optics", f"no scene spacing satisfies the beam bound for an "
                            f"aperture of {aperture:g} m and a region of {region:g} m over {L:g} m")
    need, delta1, deltan = best
    n = int(sfft.next_fast_len(int(math.ceil(need))))
    n += n % 2
    if n > max_n:
        raise SamplingError("atmosphere.model", "wave_optics",
                            f"the beam through this path needs a {n} x {n} grid (aperture {aperture:g} m at "
                            f"{delta1 * 1e3:.3g} mm, scene region {region:g} m + turbulent spread {s:.3g} m at "
                            f"{deltan * 1e3:.3g} mm, r0 {r0_spherical:.3g} m), more than {max_n}: lower Cn2, "
                            "shorten the path or image a smaller region")
    zl = np.asarray(layer_z, np.float64)
    order = np.argsort(L - zl)
    zeta = (0.0, *(float(L - zl[i]) for i in order), float(L))
    return BeamSampling(n=n, delta1=delta1, deltan=deltan, zeta=zeta,
                        layer_index=tuple(int(i) for i in order), region=float(region))


def aperture_field(n: int, delta: float, diameter: float, sub: int = 8) -> np.ndarray:
    """Uniform disc of ``diameter`` on an n x n grid of spacing ``delta`` in FFT order (the centre
    at index 0), each sample the disc's area fraction of its cell (anti-aliased edge).

    Parameters
    ----------
    n : int
    delta, diameter : float
        m.
    sub : int
        Sub-samples per cell side for the area fraction.

    Returns
    -------
    complex64 (n, n)
    """
    h = min(int(math.ceil(diameter / 2 / delta)) + 1, n // 2 - 1)  # the disc lies within |i| <= h
    i = np.arange(-h, h + 1)
    off = (np.arange(sub) + 0.5) / sub - 0.5
    x = (i[:, None] + off[None, :]).ravel() * delta
    inside = (x[:, None] ** 2 + x[None, :] ** 2) <= (diameter / 2) ** 2
    frac = inside.reshape(2 * h + 1, sub, 2 * h + 1, sub).mean(axis=(1, 3))
    out = np.zeros((n, n), np.complex64)
    out[np.ix_(i % n, i % n)] = frac
    return out


@njit(parallel=True, cache=True, fastmath=True)
def _chirp(u, q):
    """In place: u[i, j] *= q[i] q[j] (a separable quadratic phase)."""
    n0, n1 = u.shape
    for i in prange(n0):
        qi = q[i]
        for j in range(n1):
            u[i, j] *= qi * q[j]


@njit(parallel=True, cache=True, fastmath=True)
def _layer(u, scale, screen, ca, cb, delta, dx, absorber):
    """In place: u *= scale * absorber * exp(+-j phi), phi sampled bilinearly from ``screen``
    (rad, spacing |dx|, sample (0, 0) at plane coordinates (0, 0)) at (ca + i delta, cb + j delta)
    for FFT-order indices i, j; the sign of ``dx`` is the sign of the phase; the phase reduced to
    cycles in float64 before the float32 sin/cos."""
    sgn = 1.0 if dx > 0 else -1.0
    dx = abs(dx)
    n0, n1 = u.shape
    ns0, ns1 = screen.shape
    inv2pi = sgn / (2.0 * math.pi)
    has_screen = ns0 > 1
    h0, h1 = (n0 + 1) // 2, (n1 + 1) // 2
    for i in prange(n0):
        ii = np.int64(i)
        if ii >= h0:
            ii -= n0
        fa = (ca + ii * delta) / dx
        if fa < 0.0:
            fa = 0.0
        if fa > ns0 - 1.001:
            fa = ns0 - 1.001
        i0 = int(fa)
        wa = fa - i0
        for j in range(n1):
            jj = np.int64(j)
            if jj >= h1:
                jj -= n1
            ab = absorber[abs(ii)] * absorber[abs(jj)] * scale
            if has_screen:
                fb = (cb + jj * delta) / dx
                if fb < 0.0:
                    fb = 0.0
                if fb > ns1 - 1.001:
                    fb = ns1 - 1.001
                j0 = int(fb)
                wb = fb - j0
                phi = ((1 - wa) * ((1 - wb) * screen[i0, j0] + wb * screen[i0, j0 + 1])
                       + wa * ((1 - wb) * screen[i0 + 1, j0] + wb * screen[i0 + 1, j0 + 1]))
                cyc = phi * inv2pi
                y = np.float32(cyc - np.floor(cyc + 0.5))
                sn, cs = sincos_cycles(y)
                v = u[i, j]
                u[i, j] = complex(ab * (v.real * cs - v.imag * sn), ab * (v.real * sn + v.imag * cs))
            else:
                u[i, j] *= ab


def _quadratic(n: int, coef: float) -> np.ndarray:
    """exp(j coef i^2) for FFT-order indices i, complex64 (i^2 exact in float64)."""
    i = sfft.fftfreq(n, 1.0 / n)
    return np.exp(1j * coef * i * i).astype(np.complex64)


def _absorber(n: int) -> np.ndarray:
    """Per-axis factor of the separable super-Gaussian absorbing boundary exp(-(i / 0.47 n)^16)."""
    i = np.arange(n // 2 + 1)
    return np.exp(-(i / (0.47 * n)) ** 16)


def transmit_field(s: BeamSampling, wavelength: float, aperture: float, screens: np.ndarray | None = None,
                   centres: np.ndarray | None = None, screen_dx: float = 1.0, sign: float = 1.0) -> np.ndarray:
    """The aperture's transmit field at the scene plane, geometric phase exp(j k r^2 / 2L) removed,
    complex64 (n, n) in FFT order (spacing ``s.deltan``, centre at index 0).

    Parameters
    ----------
    s : BeamSampling
    wavelength, aperture : float
        m.
    screens : float32 (L, ns, ns), optional
        The path's layer screens, rad (None: vacuum).
    centres : float64 (L, 2), optional
        Screen-index coordinates (in units of m, relative to each screen's sample (0, 0)) of the
        grid's centre on each layer.
    screen_dx : float
        Screen spacing, m.
    sign : float
        +1: each screen multiplies the field by exp(j phi); -1: by exp(-j phi).

    Returns
    -------
    complex64 (n, n)
    """
    k = 2 * math.pi / wavelength
    n = s.n
    zeta = np.asarray(s.zeta)
    delta = s.spacing()
    m = delta[1:] / delta[:-1]
    dz = np.diff(zeta)
    absorber = _absorber(n)
    none = np.zeros((1, 1), np.float32)
    u = aperture_field(n, delta[0], aperture)
    _chirp(u, _quadratic(n, k / 2 * (1 - m[0]) / dz[0] * delta[0] ** 2))
    for i in range(len(dz)):
        df = 1 / (n * delta[i])
        q = _quadratic(n, -math.pi ** 2 * 2 * dz[i] / m[i] / k * df ** 2)
        u = sfft.fft2(u, workers=FFT_WORKERS, overwrite_x=True)
        _chirp(u, q)
        u = sfft.ifft2(u, workers=FFT_WORKERS, overwrite_x=True)
        if i < len(dz) - 1 and screens is not None:
            layer = s.layer_index[i]
            _layer(u, 1.0 / m[i], screens[layer], centres[layer, 0], centres[layer, 1], delta[i + 1],
                   screen_dx * sign, absorber)
        else:
            _layer(u, 1.0 / m[i], none, 0.0, 0.0, delta[i + 1], 1.0, absorber)
    _chirp(u, _quadratic(n, k / 2 * ((m[-1] - 1) / (m[-1] * dz[-1]) - 1 / zeta[-1]) * delta[-1] ** 2))
    return u


def _keys(t):
    """Keys cubic convolution weights (a = -1/2) of the four samples around fraction t."""
    return (((-0.5 * t + 1.0) * t - 0.5) * t, (1.5 * t - 2.5) * t * t + 1.0,
            ((-1.5 * t + 2.0) * t + 0.5) * t, (0.5 * t - 0.5) * t * t)


def sample_field(field: np.ndarray, deltan: float, coords: np.ndarray) -> np.ndarray:
    """Cubic-convolution (Keys) samples of a field in FFT order (spacing ``deltan``, centre at
    index 0, periodic) at plane coordinates ``coords`` (S, 2), m.

    Parameters
    ----------
    field : complex (n, n)
    deltan : float
        m.
    coords : float64 (S, 2)
        m.

    Returns
    -------
    complex128 (S,)
    """
    n = field.shape[0]
    fa = coords[:, 0] / deltan
    fb = coords[:, 1] / deltan
    i0 = np.floor(fa).astype(np.int64)
    j0 = np.floor(fb).astype(np.int64)
    wa, wb = _keys(fa - i0), _keys(fb - j0)
    out = np.zeros(len(coords), np.complex128)
    for di in range(4):
        for dj in range(4):
            out += wa[di] * wb[dj] * field[(i0 + di - 1) % n, (j0 + dj - 1) % n]
    return out


@functools.lru_cache(maxsize=8)
def _vacuum_boresight(s: BeamSampling, wavelength: float, aperture: float) -> complex:
    """The vacuum transmit field at the scene's centre (grid index 0), the gains' reference: one
    propagation of the whole grid for one number, so it is made once per sampling, wavelength and
    aperture (it depends on nothing else: paths of other screens on the same grid share it)."""
    return complex(transmit_field(s, wavelength, aperture)[0, 0])


def two_way_gains(path, positions: np.ndarray, targets: np.ndarray, aperture: float, region: float,
                  sampling: BeamSampling | None = None, progress=None) -> tuple[np.ndarray, BeamSampling]:
    """Two-way complex gains (P, S) of point scatterers through a frozen path, wave optics:
    g_p(t)^2 with g_p the transmit field at t (geometric phase removed) over the vacuum boresight
    field; in vacuum the far-field pattern (2 J1(u)/u)^2.

    Parameters
    ----------
    path : TurbulentPath
        Frozen screens, large enough for the propagation grids (:func:`screen_need`).
    positions : float64 (P, 3)
        Antenna positions, m (the scene centre at the origin).
    targets : float64 (S, 3)
        Scatterer positions, m.
    aperture : float
        Aperture diameter, m.
    region : float
        Scene region diameter, m (every scatterer should lie inside it).
    sampling : BeamSampling, optional
        Default :func:`plan_beam` for the path.
    progress : callable, optional
        ``progress(done, total)`` in pulses.

    Returns
    -------
    (complex128 (P, S), BeamSampling)
    """
    s = sampling or plan_for_path(path, aperture, region)
    lam = path.wavelength
    coords = np.stack([targets @ path.a, targets @ path.b], axis=1)
    vac0 = _vacuum_boresight(s, lam, aperture)
    out = np.empty((len(positions), len(targets)), np.complex128)
    for p, pos in enumerate(positions):
        lam_z = path.z / float(pos @ path.u0)  # ray to the scene centre crosses layer z at lam_z * pos
        centres = np.stack([lam_z * float(pos @ path.a), lam_z * float(pos @ path.b)], axis=1) - path.origin
        t = transmit_field(s, lam, aperture, path.screens, centres, path.dx, sign=-1.0)
        g = np.conj(sample_field(t, s.deltan, coords) / vac0)
        out[p] = g * g
        if progress is not None:
            progress(p + 1, len(positions))
    return out, s


def plan_for_path(path, aperture: float, region: float, max_n: int = MAX_N) -> BeamSampling:
    """:func:`plan_beam` for a :class:`~salkit.atmosphere.path.TurbulentPath`: its length, the
    spherical-wave r0 of its layers (r0_sph^(-5/3) = sum r0_i^(-5/3) (z_i / L)^(5/3)) and its
    layer distances.

    Parameters
    ----------
    path : TurbulentPath
    aperture, region : float
        m.
    max_n : int

    Returns
    -------
    BeamSampling
    """
    L = float(path.length)
    return plan_beam(path.wavelength, L, aperture, region, layered_r0_spherical(path.r0, path.z, L),
                     np.asarray(path.z), max_n=max_n)


def layered_r0_spherical(r0, z, length: float) -> float:
    """Spherical-wave Fried parameter of discrete layers for a source at the scene:
    r0_sph^(-5/3) = sum r0_i^(-5/3) (z_i / L)^(5/3), m (inf without turbulence).

    Parameters
    ----------
    r0 : float array (L,)
        Each layer's Fried parameter, m.
    z : float array (L,)
        Layer distances from the scene, m.
    length : float
        Path length, m.

    Returns
    -------
    float
        m.
    """
    w = float(np.sum(np.asarray(r0, float) ** (-5 / 3) * (np.asarray(z, float) / length) ** (5 / 3)))
    return w ** (-3 / 5) if w > 0 else math.inf


def screen_need(s: BeamSampling, length: float, swath: float) -> float:
    """Width a layer screen must cover for :func:`two_way_gains`, m: the widest grid on any layer
    plus the sweep of its centre as the antenna moves ``swath`` metres across the line of sight.

    Parameters
    ----------
    s : BeamSampling
    length : float
        Path length, m.
    swath : float
        Antenna displacement across the line of sight over the collection, m.

    Returns
    -------
    float
        m.
    """
    zeta = np.asarray(s.zeta)[1:-1]
    ext = s.extents()[1:-1]
    return float(np.max(ext + swath * (length - zeta) / length)) if len(zeta) else 0.0
