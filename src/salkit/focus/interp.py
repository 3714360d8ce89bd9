"""Kaiser-windowed sinc interpolation of uniformly sampled complex signals (numba)."""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

_OVERSAMPLE = 2048


def _kernel_table(half: int, beta: float) -> np.ndarray:
    x = np.arange(-half * _OVERSAMPLE, half * _OVERSAMPLE + 1) / _OVERSAMPLE
    return (np.sinc(x) * np.kaiser(x.size, beta)).astype(np.float32)


_TABLES: dict = {}


def kernel_table(half: int = 4, beta: float = 6.0) -> np.ndarray:
    """Tabulated Kaiser-windowed sinc of half-width ``half`` samples.

    Parameters
    ----------
    half : int
        Half-width, samples.
    beta : float
        Kaiser shape.

    Returns
    -------
    float32 ndarray
        Kernel values on a fine grid (cached).
    """
    key = (half, beta)
    if key not in _TABLES:
        _TABLES[key] = _kernel_table(half, beta)
    return _TABLES[key]


@njit(cache=True, fastmath=True, inline="always")
def _interp_one(row, x, half, table):
    N = row.shape[0]
    os = 2048
    T = 2 * half
    if not (x >= -0.5 and x <= N - 0.5):
        return complex(0.0, 0.0)
    i0 = int(math.floor(x))
    f = x - i0
    base = i0 - half + 1
    acc_re = np.float32(0.0)
    acc_im = np.float32(0.0)
    if base >= 0 and base + T <= N:
        for t in range(T):
            h = table[int((f + (half - 1 - t)) * os + half * os + 0.5)]
            v = row[base + t]
            acc_re += h * v.real
            acc_im += h * v.imag
    else:
        for t in range(T):
            i = base + t
            if i < 0 or i >= N:
                continue
            it = int((f + (half - 1 - t)) * os + half * os + 0.5)
            if it < 0 or it >= table.shape[0]:
                continue
            h = table[it]
            v = row[i]
            acc_re += h * v.real
            acc_im += h * v.imag
    return complex(acc_re, acc_im)


@njit(parallel=True, cache=True, fastmath=True, boundscheck=False)
def interp_rows(data, pos, half, table, out):
    """out[r, j] = sum_i data[r, i] * h(pos[r, j] - i), h the tabulated windowed sinc.

    ``pos`` holds fractional input indices; positions outside [-0.5, N - 0.5] give 0. Interior
    outputs take a branch-free path over 2*half contiguous taps.

    Parameters
    ----------
    data : complex64 (R, N)
    pos : float64 (R, J)
        Fractional input indices.
    half : int
    table : float32 ndarray
        :func:`kernel_table`.
    out : complex64 (R, J)
        Filled in place.
    """
    for r in prange(data.shape[0]):
        row = data[r]
        for j in range(pos.shape[1]):
            out[r, j] = _interp_one(row, pos[r, j], half, table)


@njit(parallel=True, cache=True, fastmath=True, boundscheck=False)
def interp_rows_linear(data, x0, step, half, table, out):
    """Like :func:`interp_rows` with positions x0[r] + j * step[r] (no position array).

    Parameters
    ----------
    data : complex64 (R, N)
    x0, step : float64 (R,)
        First position and step of each row, input samples.
    half : int
    table : float32 ndarray
    out : complex64 (R, J)
        Filled in place.
    """
    for r in prange(data.shape[0]):
        row = data[r]
        for j in range(out.shape[1]):
            out[r, j] = _interp_one(row, x0[r] + j * step[r], half, table)


def resample_rows(data: np.ndarray, pos: np.ndarray, half: int = 4, beta: float = 6.0) -> np.ndarray:
    """Resample each row of ``data`` (R, N) at fractional indices ``pos`` (R, J), complex64 out.

    Parameters
    ----------
    data : complex (R, N)
    pos : float64 (R, J)
        Fractional input indices.
    half : int
        Kernel half-width, samples.
    beta : float
        Kaiser shape.

    Returns
    -------
    complex64 (R, J)
    """
    out = np.empty(pos.shape, np.complex64)
    interp_rows(np.ascontiguousarray(data, dtype=np.complex64), np.ascontiguousarray(pos, dtype=np.float64),
                half, kernel_table(half, beta), out)
    return out


@njit(parallel=True, cache=True, fastmath=True, boundscheck=False)
def azimuth_pass(d1t, ts, kx, ky, v_a, v_r, half, table, buf, ia, ir):
    """PFA azimuth interpolation fused with windowing and placement into the FFT buffer.

    For K-space row j (ky[j]) and column i, the needed sample sits at t = kx[i] / ky[j] on the
    pulses' monotonic (increasing) ``ts`` = tan(look) sequence; its fractional pulse index is found
    by bisection and linear interpolation, then ``d1t[j]`` (pulses along the row) is sinc-
    interpolated there. buf[ia[i], ir[j]] = value * v_a[i] * v_r[j]. As in range, each pulse is a
    sample of its interval: the support reaches half an interval beyond the first and last pulse
    (P pulses span P intervals, the aperture of direct backprojection and of lambda R / 2L).

    Parameters
    ----------
    d1t : complex64 (Ny, P)
        Range-interpolated data, transposed.
    ts : float64 (P,)
        tan of each pulse's look angle, increasing.
    kx, ky : float64
        K-space axes, rad/m.
    v_a, v_r : float32
        Windows over the K-space columns and rows.
    half : int
    table : float32 ndarray
    buf : complex64 2-D
        FFT buffer, filled in place.
    ia, ir : int64
        Buffer indices of the columns and rows.
    """
    nky = ky.shape[0]
    nkx = kx.shape[0]
    P = ts.shape[0]
    os = 2048
    T = 2 * half
    scale = (P - 1) / (ts[P - 1] - ts[0])
    # each pulse stands for its own interval: the support runs half an interval past the end pulses
    t_lo = ts[0] - 0.5 * (ts[1] - ts[0])
    t_hi = ts[P - 1] + 0.5 * (ts[P - 1] - ts[P - 2])
    for j in prange(nky):
        row = d1t[j]
        kyj = ky[j]
        vr = v_r[j]
        for i in range(nkx):
            t = kx[i] / kyj
            if not (t >= t_lo and t <= t_hi):
                continue
            # ts is nearly linear in the pulse index: guess, then walk to the bracketing pair
            lo = int((t - ts[0]) * scale)
            if lo > P - 2:
                lo = P - 2
            if lo < 0:
                lo = 0
            while lo > 0 and ts[lo] > t:
                lo -= 1
            while lo < P - 2 and ts[lo + 1] < t:
                lo += 1
            x = lo + (t - ts[lo]) / (ts[lo + 1] - ts[lo])
            i0 = int(math.floor(x))
            f = x - i0
            base = i0 - half + 1
            acc_re = np.float32(0.0)
            acc_im = np.float32(0.0)
            for tt in range(T):
                n = base + tt
                if n < 0 or n >= P:
                    continue
                h = table[int((f + (half - 1 - tt)) * os + half * os + 0.5)]
                v = row[n]
                acc_re += h * v.real
                acc_im += h * v.imag
            buf[ia[i], ir[j]] = complex(acc_re, acc_im) * v_a[i] * vr
