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
import xarray as xr

from ..constants import SPEED_OF_LIGHT
from ..errors import DataFileError
from ..errors import ScenarioError
from ..io.reading import require_dataset
from .chirpcorr import correct_deskew, correct_resample, estimate_nonlinear_phase, remove_reference_noise
from .dechirp import analytic, deskew



def range_compress(raw: xr.Dataset, chirp_correction: str = "none",
                   phase_noise_correction: str = "none") -> xr.Dataset:
    """Turn a raw (dechirped) dataset into a frequency-domain phase history.

    Parameters
    ----------
    raw : xarray.Dataset
        ``salkit_kind`` "raw" (fast time) or "phase_history" (returned unchanged).
    chirp_correction : {"none", "resample", "deskew"}
        Nonlinear-chirp correction from the file's ``reference_signal`` (see
        :mod:`salkit.focus.chirpcorr`).
    phase_noise_correction : {"none", "reference"}
        ``reference``: remove the laser phase noise the reference channel recorded for each pulse
        (:func:`salkit.focus.chirpcorr.remove_reference_noise`; the file's ``reference_signal`` then
        has a beat a pulse). The chirp correction then reads the pulses' mean beat (over the
        pulses of ``raw``: with pulse blocks, of each block).

    Returns
    -------
    xarray.Dataset
        ``signal`` with dims (slow_time, frequency), ``frequency`` in Hz (absolute optical), the RVP
        removed, and the per-pulse geometry of ``raw``.
    """
    require_dataset(raw, "range_compress")
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
    ref = None
    if phase_noise_correction not in ("none", "reference"):
        raise ScenarioError("processing.phase_noise_correction", phase_noise_correction, "must be none or reference")
    if phase_noise_correction == "reference":
        if "reference_signal" not in raw or "slow_time" not in raw["reference_signal"].dims:
            raise ScenarioError("processing.phase_noise_correction", "reference",
                                "needs a reference channel that recorded each pulse (receiver.reference_channel "
                                "with waveform.linewidth > 0: reference_signal (slow_time, fast_time))")
        sig, ref = remove_reference_noise(sig, raw["reference_signal"].values, t, f0, k,
                                          float(raw.attrs["reference_delay"]))
    if chirp_correction != "none":
        if "reference_signal" not in raw:
            raise ScenarioError("processing.chirp_correction", chirp_correction,
                                "needs a reference channel in the raw data (receiver.reference_channel)")
        if ref is None:
            ref = raw["reference_signal"].values
            if ref.ndim == 2:  # a beat a pulse: the pulses' mean phase carries the chirp
                ref = np.exp(1j * np.angle(np.mean(ref, axis=0)))
        e = estimate_nonlinear_phase(ref, t, f0, k, float(raw.attrs["reference_delay"]))
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
