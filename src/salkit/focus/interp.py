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
    """Tabulated Kaiser-windowed sinc of half-width ``half`` samples."""
    key = (half, beta)
    if key not in _TABLES:
        _TABLES[key] = _kernel_table(half, beta)
    return _TABLES[key]


@njit(parallel=True, cache=True, fastmath=True)
def interp_rows(data, pos, half, table, out):
    """out[r, j] = sum_i data[r, i] * h(pos[r, j] - i), h the tabulated windowed sinc.

    ``pos`` holds fractional input indices; positions outside the data give 0.
    """
    R = data.shape[0]
    N = data.shape[1]
    J = pos.shape[1]
    os = 2048
    centre = half * os
    for r in prange(R):
        for j in range(J):
            x = pos[r, j]
            if x < -0.5 or x > N - 0.5 or not (x == x):
                out[r, j] = 0.0
                continue
            i0 = int(math.floor(x))
            acc_re = 0.0
            acc_im = 0.0
            for i in range(i0 - half + 1, i0 + half + 1):
                if i < 0 or i >= N:
                    continue
                t = (x - i) * os
                it = int(t + centre + 0.5)
                if it < 0 or it >= table.shape[0]:
                    continue
                h = table[it]
                v = data[r, i]
                acc_re += h * v.real
                acc_im += h * v.imag
            out[r, j] = complex(acc_re, acc_im)


def resample_rows(data: np.ndarray, pos: np.ndarray, half: int = 4, beta: float = 6.0) -> np.ndarray:
    """Resample each row of ``data`` (R, N) at fractional indices ``pos`` (R, J), complex64 out."""
    out = np.empty(pos.shape, np.complex64)
    interp_rows(np.ascontiguousarray(data, dtype=np.complex64), np.ascontiguousarray(pos, dtype=np.float64),
                half, kernel_table(half, beta), out)
    return out
