"""The ``sal`` simulator: the dechirped raw phase history of a :class:`~salkit.params.Scenario`."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import xarray as xr

from ..atmosphere.beam import two_way_gains
from ..geometry.collection import build_collection
from ..geometry.sampling import check_sampling, delay_spread, n_fast_samples, resolution_theory
from ..errors import ResourceError, ScenarioError
from ..io.datasets import make_raw_dataset
from ..io.writing import ChunkedFileWriter
from ..params.models import Scenario
from ..resources import available_memory, check_memory, size_text
from ..signals.chirp import reference_beat
from .echoes import (ProgressFn, echo_signal, fast_time_axis, memory_estimate, photon_noise, signal_scale,
                     signal_shape)
from .linewidth import lo_shift, phase_noise
from .scene import build_scatterers
from .targets import LOOK_TURN_DEG, look_turn_deg
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
    rng = rng if rng is not None else np.random.default_rng(scenario.seed)
    job = _Echoes(scenario, rng, progress)
    sig = job.block(0, job.col.n_pulses, noise)
    use_noise = scenario.receiver.noise.enabled if noise is None else noise
    units = "shot_noise" if scenario.receiver.noise.enabled else "reflectivity"
    ds = make_raw_dataset(sig, job.col, job.t, scenario, signal_units=units, noise=use_noise)
    for name, (dims, values, attrs) in job.extras().items():
        ds[name] = (dims, values, attrs)
    ds.attrs.update(job.extra_attrs())
    return ds


class _Echoes:
    """A simulation's set-up (collection, scatterers, turbulent path or gains, scale) and its echoes
    for any run of pulses, the random numbers drawn in the same order whether the pulses come at
    once or in blocks of whole noise chunks (multiples of :data:`NOISE_BLOCK`)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator, progress: ProgressFn = None):
        self.sc, self.rng, self.progress = scenario, rng, progress
        col = self.col = build_collection(scenario)
        check_sampling(scenario, col)
        n = n_fast_samples(scenario, col)
        self.t = fast_time_axis(n, scenario.receiver.adc_rate)
        self.delays = delay_spread(scenario, col)
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
        if scenario.scene.objects and look_turn_deg(col.positions, np.zeros(3)) > LOOK_TURN_DEG:
            raise ScenarioError("scene.objects", f"{len(scenario.scene.objects)} objects",
                                f"the look direction turns {look_turn_deg(col.positions, np.zeros(3)):.3g} deg over the "
                                f"aperture, more than the {LOOK_TURN_DEG:g} deg one occlusion holds for: simulate "
                                "sub-apertures apart")
        spacing = min(res["azimuth"], res["slant_range"]) / 2.0  # SAMPLES_PER_CELL = 4 samples a cell, any tilt
        self.spos, samp = build_scatterers(scenario, cell, rng, smooth_phase, sensor=col.center_position,
                                           spacing=spacing)
        self.amp = samp * signal_scale(scenario, col, n)
        self.path = turbulent_path(scenario, col) if scenario.atmosphere is not None else None
        self.gains = None
        if self.path is not None and scenario.atmosphere.model == "wave_optics":
            plan, region = wave_optics_plan(scenario, col)
            check_memory(col.n_pulses * len(self.spos) * 16.0 + 3 * plan.n ** 2 * 8.0,
                         f"wave-optics gains of {len(self.spos)} scatterers x {col.n_pulses} pulses",
                         "use fewer scatterers or pulses")
            self.gains, _ = two_way_gains(self.path, col.positions, self.spos, scenario.platform.real_aperture,
                                          region, sampling=plan, progress=progress)
            self.path = None
        pe = scenario.platform.phase_error
        self.phase_error = None if pe is None else np.exp(1j * pe.values(col.n_pulses)).astype(np.complex64)

    def block(self, a: int, b: int, noise: bool | None = None) -> np.ndarray:
        """Echoes of pulses ``a`` to ``b`` with their noise, complex64 (b - a, N)."""
        sc, col = self.sc, self.col
        sub = dataclasses.replace(col, slow_time=col.slow_time[a:b], positions=col.positions[a:b],
                                  velocity=col.velocity[a:b], reference_range=col.reference_range[a:b],
                                  boresight=col.boresight[a:b]) if (a, b) != (0, col.n_pulses) else col
        tick = None
        if self.progress is not None and self.gains is None:
            tick = (lambda d, n: self.progress(a + d, col.n_pulses))
        noise_tab = None
        if sc.waveform.linewidth > 0:  # the laser's phase noise, each pulse from its own stream
            noise_tab = phase_noise(sc.waveform.linewidth, self.t, self.delays,
                                    lo_shift(sub.reference_range, sc.receiver.lo_delay), sc.seed, np.arange(a, b))
        sig = echo_signal(sub, self.spos, self.amp, sc, self.t, progress=tick, path=self.path,
                          gains=None if self.gains is None else self.gains[a:b], phase_noise=noise_tab)
        if self.phase_error is not None:
            sig *= self.phase_error[a:b, None]
        if (sc.receiver.noise.enabled if noise is None else noise):
            photon_noise(sig, sc.receiver.noise, self.rng)
        if not sc.receiver.iq:
            sig = sig.real.astype(np.complex64)
        return sig

    def extras(self) -> dict:
        """Variables drawn after every pulse (the reference channel's beat and its noise)."""
        refc = self.sc.receiver.reference_channel
        if refc is None:
            return {}
        w, t = self.sc.waveform, self.t
        ref = reference_beat(t, w.carrier_frequency, w.rate, w.nonlinearity, refc.delay)
        sd = 10 ** (-refc.snr_db / 20) / math.sqrt(2)
        ref = ref + sd * (self.rng.standard_normal(t.size) + 1j * self.rng.standard_normal(t.size))
        return {"reference_signal": (("fast_time",), ref.astype(np.complex64),
                                     {"long_name": "dechirped reference-channel beat"})}

    def extra_attrs(self) -> dict:
        """Attributes known once the set-up is: the reference delay, the real sideband."""
        out = {}
        if self.sc.receiver.reference_channel is not None:
            out["reference_delay"] = self.sc.receiver.reference_channel.delay
        if not self.sc.receiver.iq:
            d0, d1 = delay_spread(self.sc, self.col)
            out["real_sideband"] = "negative" if d0 >= 0 else "positive"
        return out


