"""Random phase screens by FFT spectral inversion with integrated-cell subharmonics.

A screen is phi(x) = sum_c a_c z_c exp(j 2 pi f_c . x) over frequency cells c, with z_c circular
complex Gaussian (E|z|^2 = 2): the real and the imaginary parts are two independent screens, so a
batch of K screens costs K/2 transforms.

* High frequencies: the FFT grid, f = k / (N dx); a_c^2 = Phi(f_c) df^2, except the 5 x 5 cells
  around DC whose variance is integrated over the cell (the PSD changes by orders of magnitude
  across them).
* Low frequencies: the DC cell of the FFT grid is split into 3 x 3 cells, the centre one again,
  for ``levels`` levels (default 4; Lane et al. 1992; Johansson & Gavel 1994). Each cell's variance is the
  PSD integrated over the cell (a 24 x 24 sub-grid), and its sinusoid sits at the cell's
  power-weighted rms frequency (direction of the cell centre), which keeps the structure function
  right where f r << 1. Sampling the PSD at cell centres instead leaves a 10-30 % deficit at N/4.
  The sinusoids are evaluated as a separable matrix product, not N^2 exponentials each.
* Below the last level every frequency has 2 pi f L < 0.04 over the screen, so the rest of the
  spectrum acts as a random tilt: its variance (4 pi^2 int Phi f_x^2 over the innermost cell) is
  added as one (Kolmogorov converges only as f^(1/3): dropping it loses ~3-8 % of D(N/4)).
"""
from __future__ import annotations

import math
import threading
from collections import OrderedDict
from functools import lru_cache

import numpy as np
from numba import njit, prange
import scipy.fft as sfft

from ..errors import ScenarioError
from ..resources import check_memory
from .turbulence import psd
from ..constants import FFT_WORKERS
import lazy_loader as _lazy
_scipy = _lazy.load("scipy", suppress_warning=True)
_scipy_ndimage = _lazy.load("scipy.ndimage", suppress_warning=True)


NEAR = 3  # FFT cells with max(|i|, |j|) <= NEAR are modelled as explicit sinusoids
SPLIT = 3  # ... the innermost ring split into SPLIT x SPLIT sub-cells
ALIAS = 4  # spectral aliases folded into the FFT grid (|m|, |q| <= ALIAS)
INTEGRATE = 16  # FFT cells with max(|i|, |j|) <= INTEGRATE get cell-integrated variance


def _cell_integral(fx0, fy0, side, r0, L0, l0, sub=24):
    """Variance and rms |f| of a square frequency cell centred at (fx0, fy0) with side ``side``."""
    t = (np.arange(sub) + 0.5) / sub - 0.5
    fx = fx0 + side * t[:, None]
    fy = fy0 + side * t[None, :]
    f = np.hypot(fx, fy)
    w = psd(f, r0, L0, l0) * (side / sub) ** 2
    var = float(w.sum())
    frms = math.sqrt(float((w * f * f).sum()) / var) if var > 0 else math.hypot(fx0, fy0)
    return var, frms


#: Amplitude tables kept, most recently used first out last, up to this many bytes in all: an
#: ensemble's planes each have their own spacing (17 in a spherical-wave ensemble), and a cache of
#: a fixed 4 tables, visited in turn, never hit (24 of 43 s of such an ensemble were this table).
AMPLITUDE_CACHE_BYTES = 256 * 2 ** 20
_amplitude_cache: OrderedDict = OrderedDict()
_amplitude_lock = threading.Lock()


def cached_array(cache: OrderedDict, lock, key):
    """The array kept under ``key`` in ``cache`` (marked most recently used), or None.

    Parameters
    ----------
    cache : OrderedDict
    lock : threading.Lock
    key : hashable

    Returns
    -------
    ndarray or None
    """
    with lock:
        if key in cache:
            cache.move_to_end(key)
            return cache[key]
    return None


def keep_array(cache: OrderedDict, lock, key, arr: np.ndarray, max_bytes: float) -> np.ndarray:
    """Keep ``arr`` (made read-only) under ``key``, dropping the least recently used arrays while
    the cache holds more than ``max_bytes`` (the newest always stays).

    Parameters
    ----------
    cache : OrderedDict
    lock : threading.Lock
    key : hashable
    arr : ndarray
    max_bytes : float
        bytes.

    Returns
    -------
    ndarray
        ``arr``.
    """
    arr.flags.writeable = False
    with lock:
        cache[key] = arr
        while len(cache) > 1 and sum(a.nbytes for a in cache.values()) > max_bytes:
            cache.popitem(last=False)
    return arr


