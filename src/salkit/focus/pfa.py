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

import math

import numpy as np
import scipy.fft as sfft
from numba import njit, prange

from ..constants import SPEED_OF_LIGHT
from .backprojection import _sincos_cycles
from .interp import azimuth_pass, interp_rows_linear, kernel_table

WORKERS = -1


@njit(parallel=True, cache=True, fastmath=True)
def _finalise(img, az, rg, a, r, pc, kx_c, ky_c, k_c, scale):
    """In place: img *= scale * exp(-j (kx_c az + ky_c rg)) * exp(+j k_c q(x)), where
    q(x) = |x - p_c| - |p_c| + u_c . x is the wavefront curvature at the aperture centre p_c.
    Geometry and phase in float64 (reduced to cycles), sin/cos in float32."""
    nx, ny = img.shape
    rc = math.sqrt(pc[0] * pc[0] + pc[1] * pc[1] + pc[2] * pc[2])
    ux, uy, uz = pc[0] / rc, pc[1] / rc, pc[2] / rc
    inv2pi = 1.0 / (2.0 * math.pi)
    for i in prange(nx):
        for j in range(ny):
            X0 = az[i] * a[0] + rg[j] * r[0]
            X1 = az[i] * a[1] + rg[j] * r[1]
            X2 = az[i] * a[2] + rg[j] * r[2]
            d0, d1, d2 = X0 - pc[0], X1 - pc[1], X2 - pc[2]
            q = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) - rc + (X0 * ux + X1 * uy + X2 * uz)
            cyc = (k_c * q - kx_c * az[i] - ky_c * rg[j]) * inv2pi
            y = np.float32(cyc - np.float64(np.int64(cyc)))
            y = y - np.float32(np.int32(y + np.float32(0.5) * (np.float32(y >= 0) - np.float32(y < 0))))
            s, c = _sincos_cycles(y)
            v = img[i, j]
            re = v.real * c - v.imag * s
            im = v.real * s + v.imag * c
            img[i, j] = complex(re * scale, im * scale)


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
    if np.max(np.abs(ref_range - rng_c)) > 1e-9:  # re-reference to the scene centre
        corr = np.exp(-1j * 4 * np.pi * np.outer(ref_range - rng_c, freq) / c)
        data = (ph * corr).astype(np.complex64)
    else:
        data = np.ascontiguousarray(ph, dtype=np.complex64)
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
    # input index of ky[j] on pulse n is linear in j: x0[n] + j * step[n]
    x0 = (ky[0] * c / (4 * np.pi * ur) - f0) / df
    step = dky * c / (4 * np.pi * ur) / df
    d1 = np.empty((P, nky), np.complex64)
    interp_rows_linear(data, x0, step, half, kernel_table(half), d1)
    # azimuth interpolation onto a uniform kx grid
    t = ua / ur  # kx = ky * t
    if t[-1] < t[0]:  # make pulses run with increasing t
        t, d1 = t[::-1], d1[::-1]
    if np.any(np.diff(t) <= 0):
        raise ValueError("PFA needs the look angle to change monotonically over the aperture")
    kx_ends = np.stack([ky * t[0], ky * t[-1]], axis=1)
    kx_lo, kx_hi = np.max(kx_ends.min(axis=1)), np.min(kx_ends.max(axis=1))
    dkx = 2 * np.pi / (nx * dx)
    nkx = min(int(np.floor((kx_hi - kx_lo) / dkx)), nx)
    kx_c = 0.5 * (kx_lo + kx_hi)
    kx = kx_c + (np.arange(nkx) - nkx // 2) * dkx
    w_a = np.asarray(win_az(nkx), np.float64)
    w_r = np.asarray(win_rg(nky), np.float64)
    # windows and the grid-centre ramps as two 1-D vectors; azimuth pass writes the FFT buffer
    v_a = (w_a * np.exp(-1j * (np.arange(nkx) - nkx // 2) * dkx * az_c)).astype(np.complex64)
    v_r = (w_r * np.exp(-1j * (np.arange(nky) - nky // 2) * dky * rg_c)).astype(np.complex64)
    buf = np.zeros((nx, ny), np.complex64)
    ia = ((np.arange(nkx) - nkx // 2) % nx).astype(np.int64)
    ir = ((np.arange(nky) - nky // 2) % ny).astype(np.int64)
    # fftshift of the output = (-1)^index on the input for even sizes: fold it into the vectors
    if nx % 2 == 0:
        v_a = v_a * np.where(ia % 2 == 0, 1, -1).astype(np.complex64)
    if ny % 2 == 0:
        v_r = v_r * np.where(ir % 2 == 0, 1, -1).astype(np.complex64)
    azimuth_pass(np.ascontiguousarray(d1.T), np.ascontiguousarray(t), kx, ky, v_a, v_r, half,
                 kernel_table(half), buf, ia, ir)
    img = sfft.fft2(buf, workers=WORKERS, overwrite_x=True)
    if nx % 2 or ny % 2:
        img = sfft.fftshift(img, axes=tuple(ax for ax, n in ((0, nx), (1, ny)) if n % 2))
    pc = positions[P // 2]
    _finalise(img, np.ascontiguousarray(az, np.float64), np.ascontiguousarray(rg, np.float64),
              plane.azimuth, plane.range, pc, kx_c, ky_c, 4 * np.pi * freq[M // 2] / c,
              np.float32(1.0 / (w_a.sum() * w_r.sum())))
    return img.astype(np.complex64), {"support_azimuth": nkx, "support_range": nky}
