"""Polar format algorithm (PFA) for spotlight collections.

The phase history of a scatterer at x' (relative to the scene centre, motion-compensated to it)
is P(f, n) ~ exp(+j k_n(f) . x'), k = (4 pi f / c) u_n, u_n the unit vector from the scene centre
to the antenna. Projected on the image plane (azimuth a, range r) the samples lie on a polar
raster; a range (keystone) interpolation then an azimuth interpolation put them on a rectangle,
and a 2-D FFT forms the image on exactly the requested grid (dk = 2 pi / (n d)).

Phase: the plane-wave model leaves each scatterer with the wavefront-curvature phase
exp(-j 4 pi f_c q(x)/c), q(x) = |x - p_c| - |p_c| + u_c . x at the aperture centre p_c. It is
removed pixel by pixel, so PFA images carry the same phase as backprojection.
"""
from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from ..constants import SPEED_OF_LIGHT
from .interp import resample_rows

WORKERS = -1


def _place_centered(q: np.ndarray, n: int, axis: int) -> np.ndarray:
    """Put a centred spectrum (index j - N//2) into length n (wrapped) along ``axis``."""
    N = q.shape[axis]
    idx = (np.arange(N) - N // 2) % n
    shape = list(q.shape)
    shape[axis] = n
    out = np.zeros(shape, np.complex64)
    if axis == 0:
        out[idx, :] = q
    else:
        out[:, idx] = q
    return out


def pfa(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray,
        plane, az: np.ndarray, rg: np.ndarray, win_az, win_rg, half: int = 4) -> tuple[np.ndarray, dict]:
    """Form a spotlight image with the polar format algorithm.

    Parameters
    ----------
    ph : complex (P, M)
        Phase history with uniform, increasing ``freq`` (Hz).
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre (origin), m.
    ref_range : float64 (P,)
        Reference range per pulse, m (re-referenced to |p| here if different).
    plane : ImagePlane
    az, rg : float64
        Pixel coordinates, m, uniform: az[i] = az_c + (i - nx//2) dx, likewise rg.
    win_az, win_rg : callable(n) -> ndarray
        Amplitude windows over the K-space support.
    half : int
        Half-width of the interpolation kernel, samples.

    Returns
    -------
    image : complex64 (nx, ny), normalised so a unit scatterer peaks near 1.
    info : dict
        K-space support sizes.
    """
    c = SPEED_OF_LIGHT
    P, M = ph.shape
    nx, ny = az.size, rg.size
    dx, dy = az[1] - az[0], rg[1] - rg[0]
    az_c, rg_c = az[nx // 2], rg[ny // 2]
    rng_c = np.linalg.norm(positions, axis=1)
    corr = np.exp(-1j * 4 * np.pi * np.outer(ref_range - rng_c, freq) / c)
    data = (ph * corr).astype(np.complex64)
    u = positions / rng_c[:, None]
    ua = u @ plane.azimuth
    ur = u @ plane.range
    f0, df = freq[0], freq[1] - freq[0]
    kmin, kmax = 4 * np.pi * freq[0] / c, 4 * np.pi * freq[-1] / c
    # range (keystone) interpolation onto a common uniform ky grid
    ends = np.stack([kmin * ur, kmax * ur], axis=1)
    ky_lo, ky_hi = np.max(ends.min(axis=1)), np.min(ends.max(axis=1))
    dky = 2 * np.pi / (ny * dy)
    nky = min(int(np.floor((ky_hi - ky_lo) / dky)), ny)  # every sample inside the data
    ky_c = 0.5 * (ky_lo + ky_hi)
    ky = ky_c + (np.arange(nky) - nky // 2) * dky
    fpos = (ky[None, :] * c / (4 * np.pi * ur[:, None]) - f0) / df
    d1 = resample_rows(data, fpos, half=half)  # (P, nky)
    # azimuth interpolation onto a uniform kx grid
    t = ua / ur  # kx = ky * t
    order = np.argsort(t)
    ts, idx_sorted = t[order], np.arange(P, dtype=np.float64)[order]
    kx_ends = np.stack([ky * ts[0], ky * ts[-1]], axis=1)
    kx_lo, kx_hi = np.max(kx_ends.min(axis=1)), np.min(kx_ends.max(axis=1))
    dkx = 2 * np.pi / (nx * dx)
    nkx = min(int(np.floor((kx_hi - kx_lo) / dkx)), nx)
    kx_c = 0.5 * (kx_lo + kx_hi)
    kx = kx_c + (np.arange(nkx) - nkx // 2) * dkx
    tneed = kx[None, :] / ky[:, None]  # (nky, nkx)
    ppos = np.interp(tneed, ts, idx_sorted)
    d2 = resample_rows(np.ascontiguousarray(d1.T), ppos, half=half)  # (nky, nkx)
    w_a = np.asarray(win_az(nkx), np.float32)
    w_r = np.asarray(win_rg(nky), np.float32)
    q = (d2 * w_r[:, None] * w_a[None, :]).T  # (nkx, nky)
    # centre-offset ramps, then separable DFTs onto the requested grid
    q = q * np.exp(-1j * (np.arange(nkx) - nkx // 2) * dkx * az_c)[:, None]
    q = q * np.exp(-1j * (np.arange(nky) - nky // 2) * dky * rg_c)[None, :]
    buf = _place_centered(_place_centered(q.astype(np.complex64), nx, 0), ny, 1)
    img = sfft.fftshift(sfft.fft2(buf, workers=WORKERS), axes=(0, 1))
    img *= np.exp(-1j * kx_c * az)[:, None].astype(np.complex64)
    img *= np.exp(-1j * ky_c * rg)[None, :].astype(np.complex64)
    img /= np.float32(w_a.sum() * w_r.sum())
    # wavefront-curvature phase at the aperture centre, pixel by pixel (float64 geometry)
    pc = positions[P // 2]
    X = plane.points(az[:, None], rg[None, :])
    q_curv = np.linalg.norm(X - pc, axis=-1) - np.linalg.norm(pc) + X @ (pc / np.linalg.norm(pc))
    fc = freq[M // 2]
    img *= np.exp(1j * 4 * np.pi * fc / c * q_curv).astype(np.complex64)
    return img.astype(np.complex64), {"support_azimuth": nkx, "support_range": nky}
