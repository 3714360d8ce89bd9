"""Shift-invariant stripmap backprojection.

Per-pixel apertures (each pixel integrating its own 3 dB aperture, equalised by 1/g) are not
shift-invariant: a target seen from a neighbouring pixel is weighted by g(u - x_t)/g(u - x), which
narrows the azimuth response by ~2.6 %. Instead:

1. backproject with unit weights every pulse whose beam (to the first nulls) covers the pixel,
   on an azimuth grid fine enough for the whole beam's Doppler band (dx' <= lambda / (4 s_null));
2. at fixed range the image of a target is sum_u g(u - x_t) exp(-j kappa_u (x - x_t)) with
   kappa_u = -2K sin(theta_u): its azimuth spectrum is the target's Doppler history. Multiply it by
   w(kappa)/g(kappa) over the two-way 3 dB band and zero elsewhere, exactly like omega-k;
3. keep every L-th row (the requested grid) and normalise by the window sum over the band's pulses.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

from ..geometry.collection import beam_gain, beam_gain_table, two_way_3db_sin
from .bp_kernel import backproject
from ..constants import FFT_WORKERS
from ..tolerances import BP_UPSAMPLE

_NULL = 1.2196698912665045  # first null of the Airy pattern, in lambda / D


def _window_continuous(win, x):
    """Window values at normalised positions x in [0, 1] (linear interpolation of 4097 samples)."""
    ref = np.asarray(win(4097), np.float64)
    return np.interp(x, np.linspace(0, 1, ref.size), ref)


def stripmap_backprojection(ph, plane, az, rg, win, upsample=BP_UPSAMPLE, progress=None, interpolation="linear"):
    """Focus stripmap data by full-beam backprojection and Doppler-domain equalisation.

    Parameters
    ----------
    ph : PhaseHistory
        Range-compressed stripmap collection (straight or curved track).
    plane : ImagePlane
    az, rg : ndarray
        Requested pixel coordinates, m (uniform azimuth spacing).
    win : callable(n) -> ndarray
        Amplitude window (applied over the 3 dB Doppler band and over frequency).
    upsample : int
        Range-profile upsampling of the backprojection.
    progress : callable, optional
        ``progress(done, total)`` in pulses.
    interpolation : {"linear", "nearest", "cubic", "fitted"}
        How the kernel reads the range profiles between bins.

    Returns
    -------
    complex64 (nx, ny), calibrated so a unit scatterer on the beam centre line peaks at 1.
    """
    lam = ph.wavelength
    D = ph.real_aperture
    K = 2 * math.pi / lam
    s_null = min(_NULL * lam / D, 0.99)
    s3 = two_way_3db_sin(lam, D)
    a = ph.track
    pc = ph.center_position
    Rs = float(np.linalg.norm(-pc - np.dot(-pc, a) * a))
    u_c = float(pc @ a)
    dx = float(az[1] - az[0])
    L = max(1, int(math.ceil(dx / (0.95 * lam / (4 * s_null)))))
    dxp = dx / L
    rho3 = lam / (4 * s3)
    n_pad = int(math.ceil(16 * rho3 / dxp)) + 8
    nxp = az.size * L + 2 * n_pad
    azp = az[0] + (np.arange(nxp) - n_pad) * dxp
    u = ph.positions @ a
    half_null = Rs * math.tan(math.asin(s_null))
    W = (np.abs(u[None, :] - (azp[:, None] + u_c)) <= half_null).astype(np.float32)
    M = ph.data.shape[1]
    wr = win(M)
    row_origin = plane.points(azp, np.zeros_like(azp))
    img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, row_origin, plane.range, rg,
                      W, wr, upsample=upsample, progress=progress, interpolation=interpolation)
    img = img / wr.sum()
    # Doppler-domain equalisation over the two-way 3 dB band
    kappa = 2 * math.pi * sfft.fftfreq(nxp, dxp)
    rel = -pc / np.linalg.norm(pc)
    sin_c = float(rel @ a)  # sine of the squint of the beam centre
    sin_off = -kappa / (2 * K) - sin_c
    band = np.abs(sin_off) <= s3
    table, dsin = beam_gain_table(lam, D)
    g = beam_gain(table, dsin, sin_off[band])
    H = np.zeros(nxp)
    H[band] = _window_continuous(win, (sin_off[band] + s3) / (2 * s3)) / np.maximum(g, 1e-3)
    spec = sfft.fft(img, axis=0, workers=FFT_WORKERS)
    spec *= H[:, None]
    out = sfft.ifft(spec, axis=0, workers=FFT_WORKERS)[n_pad:n_pad + az.size * L:L]
    # a unit target collects sum over the band's pulses of w: normalise by it
    du = float(np.mean(np.abs(np.diff(u))))
    half3 = Rs * math.tan(math.asin(s3))
    k = np.arange(-int(half3 / du), int(half3 / du) + 1)
    sin_k = k * du / np.hypot(k * du, Rs)
    norm = _window_continuous(win, (sin_k + s3) / (2 * s3)).sum()
    return (out / norm).astype(np.complex64)