def _spectrum_amplitudes(n, dx, r0, L0, l0):
    """:func:`_spectrum_table`, kept for the next screen of the same size, spacing and scales
    (read-only; least recently used dropped beyond :data:`AMPLITUDE_CACHE_BYTES`)."""
    key = (n, dx, r0, L0, l0)
    amp = cached_array(_amplitude_cache, _amplitude_lock, key)
    if amp is None:
        amp = keep_array(_amplitude_cache, _amplitude_lock, key, _spectrum_table(n, dx, r0, L0, l0),
                         AMPLITUDE_CACHE_BYTES)
    return amp


def _spectrum_table(n, dx, r0, L0, l0):
    """Amplitude a_c of each FFT cell (rad): aliased, near-DC cells integrated, the NEAR cells 0."""
    df = 1.0 / (n * dx)
    k = sfft.fftfreq(n, 1.0 / n)  # integer indices in FFT order
    fx = k[:, None] * df
    fy = k[None, :] * df
    f = np.hypot(fx, fy)
    # samples of a continuous field have the aliased spectrum: fold Phi(f + (m, q)/dx) into the grid.
    # The alias sum is smooth over the band, so it is evaluated on a coarse grid and interpolated.
    fs = 1.0 / dx
    with np.errstate(divide="ignore"):
        var = psd(f, r0, L0, l0)
    gc = np.linspace(-fs / 2, fs / 2, 129)
    GX, GY = np.meshgrid(gc, gc, indexing="ij")
    alias = np.zeros_like(GX)
    for m in range(-ALIAS, ALIAS + 1):
        for q in range(-ALIAS, ALIAS + 1):
            if m or q:
                alias += psd(np.hypot(GX + m * fs, GY + q * fs), r0, L0, l0)
    ix = (fx / fs + 0.5) * 128 + 0 * fy
    iy = (fy / fs + 0.5) * 128 + 0 * fx
    var += _scipy_ndimage.map_coordinates(alias, [ix.ravel(), iy.ravel()], order=1, mode="nearest").reshape(n, n)
    var *= df * df
    # the PSD is strongly convex near DC: integrate the main (unaliased) term over each cell out to
    # |k| <= INTEGRATE (its centre value is 1.4/k^2 too low; beyond, < 0.5 %)
    K = min(INTEGRATE, n // 2 - 1)
    idx = np.arange(-K, K + 1)
    sub = 8
    t = (np.arange(sub) + 0.5) / sub - 0.5
    cx = (idx[:, None, None, None] + t[None, None, :, None]) * df
    cy = (idx[None, :, None, None] + t[None, None, None, :]) * df
    with np.errstate(divide="ignore"):
        cell = psd(np.hypot(cx, cy), r0, L0, l0).mean(axis=(2, 3)) * df * df
        centre = psd(np.hypot(idx[:, None] * df, idx[None, :] * df), r0, L0, l0) * df * df
    ii, jj = np.meshgrid(idx % n, idx % n, indexing="ij")
    var[ii, jj] += np.where(np.isfinite(centre), cell - centre, 0.0)
    for i in range(-NEAR, NEAR + 1):  # near-DC cells become explicit sinusoids
        for j in range(-NEAR, NEAR + 1):
            var[i % n, j % n] = 0.0
    return np.sqrt(var)


def _near_dc_cells(n, dx, r0, L0, l0):
    """The FFT-grid cells within NEAR of DC as sinusoids at their power-weighted rms frequency."""
    df = 1.0 / (n * dx)
    fxs, fys, amps = [], [], []
    for i in range(-NEAR, NEAR + 1):
        for j in range(-NEAR, NEAR + 1):
            if i == 0 and j == 0:
                continue
            sp = SPLIT if max(abs(i), abs(j)) == 1 else 1  # the ring next to DC varies most
            side = df / sp
            for a in range(sp):
                for b in range(sp):
                    cx = i * df + (a - (sp - 1) / 2) * side
                    cy = j * df + (b - (sp - 1) / 2) * side
                    v, frms = _cell_integral(cx, cy, side, r0, L0, l0, sub=16)
                    d = math.hypot(cx, cy)
                    fxs.append(frms * cx / d)
                    fys.append(frms * cy / d)
                    amps.append(math.sqrt(v))
    return fxs, fys, amps


def _subharmonic_cells(n, dx, r0, L0, l0, levels):
    """Frequencies (fx, fy) and amplitudes of the subharmonic cells, all levels."""
    df = 1.0 / (n * dx)
    fxs, fys, amps = _near_dc_cells(n, dx, r0, L0, l0)
    for p in range(1, levels + 1):
        side = df / 3 ** p
        for i in (-1, 0, 1):
            for j in (-1, 0, 1):
                if i == 0 and j == 0:
                    continue
                v, frms = _cell_integral(i * side, j * side, side, r0, L0, l0)
                d = math.hypot(i, j)
                fxs.append(frms * i / d)
                fys.append(frms * j / d)
                amps.append(math.sqrt(v))
    return np.array(fxs), np.array(fys), np.array(amps)


def _residual_tilt_std(n, dx, r0, L0, l0, levels):
    """Std (rad/m) of the random tilt that stands in for the innermost, dropped frequency cell.

    Below |f| ~ rho the cos in D(r) = int Phi (2 - 2 cos(2 pi f.r)) is quadratic, so the cell adds
    4 pi^2 r^2 int Phi f_x^2 d^2f: the structure function of a random tilt. For Kolmogorov this is
    still ~2.6 % of D(N/4) after 8 levels (it converges only as rho^(1/3)).
    """
    side = 1.0 / (n * dx) / 3 ** levels
    rho = side / math.sqrt(math.pi)  # disk of the cell's area
    val = _scipy.integrate.quad(lambda f: psd(f, r0, L0, l0) * f ** 3, 0.0, rho, limit=200)[0]
    return math.sqrt(4 * math.pi ** 2 * math.pi * val)


@lru_cache(maxsize=256)
def _subharmonic_table(n, dx, L0, l0, levels):
    """:func:`_subharmonic_cells` at r0 = 1 m, computed once per size, spacing and scales."""
    return _subharmonic_cells(n, dx, 1.0, L0, l0, levels)


@lru_cache(maxsize=256)
def _tilt_table(n, dx, L0, l0, levels):
    """:func:`_residual_tilt_std` at r0 = 1 m, computed once per size, spacing and scales."""
    return _residual_tilt_std(n, dx, 1.0, L0, l0, levels)


def phase_screens(n: int, dx: float, r0: float, count: int = 1, seed: int | None = 0,
                  outer_scale: float | None = None, inner_scale: float | None = None,
                  levels: int = 4, dtype=np.float64, rng: np.random.Generator | None = None,
                  pad: float = 1.0) -> np.ndarray:
    """Generate ``count`` independent phase screens (rad), shape (count, n, n).

    Parameters
    ----------
    n : int
        Screen size, samples (any size >= 8).
    dx : float
        Sample spacing, m.
    r0 : float
        Fried parameter of the screen, m.
    count : int
        Number of screens.
    seed : int, optional
        Seed of the default generator (ignored when ``rng`` is given).
    outer_scale, inner_scale : float, optional
        von Karman outer scale L0 and inner scale l0, m (None: Kolmogorov).
    levels : int
        Subharmonic levels (0 disables the low-frequency compensation: subharmonics and the
        residual tilt).
    pad : float
        The FFT grid is ``pad`` times the screen (then cropped), for finer frequency cells. With the
        near-DC cells and the residual tilt modelled explicitly, pad = 1 keeps the structure
        function within ~1 % of theory from 2 pixels to N/4; pad = 2 costs 4x for ~0.5 %.
    dtype : numpy dtype
        float32 or float64 output.

    Returns
    -------
    ndarray (count, n, n)

    Examples
    --------
    >>> phi = phase_screens(256, 0.01, 0.05, count=4, seed=1)
    >>> phi.shape
    (4, 256, 256)
    """
    if not isinstance(n, (int, np.integer)) or n < 8:
        raise ScenarioError("n", n, "must be an integer >= 8")
    for name, v in (("dx", dx), ("r0", r0)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ScenarioError(name, v, "must be finite and > 0")
    if count < 1:
        raise ScenarioError("count", count, "must be >= 1")
    if outer_scale is not None and not outer_scale > 0:
        raise ScenarioError("outer_scale", outer_scale, "must be > 0")
    if inner_scale is not None and not inner_scale >= 0:
        raise ScenarioError("inner_scale", inner_scale, "must be >= 0")
    if outer_scale is not None and inner_scale is not None and not inner_scale < outer_scale:
        raise ScenarioError("inner_scale", inner_scale, f"must be below the outer scale {outer_scale} m")
    if rng is None and seed is not None and (not isinstance(seed, (int, np.integer)) or seed < 0):
        raise ScenarioError("seed", seed, "must be an integer >= 0")
    m = sfft.next_fast_len(max(int(math.ceil(pad * n)), n))
    need = float(count) * n * n * np.dtype(dtype).itemsize + 80.0 * m * m * max(1, min((count + 1) // 2, 2 ** 25 // (m * m)))
    check_memory(need, f"{count} phase screen(s) of {n} x {n}", "reduce --n or --count (screens can be made in "
                 "several files)")
    rng = rng if rng is not None else np.random.default_rng(seed)
    # the PSD is r0^(-5/3) times a shape: tables at r0 = 1 m (cached), amplitudes scaled by r0^(-5/6)
    scale = r0 ** (-5.0 / 6.0)
    amp = _spectrum_amplitudes(m, dx, 1.0, outer_scale, inner_scale) * scale
    sfx, sfy, samp = _subharmonic_table(m, dx, outer_scale, inner_scale, levels)
    samp = samp * scale
    tilt = _tilt_table(m, dx, outer_scale, inner_scale, levels) * scale if levels else 0.0
    x = np.arange(n) * dx
    xc = x - x.mean()
    ex = np.exp(2j * np.pi * np.outer(sfx, x)).astype(np.complex64)  # (C, n)
    ey = np.exp(2j * np.pi * np.outer(sfy, x)).astype(np.complex64)
    out = np.empty((count, n, n), dtype=dtype)
    pairs = (count + 1) // 2
    batch = max(1, min(pairs, int(2 ** 25 // (m * m))))
    done = 0
    single = np.dtype(dtype) == np.float32
    rdt = np.float32 if single else np.float64
    amp_r = amp.astype(rdt)
    for b0 in range(0, pairs, batch):
        nb = min(batch, pairs - b0)
        # the two draws as the real and imaginary parts, in place (the same numbers as a + 1j b,
        # without its two complex temporaries)
        z = np.empty((nb, m, m), np.complex64 if single else np.complex128)
        z.real = rng.standard_normal((nb, m, m), dtype=rdt)
        z.imag = rng.standard_normal((nb, m, m), dtype=rdt)
        z *= amp_r
        field = sfft.fft2(z, workers=FFT_WORKERS, overwrite_x=True)[:, :n, :n]
        if samp.size:
            zs = (rng.standard_normal((nb, samp.size)) + 1j * rng.standard_normal((nb, samp.size))) * samp
            # sum_c zs_c ex_c(x) ey_c(y): (n, C) @ (C, n) per screen pair, complex64 GEMM
            for k in range(nb):
                field[k] += (ex.T * zs[k].astype(np.complex64)) @ ey
        zt = (rng.standard_normal((nb, 2)) + 1j * rng.standard_normal((nb, 2))) * tilt
        for k in range(nb):
            # the residual tilt, a screen at a time (a batch's worth of temporaries cost as much as the draws)
            field[k] += zt[k, 0] * xc[:, None] + zt[k, 1] * xc[None, :]
            for part in (field[k].real, field[k].imag):
                if done < count:
                    out[done] = part
                    done += 1
    return out


@njit(parallel=True, cache=True)
def _sf_per_screen(s, L, per):
    """per[k, lag - 1] = mean over both axes of (phi(x + lag) - phi(x))^2 on screen k (no
    temporaries: the ensembles are hundreds of MB)."""
    K, n, m = s.shape
    for k in prange(K):
        for lag in range(1, L + 1):
            ax = 0.0
            for i in range(n - lag):
                for j in range(m):
                    d = s[k, i + lag, j] - s[k, i, j]
                    ax += d * d
            ay = 0.0
            for i in range(n):
                for j in range(m - lag):
                    d = s[k, i, j + lag] - s[k, i, j]
                    ay += d * d
            per[k, lag - 1] = 0.5 * (ax / ((n - lag) * m) + ay / (n * (m - lag)))


def structure_function_estimate(screens: np.ndarray, dx: float, max_lag: int | None = None):
    """Ensemble structure function over both axes, with its standard error.

    Parameters
    ----------
    screens : ndarray (K, n, n)
    dx : float
        Spacing, m.
    max_lag : int, optional
        Largest lag in samples (default n // 4).

    Returns
    -------
    r : ndarray (L,)
        Separations, m (lags 1..max_lag).
    d : ndarray (L,)
        Mean of <(phi(x + r) - phi(x))^2> over positions, both axes and screens, rad^2.
    err : ndarray (L,)
        Standard error of ``d`` from the spread of the per-screen estimates.
    """
    s = np.asarray(screens, dtype=np.float64)
    if s.ndim == 2:
        s = s[None]
    K, n, _ = s.shape
    L = max_lag or n // 4
    per = np.empty((K, L))
    _sf_per_screen(s, L, per)
    d = per.mean(axis=0)
    err = per.std(axis=0, ddof=1) / math.sqrt(K) if K > 1 else np.full(L, np.nan)
    return np.arange(1, L + 1) * dx, d, err
