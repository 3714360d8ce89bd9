"""The ``sal`` simulator: the dechirped raw phase history of a :class:`~salkit.params.Scenario`."""
from __future__ import annotations

import dataclasses
import math
from collections import deque
from itertools import islice

import numpy as np
import xarray as xr

from ..atmosphere.beam import two_way_gains
from ..geometry.collection import build_collection
from ..geometry.sampling import check_sampling, delay_spread, n_fast_samples, resolution_theory
from ..errors import ResourceError, ScenarioError
from ..io.datasets import make_raw_dataset
from ..io.writing import ChunkedFileWriter
from ..params.models import Scenario
from ..resources import available_memory, check_memory, size_text, task_numba_threads
from ..signals.chirp import reference_beat
from .echoes import (ProgressFn, echo_signal, fast_time_axis, memory_estimate, photon_noise, scene_memory,
                     signal_scale, signal_shape)
from .linewidth import lo_shift, phase_noise, substeps
from .scene import build_scatterers
from .views import LOOK_TURN_DEG, ObjectScene, look_segments, object_frame
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
    once or in blocks of whole noise chunks (multiples of :data:`NOISE_BLOCK`). ``echoes=False``
    sets up what the receiver's noise and the file need (the scene's draws, the collection), not
    the turbulence: the echoes are then computed elsewhere (:meth:`clean` on Dask workers)."""

    def __init__(self, scenario: Scenario, rng: np.random.Generator, progress: ProgressFn = None,
                 echoes: bool = True):
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
        objs = scenario.scene.objects
        wave_optics = scenario.atmosphere is not None and scenario.atmosphere.model == "wave_optics"
        if scenario.atmosphere is not None and any(o.spinning for o in objs):
            raise ScenarioError("scene.objects.attitude_rate_deg_s", [list(o.attitude_rate_deg_s) for o in objs],
                                "a spinning object through turbulence is not modelled (the screens' path phases "
                                "follow fixed scatterers): drop the atmosphere or the spin")
        scale = signal_scale(scenario, col, n)
        spos, samp = build_scatterers(scenario, cell, rng, smooth_phase)
        #: runs of pulses seen from one look, and for each its scatterer groups: (the spinning object whose
        #: frame they are in, or None; positions (S, 3) m; amplitudes (S,))
        self.looks, self.groups = [(0, col.n_pulses)], [[(None, spos, samp * scale)]]
        if objs:
            spacing = min(res["azimuth"], res["slant_range"]) / 2.0  # SAMPLES_PER_CELL = 4 samples a cell, any tilt
            scene = ObjectScene(objs, cell, spacing, scenario.waveform.wavelength, rng, smooth_phase)
            self.looks = look_segments(col.positions, col.slow_time, objs)
            if wave_optics and len(self.looks) > 1:
                raise ScenarioError("scene.objects", f"{len(objs)} objects",
                                    f"the look turns by more than {LOOK_TURN_DEG:g} deg over the aperture "
                                    f"({len(self.looks)} looks) and wave-optics gains hold one scatterer set: "
                                    "simulate sub-apertures apart")
            spinning = np.isin(scene.owner, [k for k, o in enumerate(objs) if o.spinning])
            self.groups = []
            for a, b in self.looks:
                m = (a + b - 1) // 2  # seen from the run's middle pulse
                amp = scene.amplitudes(col.positions[m], float(col.slow_time[m])) * scale
                seen = amp != 0
                still = seen & ~spinning
                groups = [(None, np.concatenate([spos, scene.positions[still]]), np.concatenate([samp * scale,
                                                                                                  amp[still]]))]
                groups += [(o, scene.positions[seen & (scene.owner == k)], amp[seen & (scene.owner == k)])
                           for k, o in enumerate(objs) if o.spinning]
                self.groups.append(groups)
        self.path = turbulent_path(scenario, col) if scenario.atmosphere is not None and echoes else None
        self.gains = None
        if wave_optics and echoes:  # one look, nothing spinning: one scatterer set
            spos = self.groups[0][0][1]
            plan, region = wave_optics_plan(scenario, col)
            check_memory(col.n_pulses * len(spos) * 16.0 + 3 * plan.n ** 2 * 8.0,
                         f"wave-optics gains of {len(spos)} scatterers x {col.n_pulses} pulses",
                         "use fewer scatterers or pulses")
            self.gains, _ = two_way_gains(self.path, col.positions, spos, scenario.platform.real_aperture,
                                          region, sampling=plan, progress=progress)
            self.path = None
        pe = scenario.platform.phase_error
        self.phase_error = None if pe is None else np.exp(1j * pe.values(col.n_pulses)).astype(np.complex64)
        refc = scenario.receiver.reference_channel
        self.ref_delay = refc.delay if refc is not None and scenario.waveform.linewidth > 0 else 0.0
        # the reference channel's phase noise of every pulse, filled as the pulses are simulated
        self.ref_noise = np.zeros((col.n_pulses, self.t.size), np.float32) if self.ref_delay else None
        self.noise_steps = 1
        if scenario.waveform.linewidth > 0:  # the noise tables resolve the delay differences that matter
            shift = lo_shift(col.reference_range, scenario.receiver.lo_delay)
            diffs = [self.delays[0] - shift.min(), self.delays[0] - shift.max(), self.delays[1] - shift.min(),
                     self.delays[1] - shift.max(), self.ref_delay]
            self.noise_steps = substeps(float(self.t[1] - self.t[0]) if self.t.size > 1 else 1.0, diffs)

    def _pulses(self, a: int, b: int):
        col = self.col
        if (a, b) == (0, col.n_pulses):
            return col
        return dataclasses.replace(col, slow_time=col.slow_time[a:b], positions=col.positions[a:b],
                                   velocity=col.velocity[a:b], reference_range=col.reference_range[a:b],
                                   boresight=col.boresight[a:b])

    def _echoes(self, a: int, b: int, groups) -> np.ndarray:
        """Noise-free echoes of pulses ``a`` to ``b`` (one look) from its scatterer groups."""
        sc, col = self.sc, self.col
        sub = self._pulses(a, b)
        noise_tab = None
        if sc.waveform.linewidth > 0:  # the laser's phase noise, each pulse from its own stream
            noise_tab = phase_noise(sc.waveform.linewidth, self.t, self.delays,
                                    lo_shift(sub.reference_range, sc.receiver.lo_delay), sc.seed, np.arange(a, b),
                                    reference_delay=self.ref_delay, steps=self.noise_steps)
            if self.ref_noise is not None:
                self.ref_noise[a:b] = noise_tab.reference_phase(self.t, self.ref_delay)
        sig = None
        biggest = max(range(len(groups)), key=lambda i: groups[i][1].shape[0])
        for i, (obj, pos, amp) in enumerate(groups):
            if pos.shape[0] == 0:
                continue
            tick = None
            if self.progress is not None and self.gains is None and i == biggest:
                tick = (lambda d, n: self.progress(a + d, col.n_pulses))
            part = echo_signal(sub if obj is None else object_frame(sub, obj), pos, amp, sc, self.t, progress=tick,
                               path=self.path, gains=None if self.gains is None else self.gains[a:b],
                               phase_noise=noise_tab)
            sig = part if sig is None else sig + part
        return sig if sig is not None else np.zeros((b - a, self.t.size), np.complex64)

    def clean(self, a: int, b: int) -> np.ndarray:
        """Echoes of pulses ``a`` to ``b`` without the receiver's noise, complex64 (b - a, N): each
        look's run of pulses from its scatterers, with the laser's phase noise
        :data:`NOISE_TABLE_PULSES` pulses at a time, and the platform's phase error. No random
        number of ``rng`` is drawn: any process may compute any block."""
        step = NOISE_TABLE_PULSES if self.sc.waveform.linewidth > 0 else b - a
        parts = []
        for (la, lb), groups in zip(self.looks, self.groups):
            for s in range(max(a, la), min(b, lb), max(step, 1)):
                parts.append(self._echoes(s, min(s + step, b, lb), groups))
        if not parts:
            return np.zeros((0, self.t.size), np.complex64)
        sig = parts[0] if len(parts) == 1 else np.concatenate(parts)
        if self.phase_error is not None:
            sig *= self.phase_error[a:b, None]
        return sig

    def finish(self, sig: np.ndarray, noise: bool | None = None) -> np.ndarray:
        """The receiver's noise added to the next block's clean echoes (drawn from ``rng`` in pulse
        order) and, for real sampling, the real part.

        Parameters
        ----------
        sig : complex64 (B, N)
            :meth:`clean` of the pulses after the last block finished.
        noise : bool, optional
            Override ``receiver.noise.enabled``.

        Returns
        -------
        complex64 (B, N)
        """
        sc = self.sc
        if (sc.receiver.noise.enabled if noise is None else noise):
            photon_noise(sig, sc.receiver.noise, self.rng)
        if not sc.receiver.iq:
            sig = sig.real.astype(np.complex64)
        return sig

    def block(self, a: int, b: int, noise: bool | None = None) -> np.ndarray:
        """Echoes of pulses ``a`` to ``b`` with their noise, complex64 (b - a, N)."""
        return self.finish(self.clean(a, b), noise)

    def extras(self) -> dict:
        """Variables drawn after every pulse (the reference channel's beat and its noise: one beat
        for a coherent laser, one a pulse with the laser's phase noise)."""
        refc = self.sc.receiver.reference_channel
        if refc is None:
            return {}
        w, t = self.sc.waveform, self.t
        ref = reference_beat(t, w.carrier_frequency, w.rate, w.nonlinearity, refc.delay)
        sd = 10 ** (-refc.snr_db / 20) / math.sqrt(2)
        attrs = {"long_name": "dechirped reference-channel beat"}
        if self.ref_noise is None:
            ref = ref + sd * (self.rng.standard_normal(t.size) + 1j * self.rng.standard_normal(t.size))
            return {"reference_signal": (("fast_time",), ref.astype(np.complex64), attrs)}
        out = (ref[None, :] * np.exp(1j * self.ref_noise)).astype(np.complex64)
        for a in range(0, out.shape[0], 256):  # the receiver noise in blocks of pulses
            b = min(out.shape[0], a + 256)
            out[a:b] += (sd * (self.rng.standard_normal((b - a, t.size)) + 1j * self.rng.standard_normal((b - a, t.size)))
                         ).astype(np.complex64)
        return {"reference_signal": (("slow_time", "fast_time"), out, attrs)}

    def extra_attrs(self) -> dict:
        """Attributes known once the set-up is: the reference delay, the real sideband."""
        out = {}
        if self.sc.receiver.reference_channel is not None:
            out["reference_delay"] = self.sc.receiver.reference_channel.delay
        if not self.sc.receiver.iq:
            d0, d1 = delay_spread(self.sc, self.col)
            out["real_sideband"] = "negative" if d0 >= 0 else "positive"
        return out


#: Pulses whose laser phase-noise tables are drawn at once (their size bounded whatever the block).
NOISE_TABLE_PULSES = 256
#: Pulses of one draw of :func:`salkit.simulate.echoes.photon_noise` (512 Gaussian, 256 Poisson):
#: blocks of a multiple of it draw the same numbers as the whole signal at once.
NOISE_BLOCK = 512


_WORKER_JOB: dict = {}


def _clean_block_task(scenario: Scenario, a: int, b: int):
    """On a Dask worker: pulses ``a`` to ``b`` without the receiver's noise, and the reference
    channel's phase noise of those pulses (the worker's set-up kept for its next block)."""
    task_numba_threads()
    key = scenario.model_dump_json()
    if _WORKER_JOB.get("key") != key:
        _WORKER_JOB.clear()
        _WORKER_JOB.update(key=key, job=_Echoes(scenario, np.random.default_rng(scenario.seed)))
    job = _WORKER_JOB["job"]
    sig = job.clean(a, b)
    return sig, None if job.ref_noise is None else job.ref_noise[a:b].copy()


def simulate_to_file(scenario: Scenario, path, memory_limit: float | None = None, progress: ProgressFn = None,
                     client=None):
    """Simulate the raw data of a SAL scenario straight into a NetCDF file, a block of pulses at a
    time, for histories larger than memory: the same numbers as :func:`simulate_sal` (the random
    numbers are drawn in the same order), written as a chunked file (chunks of about 8 MiB of
    pulses; :class:`salkit.io.ChunkedFileWriter`, complete or absent). Given a Dask ``client``,
    the blocks' echoes are computed on its workers (each sets the scene up once) and their
    receiver noise is drawn here in pulse order: the same numbers again.

    Parameters
    ----------
    scenario : Scenario
    path : path
        The raw file to write.
    memory_limit : float, optional
        Bytes for the job: the scatterers (:func:`salkit.simulate.echoes.scene_memory`) and, in half
        of what they leave, the signal of one block (default: a quarter of the memory available).
    progress : callable, optional
        ``progress(done, total)`` in pulses.
    client : dask.distributed.Client, optional
        Compute the blocks on its workers (at most one more block in flight than workers; each
        worker holds the scene).

    Returns
    -------
    Path

    Raises
    ------
    ResourceError
        When one block (512 pulses with noise, one without), or the scene, does not fit.
    """
    rng = np.random.default_rng(scenario.seed)
    whole = float(memory_limit) if memory_limit is not None else available_memory() / 4.0
    scene, n_scat = scene_memory(scenario)
    if scene >= whole:
        raise ResourceError(f"the scene's {n_scat} scatterers need about {size_text(scene)} while simulated, more than "
                            f"the {size_text(whole)} budget; raise --memory-limit or sample the scene more coarsely "
                            "(scene.extended.spacing, fewer or smaller objects)")
    budget = (whole - scene) / 2.0
    ahead = 1
    if client is not None:  # the blocks in flight share the budget here
        ahead = max(1, len(client.scheduler_info().get("workers", {}))) + 1
        budget /= ahead
    P, N = signal_shape(scenario)
    per_pulse = 3 * 8.0 * N  # the block, its float32 parts in the kernels, the noise draw
    unit = NOISE_BLOCK if scenario.receiver.noise.enabled else 1  # without noise no draw to keep in step
    blk = P if per_pulse * P <= budget else int(budget // (per_pulse * unit)) * unit
    if blk < min(unit, P):
        raise ResourceError(f"simulating {P} pulses x {N} samples in blocks: one block of {min(unit, P)} pulses "
                            f"needs about {size_text(per_pulse * min(unit, P))}, more than the {size_text(budget)} "
                            "available (the budget); raise --memory-limit or reduce receiver.adc_rate")
    job = _Echoes(scenario, rng, progress if client is None else None, echoes=client is None)
    col = job.col
    units = "shot_noise" if scenario.receiver.noise.enabled else "reflectivity"
    blank = np.broadcast_to(np.complex64(0), (col.n_pulses, job.t.size))
    skel = make_raw_dataset(blank, col, job.t, scenario, signal_units=units,
                            noise=scenario.receiver.noise.enabled).drop_vars("signal")
    rows = max(1, min(blk, (8 * 2 ** 20) // (8 * job.t.size)))  # chunks of about 8 MiB: a block reads only itself
    with ChunkedFileWriter(path, skel, "signal", ("slow_time", "fast_time"), (rows, job.t.size),
                           {"long_name": "dechirped I/Q signal", "units": units}) as w:
        blocks = [(a, min(col.n_pulses, a + blk)) for a in range(0, col.n_pulses, blk)]
        if client is None:
            for a, b in blocks:
                w.write(a, 0, job.block(a, b))
        else:
            todo = iter(blocks)
            flying = deque(client.submit(_clean_block_task, scenario, a, b, pure=False) for a, b in islice(todo, ahead))
            for a, b in blocks:  # in pulse order: the receiver's noise drawn as simulate_sal draws it
                sig, ref_noise = flying.popleft().result()
                for nxt in islice(todo, 1):
                    flying.append(client.submit(_clean_block_task, scenario, *nxt, pure=False))
                if ref_noise is not None:
                    job.ref_noise[a:b] = ref_noise
                w.write(a, 0, job.finish(sig))
                if progress is not None:
                    progress(b, col.n_pulses)
        for name, (dims, values, attrs) in job.extras().items():
            w.add(name, dims, values, attrs)
        return w.close(job.extra_attrs())
