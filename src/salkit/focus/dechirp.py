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


def deskew(signal: np.ndarray, adc_rate: float, chirp_rate: float) -> np.ndarray:
    """RVP removal and deskew of dechirped samples (P, N), fast time centred at index N//2.

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
    buf = np.zeros((P, n2), np.complex64)
    # place sample i (time (i - N//2)/fs) at index (i - N//2) mod n2
    idx = (np.arange(N) - N // 2) % n2
    buf[:, idx] = signal
    spec = sfft.fft(buf, axis=1, workers=WORKERS)
    f = sfft.fftfreq(n2, 1.0 / adc_rate)
    spec *= np.exp(-1j * np.pi * f ** 2 / chirp_rate).astype(np.complex64)
    out = sfft.ifft(spec, axis=1, workers=WORKERS)
    return out[:, idx].astype(np.complex64)


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
