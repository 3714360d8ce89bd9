"""Operations on dechirped samples: the residual video phase removal and deskew, and the analytic
signal of real samples.

A dechirped sample at fast time t (after the reference delay) of a scatterer with differential
delay dtau is exp(-j 2 pi (f0 + k t) dtau + j pi k dtau^2). Multiplying its spectrum by
exp(-j pi f^2 / k) removes the residual video phase pi k dtau^2 and shifts each echo's envelope by
its own delay (deskew).
"""
from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from ..constants import FFT_WORKERS

WORKERS = FFT_WORKERS


#: Bytes of the 2N-point buffers of one pass of :func:`deskew` (its pulses go through in passes).
DESKEW_BYTES = 16 * 2 ** 20


def deskew(signal: np.ndarray, adc_rate: float, chirp_rate: float) -> np.ndarray:
    """RVP removal and deskew of dechirped samples (P, N), fast time centred at index N//2, a pass
    of pulses at a time (:data:`DESKEW_BYTES` of buffers).

    Parameters
    ----------
    signal : complex (P, N)
    adc_rate : float
        Hz.
    chirp_rate : float
        Hz/s.

    Returns
    -------
    complex64 (P, N)
    """
    P, N = signal.shape
    n2 = sfft.next_fast_len(2 * N)
    # place sample i (time (i - N//2)/fs) at index (i - N//2) mod n2
    idx = (np.arange(N) - N // 2) % n2
    f = sfft.fftfreq(n2, 1.0 / adc_rate)
    ramp = np.exp(-1j * np.pi * f ** 2 / chirp_rate).astype(np.complex64)
    out = np.empty((P, N), np.complex64)
    rows = max(1, int(DESKEW_BYTES // (8 * n2)))  # pulses a pass: the 2N-point buffers stay small
    for a in range(0, P, rows):
        b = min(P, a + rows)
        buf = np.zeros((b - a, n2), np.complex64)
        buf[:, idx] = signal[a:b]
        spec = sfft.fft(buf, axis=1, workers=WORKERS)
        spec *= ramp
        out[a:b] = sfft.ifft(spec, axis=1, workers=WORKERS)[:, idx]
    return out


def analytic(signal: np.ndarray, sideband: str = "negative") -> np.ndarray:
    """Complex signal from real dechirped samples, keeping the half-spectrum of the echoes.

    The beat frequency is -k * dtau: a scene beyond the reference range (dtau > 0) beats at
    negative frequencies (``sideband="negative"``), one nearer than the reference at positive.
    A real signal's spectrum is symmetric, so this choice comes from the geometry, not the data.

    Parameters
    ----------
    signal : (P, N)
        Real samples (complex dtype allowed).
    sideband : {"negative", "positive"}

    Returns
    -------
    complex64 (P, N)
    """
    spec = sfft.fft(signal.real, axis=1, workers=WORKERS)
    N = signal.shape[1]
    f = sfft.fftfreq(N)
    keep = (f < 0) if sideband == "negative" else (f > 0)
    spec = spec * (2.0 * keep)
    return sfft.ifft(spec, axis=1, workers=WORKERS).astype(np.complex64)
