"""Range compression of dechirped data: analytic signal, RVP removal and deskew.

A dechirped sample at fast time t (after the reference delay) of a scatterer with differential
delay dtau is exp(-j 2 pi (f0 + k t) dtau + j pi k dtau^2). Multiplying its spectrum by
exp(-j pi f^2 / k) removes the residual video phase pi k dtau^2 and shifts each echo's envelope by
its own delay (deskew). What remains is the frequency-domain phase history

    P(f) = exp(-j 4 pi f (R - R_ref) / c),  f = f0 + k t,

which every image-formation algorithm in salkit consumes.
"""
from __future__ import annotations

import numpy as np
import scipy.fft as sfft
import xarray as xr

from ..constants import FFT_WORKERS, SPEED_OF_LIGHT
from ..errors import DataFileError
from ..errors import ScenarioError

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


def range_compress(raw: xr.Dataset, chirp_correction: str = "none") -> xr.Dataset:
    """Turn a raw (dechirped) dataset into a frequency-domain phase history.

    Parameters
    ----------
    raw : xarray.Dataset
        ``salkit_kind`` "raw" (fast time) or "phase_history" (returned unchanged).
    chirp_correction : {"none", "resample", "deskew"}
        Nonlinear-chirp correction from the file's ``reference_signal`` (see
        :mod:`salkit.focus.chirpcorr`).

    Returns
    -------
    xarray.Dataset
        ``signal`` with dims (slow_time, frequency), ``frequency`` in Hz (absolute optical), the RVP
        removed, and the per-pulse geometry of ``raw``.
    """
    kind = raw.attrs.get("salkit_kind")
    if kind == "phase_history":
        return raw
    if kind != "raw":
        raise DataFileError(f"range_compress needs a raw or phase_history dataset, got kind {kind!r}")
    sig = np.asarray(raw["signal"].values, dtype=np.complex64)
    fs = float(raw.attrs["adc_rate"])
    k = float(raw.attrs["chirp_rate"])
    f0 = SPEED_OF_LIGHT / float(raw.attrs["wavelength"])
    if not int(raw.attrs.get("iq", 1)):
        sig = analytic(sig, str(raw.attrs.get("real_sideband", "negative")))
    t = raw["fast_time"].values
    if chirp_correction != "none":
        from .chirpcorr import correct_deskew, correct_resample, estimate_nonlinear_phase
        if "reference_signal" not in raw:
            raise ScenarioError("processing.chirp_correction", chirp_correction,
                                "needs a reference channel in the raw data (receiver.reference_channel)")
        e = estimate_nonlinear_phase(raw["reference_signal"].values, t, f0, k, float(raw.attrs["reference_delay"]))
        if chirp_correction == "resample":
            ph = deskew(correct_resample(sig, e, t, k), fs, k)
        else:
            ph = correct_deskew(sig, e, fs, k)
    else:
        ph = deskew(sig, fs, k)
    freq = f0 + k * t
    out = raw.drop_vars([v for v in ("signal", "fast_time", "reference_signal") if v in raw.variables]).assign(
        signal=(("slow_time", "frequency"), ph, {"long_name": "phase history, RVP removed"}))
    out = out.assign_coords(frequency=("frequency", freq, {"units": "Hz"}))
    out.attrs = dict(raw.attrs)
    out.attrs["salkit_kind"] = "phase_history"
    out.attrs["rvp_removed"] = 1
    return out
