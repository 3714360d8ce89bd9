"""A turbulent path of frozen phase-screen layers between the scene and the platform.

Layers are planes perpendicular to the nominal line of sight u0 (scene centre -> aperture centre),
at distances z_i from the scene centre. The ray from the antenna p to a scatterer t crosses layer i
at q = t + lambda (p - t), lambda = (z_i - t.u0) / ((p - t).u0); the screen is sampled there
(bilinear). Monostatic and stop-and-go: transmit and receive follow the same ray through the same
frozen screens, so the two-way phase is twice the one-way sum, and the two-way structure function
is 4 times the one-way one: r0_two_way = 2^(-6/5) r0 (see docs/turbulence.md for the comparison
with the seed's r0 / 2^(5/6)).

Each layer of thickness dz gets r0_i = (0.423 k^2 Cn^2 dz)^(-3/5). Two rays from the same target
to antennas a distance d apart cross layer i d z_i/R apart, so the one-way phase difference has
D(d) = sum_i 6.88 (d z_i / (R r0_i))^(5/3): the spherical-wave r0 of the path, as it should be.
"""
from __future__ import annotations

import math
import threading
import warnings
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from ..errors import ScenarioError
from .screens import cached_array, keep_array, phase_screens
from .turbulence import max_layer_spacing, r0_from_cn2, structure_function


@dataclass(frozen=True)
class TurbulentPath:
    """Frozen screens (L, n, n) rad at distances ``z`` (L,) m from the scene centre along ``u0``.

    Screen coordinates: sample (i, j) is at origin + i*dx*a + j*dx*b in the layer plane, with
    ``a`` the along-track axis and ``b`` = u0 x a.
    """

    screens: np.ndarray
    z: np.ndarray
    r0: np.ndarray
    dx: float
    origin: np.ndarray  # (L, 2) plane coordinates (a, b) of sample (0, 0), m
    u0: np.ndarray
    a: np.ndarray
    b: np.ndarray
    wavelength: float
    length: float = math.nan  # path length (slant range), m

    def crossing_extent(self, positions: np.ndarray, targets: np.ndarray) -> tuple[float, float]:
        """Largest extents (along a, along b) the rays cover on any layer, m."""
        ext_a, ext_b = 0.0, 0.0
        for zi in self.z:
            q = ray_crossings(positions, targets, zi, self.u0)
            ext_a = max(ext_a, float(np.ptp(q @ self.a)))
            ext_b = max(ext_b, float(np.ptp(q @ self.b)))
        return ext_a, ext_b

    def one_way_structure_function(self, d: np.ndarray, slant_range: float) -> np.ndarray:
        """Theoretical D(d) (rad^2) of the one-way phase difference between antennas d apart."""
        d = np.atleast_1d(np.asarray(d, dtype=np.float64))
        return sum(structure_function(d * zi / slant_range, ri) for zi, ri in zip(self.z, self.r0))


def ray_crossings(positions, targets, z, u0):
    """Where the rays from ``positions`` (P, 3) to ``targets`` (T, 3) cross the layer at distance
    ``z`` (m) along the path axis ``u0``: points (P * T, 3), m.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    targets : float64 (T, 3)
        Scatterer positions, m.
    z : float
        Distance of the layer from the scene along ``u0``, m.
    u0 : float64 (3,)
        Unit path axis (scene to antenna).

    Returns
    -------
    float64 (P * T, 3)
        Crossing points, m.
    """
    p = positions[:, None, :]
    t = targets[None, :, :]
    lam = (z - t @ u0) / np.maximum((p - t) @ u0, 1e-30)
    return (t + lam[..., None] * (p - t)).reshape(-1, 3)


