"""The ``sal`` simulator: the dechirped raw phase history of a :class:`~salkit.params.Scenario`."""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..atmosphere.beam import two_way_gains
from ..geometry.collection import build_collection
from ..geometry.sampling import check_sampling, delay_spread, n_fast_samples, resolution_theory
from ..io.datasets import make_raw_dataset
from ..params.models import Scenario
from ..resources import check_memory
from ..signals.chirp import reference_beat
from .echoes import ProgressFn, echo_signal, fast_time_axis, memory_estimate, photon_noise, signal_scale
from .scene import build_scatterers
from .turbulent import turbulent_path, wave_optics_plan


def simulate_sal(scenario: Scenario, progress: ProgressFn = None, noise: bool | None = None,
                 rng: np.random.Generator | None = None) -> xr.Dataset:
    """Simulate the dechirped raw phase history of a SAL scenario (the ``sal`` simulator).

    Parameters
    ----------
    scenario : Scenario
    progress : callable, optional
        ``progress(done, total)`` in pulses.
    noise : bool, optional
        Override ``scenario.receiver.noise.enabled``.
    rng : numpy.random.Generator, optional
        Default: seeded from ``scenario.seed`` (scene speckle first, then noise).

    Returns
    -------
    xarray.Dataset
        Raw data in the format of ``docs/data-format.md``: complex64 ``signal`` (pulse, sample).
    """
    need, what = memory_estimate(scenario)
    check_memory(need, what, "reduce receiver.adc_rate, the aperture (platform.aperture_length, prf) or the "
                 "scene's scatterer count")
    col = build_collection(scenario)
    check_sampling(scenario, col)
    rng = rng if rng is not None else np.random.default_rng(scenario.seed)
    n = n_fast_samples(scenario, col)
    t = fast_time_axis(n, scenario.receiver.adc_rate)
    res = resolution_theory(scenario, col)
    look = -col.center_position / np.linalg.norm(col.center_position)
    cos_graze = math.sqrt(max(1.0 - look[2] ** 2, 1e-12))
    cell = res["azimuth"] * res["slant_range"] / cos_graze  # ground area of a resolution cell
    k = 4 * math.pi / scenario.waveform.wavelength
    pc = col.center_position
    if scenario.platform.mode == "spotlight":  # the image phase model of salkit.focus
        def smooth_phase(x):
            return k * (np.linalg.norm(x - pc, axis=1) - np.linalg.norm(pc))
    else:
        a = col.track
        rs = np.linalg.norm(-pc - np.dot(-pc, a) * a)

        def smooth_phase(x):
            rel = x - pc
            return k * (np.linalg.norm(rel - np.outer(rel @ a, a), axis=1) - rs)
    spos, samp = build_scatterers(scenario, cell, rng, smooth_phase)
    scale = signal_scale(scenario, col, n)
    path = turbulent_path(scenario, col) if scenario.atmosphere is not None else None
    gains = None
    if path is not None and scenario.atmosphere.model == "wave_optics":
        plan, region = wave_optics_plan(scenario, col)
        check_memory(col.n_pulses * len(spos) * 16.0 + 3 * plan.n ** 2 * 8.0,
                     f"wave-optics gains of {len(spos)} scatterers x {col.n_pulses} pulses",
                     "use fewer scatterers or pulses")
        gains, _ = two_way_gains(path, col.positions, spos, scenario.platform.real_aperture, region,
                                 sampling=plan, progress=progress)
        path = None
    sig = echo_signal(col, spos, samp * scale, scenario, t, progress=None if gains is not None else progress,
                      path=path, gains=gains)
    if scenario.platform.phase_error is not None:
        err = scenario.platform.phase_error.values(col.n_pulses)
        sig *= np.exp(1j * err).astype(np.complex64)[:, None]
    use_noise = scenario.receiver.noise.enabled if noise is None else noise
    if use_noise:
        photon_noise(sig, scenario.receiver.noise, rng)
    if not scenario.receiver.iq:
        sig = sig.real.astype(np.complex64)
    units = "shot_noise" if scenario.receiver.noise.enabled else "reflectivity"
    ds = make_raw_dataset(sig, col, t, scenario, signal_units=units, noise=use_noise)
    refc = scenario.receiver.reference_channel
    if refc is not None:
        w = scenario.waveform
        ref = reference_beat(t, w.carrier_frequency, w.rate, w.nonlinearity, refc.delay)
        sd = 10 ** (-refc.snr_db / 20) / math.sqrt(2)
        ref = ref + sd * (rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size))
        ds["reference_signal"] = (("fast_time",), ref.astype(np.complex64),
                                  {"long_name": "dechirped reference-channel beat"})
        ds.attrs["reference_delay"] = refc.delay
    if not scenario.receiver.iq:
        d0, d1 = delay_spread(scenario, col)
        ds.attrs["real_sideband"] = "negative" if d0 >= 0 else "positive"
    return ds