#: Pulses of one draw of :func:`salkit.simulate.echoes.photon_noise` (512 Gaussian, 256 Poisson):
#: blocks of a multiple of it draw the same numbers as the whole signal at once.
NOISE_BLOCK = 512


def simulate_to_file(scenario: Scenario, path, memory_limit: float | None = None, progress: ProgressFn = None):
    """Simulate the raw data of a SAL scenario straight into a NetCDF file, a block of pulses at a
    time, for histories larger than memory: the same numbers as :func:`simulate_sal` (the random
    numbers are drawn in the same order), written as a chunked file (chunks of about 8 MiB of
    pulses; :class:`salkit.io.ChunkedFileWriter`, complete or absent).

    Parameters
    ----------
    scenario : Scenario
    path : path
        The raw file to write.
    memory_limit : float, optional
        Bytes for the signal of one block (default: an eighth of the memory available).
    progress : callable, optional
        ``progress(done, total)`` in pulses.

    Returns
    -------
    Path

    Raises
    ------
    ResourceError
        When one block (512 pulses with noise, one without), or the scene, does not fit.
    """
    rng = np.random.default_rng(scenario.seed)
    budget = float(memory_limit) if memory_limit is not None else available_memory() / 8.0
    P, N = signal_shape(scenario)
    per_pulse = 3 * 8.0 * N  # the block, its float32 parts in the kernels, the noise draw
    unit = NOISE_BLOCK if scenario.receiver.noise.enabled else 1  # without noise no draw to keep in step
    blk = P if per_pulse * P <= budget else int(budget // (per_pulse * unit)) * unit
    if blk < min(unit, P):
        raise ResourceError(f"simulating {P} pulses x {N} samples in blocks: one block of {min(unit, P)} pulses "
                            f"needs about {size_text(per_pulse * min(unit, P))}, more than the {size_text(budget)} "
                            "available (the budget); raise --memory-limit or reduce receiver.adc_rate")
    job = _Echoes(scenario, rng, progress)
    col = job.col
    units = "shot_noise" if scenario.receiver.noise.enabled else "reflectivity"
    blank = np.broadcast_to(np.complex64(0), (col.n_pulses, job.t.size))
    skel = make_raw_dataset(blank, col, job.t, scenario, signal_units=units,
                            noise=scenario.receiver.noise.enabled).drop_vars("signal")
    rows = max(1, min(blk, (8 * 2 ** 20) // (8 * job.t.size)))  # chunks of about 8 MiB: a block reads only itself
    with ChunkedFileWriter(path, skel, "signal", ("slow_time", "fast_time"), (rows, job.t.size),
                           {"long_name": "dechirped I/Q signal", "units": units}) as w:
        for a in range(0, col.n_pulses, blk):
            b = min(col.n_pulses, a + blk)
            w.write(a, 0, job.block(a, b))
        for name, (dims, values, attrs) in job.extras().items():
            w.add(name, dims, values, attrs)
        return w.close(job.extra_attrs())
