"""Spherical waves through turbulence: a point source propagated on scaled grids (the source plane
finer than the observation plane) through extended screens (Schmidt 2010, ch. 8-9), for the
spherical-wave scintillation and structure function of a ladar's return path.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from ..constants import FFT_WORKERS
from ..errors import SamplingError
from .screens import phase_screens
from .turbulence import r0_from_cn2, rytov_variance
from .waveoptics import MAX_N


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