def path_frame(u0: np.ndarray, along: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The frame of a path and of its layers' screens: the path axis, the screens' first axis
    (``along`` made orthogonal to it) and their second, ``b = u0 x a``.

    Parameters
    ----------
    u0 : float64 (3,)
        Path direction (any length), scene towards the platform.
    along : float64 (3,)
        Direction of the screens' first axis (the track), any length, not parallel to ``u0``.

    Returns
    -------
    (u0, a, b) : three float64 (3,) unit vectors, dimensionless
        Orthonormal, right-handed.

    Examples
    --------
    >>> u0, a, b = path_frame(np.array([0.0, 0.0, 2.0]), np.array([1.0, 0.0, 1.0]))
    >>> a.tolist(), b.tolist()
    ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    """
    u0 = np.asarray(u0, float) / np.linalg.norm(u0)
    a = np.asarray(along, float) - np.dot(along, u0) * u0
    a = a / np.linalg.norm(a)
    return u0, a, np.cross(u0, a)


def build_path(cn2, slant_range: float, wavelength: float, layers: int, n: int, dx: float,
               u0: np.ndarray, a: np.ndarray, seed: int = 0, outer_scale: float | None = None,
               inner_scale: float | None = None, centre: tuple[float, float] = (0.0, 0.0)) -> TurbulentPath:
    """Equal layers over the path, each at the middle of its slab (:func:`path_layers`), with
    screens of n x n at dx.

    ``cn2`` is a constant or one value per layer (index 0 next to the scene): a profiled path.
    Warns (with the numbers) when the layer spacing exceeds seed 004 eq 8 for the strongest layer.

    Parameters
    ----------
    cn2 : float or sequence of float
        Cn^2, m^(-2/3): constant, or one value per layer.
    slant_range : float
        Path length, m.
    wavelength : float
        m.
    layers : int
        Number of equal layers.
    n : int
        Screen size, samples.
    dx : float
        Screen sample spacing, m.
    u0 : float64 (3,)
        Unit path axis, scene to antenna.
    a : float64 (3,)
        Unit along-track axis (the screens' first axis, made orthogonal to ``u0``).
    seed : int
        Seed of the screens (one draw, scaled per layer).
    outer_scale, inner_scale : float, optional
        Von Karman L0 and inner scale l0, m.
    centre : (float, float)
        Offset of the screens' centre in the layer plane, m.

    Returns
    -------
    TurbulentPath
        Screens (rad), layer distances z (m), per-layer r0 (m) and the frame.
    """
    z, r0 = path_layers(cn2, slant_range, wavelength, layers)
    # a screen scales as r0^(-5/6): the same seed's draws at r0 = 1 m serve every Cn2 (the classes
    # of a turbulence study, the models compared, the figures' path), each layer scaled to its r0
    scr = _unit_screens(layers, n, float(dx), seed, outer_scale, inner_scale)
    scr = scr.copy() if not scr.flags.writeable else scr  # the cache's own stays as drawn
    scr *= (np.asarray(r0, np.float64) ** (-5.0 / 6.0)).astype(np.float32)[:, None, None]
    u0, a, b = path_frame(u0, a)
    origin = np.tile(np.array(centre) - (n - 1) / 2 * dx, (layers, 1))
    return TurbulentPath(scr, z, r0, dx, origin, u0, a, b, wavelength, float(slant_range))


#: Bytes of unit-r0 layer screens kept for the next path of the same size, spacing, scales and seed.
UNIT_SCREEN_CACHE_BYTES = 256 * 2 ** 20
_unit_cache: OrderedDict = OrderedDict()
_unit_lock = threading.Lock()


def screens_memory(layers: int, n: int) -> float:
    """Bytes a path's screens hold: float32 (layers, n, n), twice where the unit-r0 draw is kept
    (:data:`UNIT_SCREEN_CACHE_BYTES`) beside the path's scaled copy.

    Parameters
    ----------
    layers, n : int

    Returns
    -------
    float
        bytes.
    """
    size = 4.0 * layers * n * n
    return 2.0 * size if size <= UNIT_SCREEN_CACHE_BYTES else size


def _unit_screens(layers: int, n: int, dx: float, seed: int, outer_scale, inner_scale) -> np.ndarray:
    """The layers' screens at r0 = 1 m, float32 (layers, n, n), drawn together from one generator
    seeded ``seed``: kept (read-only) for the next path of the same key when seeded and within
    :data:`UNIT_SCREEN_CACHE_BYTES`, else a writable array of the caller's own."""
    key = (layers, n, dx, seed, outer_scale, inner_scale)
    keep = isinstance(seed, (int, np.integer))  # no seed: fresh entropy, never kept
    scr = cached_array(_unit_cache, _unit_lock, key) if keep else None
    if scr is not None:
        return scr
    # all the layers in one call: two screens an FFT (the real and imaginary parts of one complex
    # field, independent) and the FFTs batched, where a call a layer threw the imaginary half away
    # (4x faster; 0.22.0)
    scr = phase_screens(n, dx, 1.0, count=layers, rng=np.random.default_rng(seed), outer_scale=outer_scale,
                        inner_scale=inner_scale, dtype=np.float32)
    if keep and scr.nbytes <= UNIT_SCREEN_CACHE_BYTES:
        keep_array(_unit_cache, _unit_lock, key, scr, UNIT_SCREEN_CACHE_BYTES)
    return scr


def path_layers(cn2, slant_range: float, wavelength: float, layers: int) -> tuple[np.ndarray, np.ndarray]:
    """The layers of :func:`build_path` without their screens: distances from the scene and Fried
    parameters. Warns (with the numbers) when the spacing exceeds seed 004 eq 8.

    Parameters
    ----------
    cn2 : float or sequence of float
        Cn^2, m^(-2/3): constant, or one value per layer (index 0 next to the scene).
    slant_range : float
        Path length, m.
    wavelength : float
        m.
    layers : int

    Returns
    -------
    (float64 (L,), float64 (L,))
        z (m) and r0 (m) of each layer.
    """
    if layers < 1:
        raise ScenarioError("atmosphere.layers", layers, "must be >= 1")
    prof = np.broadcast_to(np.asarray(cn2, dtype=np.float64), (layers,)) if np.ndim(cn2) == 0 else \
        np.asarray(cn2, dtype=np.float64)
    if prof.shape != (layers,):
        raise ScenarioError("atmosphere.cn2", f"{prof.size} values", f"a profile needs one value per layer ({layers})")
    if not np.all(np.isfinite(prof)) or np.any(prof <= 0):
        raise ScenarioError("atmosphere.cn2", cn2, "must be finite and > 0")
    dz = slant_range / layers
    zmax = max_layer_spacing(float(prof.max()), wavelength)
    if dz > zmax:
        warnings.warn(f"atmosphere.layers: spacing {dz:.4g} m exceeds the Fresnel limit {zmax:.4g} m "
                      f"(seed 004 eq 8) for Cn2 = {prof.max():g}; use at least {math.ceil(slant_range / zmax)} "
                      f"layers", UserWarning, stacklevel=2)
    z = (np.arange(layers) + 0.5) * dz
    return z, np.asarray(r0_from_cn2(prof, dz, wavelength), dtype=np.float64)


def aperture_strehl(z, r0, slant_range: float, positions: np.ndarray, weights: np.ndarray, u0: np.ndarray,
                    outer_scale: float | None = None, inner_scale: float | None = None) -> float:
    """Expected |I(t)|^2 / |I_vacuum(t)|^2 at a point target t at the scene centre (the
    long-exposure Strehl ratio of the synthetic aperture): sum_nm w_n w_m exp(-D2(d_nm) / 2) /
    (sum w)^2, with D2 = 4 D1 the two-way structure function of the phases of pulses d_nm apart
    across the line of sight (D1 = sum_i D(d z_i / R; r0_i), the path's spherical-wave one) and
    E exp(i (phi_n - phi_m)) = exp(-D2 / 2) exact for Gaussian phase screens. Pulses on a straight
    track at equal spacing (the lags' separations are k times the mean step).

    Parameters
    ----------
    z, r0 : float arrays (L,)
        Layer distances from the scene and Fried parameters, m (:func:`path_layers`).
    slant_range : float
        m.
    positions : float64 (N, 3)
        Antenna positions, m.
    weights : float64 (N,)
        Azimuth amplitude weights of the image formation.
    u0 : float64 (3,)
        Unit line of sight, scene to antenna.
    outer_scale, inner_scale : float, optional
        Von Karman L0 and inner scale l0 of the screens, m.

    Returns
    -------
    float
        In (0, 1].
    """
    w = np.asarray(weights, np.float64)
    p = np.asarray(positions, np.float64)
    n = len(w)
    if n < 2:
        return 1.0
    across = (p[-1] - p[0]) - np.dot(p[-1] - p[0], u0) * u0
    step = float(np.linalg.norm(across)) / (n - 1)
    c = np.correlate(w, w, "full")[n - 1:]  # lags 0 .. n-1
    lag = np.arange(n) * step
    probe = np.unique(np.concatenate([np.linspace(0.0, lag[-1], 513), lag[:64]]))  # D is smooth: interpolate
    d1 = sum(structure_function(probe * zi / slant_range, ri, outer_scale, inner_scale) for zi, ri in zip(z, r0))
    d2 = 4.0 * np.interp(lag, probe, d1)
    return float((c[0] + 2.0 * np.sum(c[1:] * np.exp(-0.5 * d2[1:]))) / np.sum(w) ** 2)


@njit(cache=True, inline="always")
def path_phase(px, py, pz, tx, ty, tz, screens, z, origin, dx, u0, a, b):
    """One-way phase (rad) along the ray p -> t through all layers (bilinear interpolation).

    Parameters
    ----------
    px, py, pz : float
        Antenna position, m.
    tx, ty, tz : float
        Scatterer position, m.
    screens : float (L, n, n)
        Phase screens, rad.
    z : float64 (L,)
        Layer distances from the scene, m.
    origin : float64 (2,)
        Screen origin in the layer plane, m.
    dx : float
        Screen spacing, m.
    u0, a, b : float64 (3,)
        Path axis and the screens' two axes.

    Returns
    -------
    float
        rad.
    """
    L, n, _ = screens.shape
    dpx, dpy, dpz = px - tx, py - ty, pz - tz
    den = dpx * u0[0] + dpy * u0[1] + dpz * u0[2]
    tu = tx * u0[0] + ty * u0[1] + tz * u0[2]
    acc = 0.0
    for l in range(L):
        lam = (z[l] - tu) / den
        qx, qy, qz = tx + lam * dpx, ty + lam * dpy, tz + lam * dpz
        ca = ((qx * a[0] + qy * a[1] + qz * a[2]) - origin[l, 0]) / dx
        cb = ((qx * b[0] + qy * b[1] + qz * b[2]) - origin[l, 1]) / dx
        if ca < 0.0:
            ca = 0.0
        if cb < 0.0:
            cb = 0.0
        if ca > n - 1.001:
            ca = n - 1.001
        if cb > n - 1.001:
            cb = n - 1.001
        i0 = int(ca)
        j0 = int(cb)
        fa = ca - i0
        fb = cb - j0
        acc += ((1 - fa) * ((1 - fb) * screens[l, i0, j0] + fb * screens[l, i0, j0 + 1])
                + fa * ((1 - fb) * screens[l, i0 + 1, j0] + fb * screens[l, i0 + 1, j0 + 1]))
    return acc


@njit(parallel=True, cache=True)
def two_way_phases(positions, targets, screens, z, origin, dx, u0, a, b):
    """Two-way path phase (P, S) rad: twice the one-way phase along the same ray.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    targets : float64 (S, 3)
        Scatterer positions, m.
    screens, z, origin, dx, u0, a, b
        As :func:`path_phase`.

    Returns
    -------
    float64 (P, S)
        rad.
    """
    P = positions.shape[0]
    S = targets.shape[0]
    out = np.empty((P, S), np.float64)
    for p in prange(P):
        for s in range(S):
            out[p, s] = 2.0 * path_phase(positions[p, 0], positions[p, 1], positions[p, 2], targets[s, 0],
                                         targets[s, 1], targets[s, 2], screens, z, origin, dx, u0, a, b)
    return out
