"""Raw-data simulation: dechirped (stretch) LFM echoes with beam weighting, speckle and noise."""
from __future__ import annotations

import math
from typing import Callable, Optional

import numpy as np
import xarray as xr

from ..geometry.collection import (Collection, beam_gain_table, build_collection,
                                   resolution_theory)
from ..resources import check_memory
from ..geometry.sampling import check_sampling, n_fast_samples
from ..io.datasets import make_raw_dataset
from ..params.models import Noise, Scenario
from .downlooking import simulate_downlooking
from .kernels import simulate_exact, simulate_linear
from .scene import build_scatterers

ProgressFn = Optional[Callable[[int, int], None]]


def fast_time_axis(n: int, adc_rate: float) -> np.ndarray:
    """Fast-time sample times relative to the reference delay, s: (i - n//2)/adc_rate.

    Parameters
    ----------
    n : int
    adc_rate : float
        Hz.

    Returns
    -------
    float64 (n,)
        s.

    Examples
    --------
    >>> fast_time_axis(4, 2.0).tolist()
    [-1.0, -0.5, 0.0, 0.5]
    """
    return (np.arange(n) - n // 2) / adc_rate


_NO_PATH = (np.zeros((0, 2, 2), np.float32), np.zeros(0), np.zeros((0, 2)), 1.0, np.array([0.0, 0.0, 1.0]),
            np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))


def _path_args(path):
    if path is None:
        return _NO_PATH
    return (np.ascontiguousarray(path.screens, np.float32), np.asarray(path.z, float),
            np.asarray(path.origin, float), float(path.dx), path.u0, path.a, path.b)


def echo_signal(collection: Collection, scatter_pos: np.ndarray, scatter_amp: np.ndarray,
                scenario: Scenario, fast_time: np.ndarray, chunk: int = 256,
                progress: ProgressFn = None, path=None, gains: np.ndarray | None = None) -> np.ndarray:
    """Noise-free dechirped echoes (P, N) complex64 of the given scatterers.

    Parameters
    ----------
    collection : Collection
        Per-pulse geometry.
    scatter_pos : ndarray (S, 3)
        Scatterer positions, m (float64).
    scatter_amp : ndarray (S,)
        Complex reflectivities (amplitude per sample before noise scaling).
    scenario : Scenario
    fast_time : ndarray (N,)
        Sample times relative to the reference delay, s (uniform).
    chunk : int
        Pulses per kernel call (bounds memory of the intermediate float32 planes).
    progress : callable, optional
        Called as ``progress(done_pulses, total_pulses)``.
    path : TurbulentPath, optional
        Frozen turbulence screens; each echo carries its two-way path phase.
    gains : complex ndarray (P, S), optional
        Two-way complex gain of each scatterer at each pulse, in place of the beam pattern (wave
        optics, :func:`salkit.atmosphere.beam.two_way_gains`).

    Returns
    -------
    complex64 (P, N)
    """
    w, p = scenario.waveform, scenario.platform
    pargs = _path_args(path)
    P, N = collection.n_pulses, fast_time.size
    out = np.empty((P, N), np.complex64)
    table, dsin = beam_gain_table(w.wavelength, p.real_aperture)
    pos = np.ascontiguousarray(scatter_pos, dtype=np.float64)
    are = np.ascontiguousarray(scatter_amp.real, dtype=np.float64)
    aim = np.ascontiguousarray(scatter_amp.imag, dtype=np.float64)
    t0 = float(fast_time[0])
    dt = float(fast_time[1] - fast_time[0]) if N > 1 else 1.0
    exact = (not w.is_linear) or p.intra_pulse_motion
    coeffs = np.asarray(w.nonlinearity, dtype=np.float64)
    if w.phase_error is not None:
        try:
            et, ev = w.phase_error.table(w.pulse_width)
        except ValueError as err:
            raise ScenarioError("waveform.phase_error", w.phase_error.file or w.phase_error.kind, str(err)) from None
        etab = (float(et[0]), float(et[1] - et[0]), np.ascontiguousarray(ev, dtype=np.float64))
    else:
        etab = (0.0, 1.0, np.zeros(0))
    no_gain = np.zeros((0, 0), np.complex128)
    for a in range(0, P, chunk):
        b = min(P, a + chunk)
        g = no_gain if gains is None else np.ascontiguousarray(gains[a:b], np.complex128)
        re = np.zeros((b - a, N), np.float32)
        im = np.zeros((b - a, N), np.float32)
        args_geo = (np.ascontiguousarray(collection.positions[a:b]),)
        if exact:
            simulate_exact(args_geo[0], np.ascontiguousarray(collection.velocity[a:b]),
                           np.ascontiguousarray(collection.reference_range[a:b]),
                           np.ascontiguousarray(collection.boresight[a:b]), pos, are, aim, t0, dt,
                           w.carrier_frequency, w.rate, w.pulse_width, coeffs, p.intra_pulse_motion,
                           table, dsin, re, im, *pargs, g, *etab)
        else:
            simulate_linear(args_geo[0], np.ascontiguousarray(collection.reference_range[a:b]),
                            np.ascontiguousarray(collection.boresight[a:b]), pos, are, aim, t0, dt,
                            w.carrier_frequency, w.rate, w.pulse_width, table, dsin, re, im, *pargs, g)
        out[a:b].real = re
        out[a:b].imag = im
        if progress is not None:
            progress(b, P)
    return out


def photon_noise(signal: np.ndarray, noise: Noise, rng: np.random.Generator) -> np.ndarray:
    """Add photon-limited heterodyne noise to a signal in shot-noise units (in place, returned).

    ``gaussian``: the strong-LO limit, complex white noise of unit variance per sample.
    ``poisson``: photocounts of the I and Q outputs of a 90-degree hybrid (seed 001 eq 8),
    Poisson with means eta_d (n_L + |U|^2)/2 + sqrt(eta_d n_L) Re/Im(s), LO DC removed and
    normalised by sqrt(eta_d n_L); n_L is the LO photon number per sample.

    Parameters
    ----------
    signal : complex64 (P, N)
        In shot-noise units; modified in place.
    noise : Noise
    rng : numpy.random.Generator

    Returns
    -------
    complex64 (P, N)
        ``signal``.
    """
    P, N = signal.shape
    if noise.model == "gaussian":
        for a in range(0, P, 512):
            b = min(P, a + 512)
            z = rng.standard_normal((b - a, N, 2), dtype=np.float32) * np.float32(math.sqrt(0.5))
            signal[a:b] += z[..., 0] + 1j * z[..., 1]
        return signal
    eta_d = noise.quantum_efficiency
    n_l = noise.lo_photons / N
    dc = eta_d * n_l / 2.0
    g = math.sqrt(eta_d * n_l)
    for a in range(0, P, 256):
        b = min(P, a + 256)
        s = signal[a:b].astype(np.complex128)
        u2 = np.abs(s) ** 2 / noise.efficiency  # |U|^2 photons
        mean_i = dc + eta_d * u2 / 2.0 + g * s.real
        mean_q = dc + eta_d * u2 / 2.0 + g * s.imag
        ci = rng.poisson(np.maximum(mean_i, 0.0))
        cq = rng.poisson(np.maximum(mean_q, 0.0))
        signal[a:b] = ((ci - dc) + 1j * (cq - dc)) / g
    return signal


def signal_shape(scenario: Scenario) -> tuple[int, int]:
    """Pulses and an upper bound on the samples per pulse of :func:`simulate`, without building
    anything: (pulse count, (ADC gate or pulse width) x ADC rate + 1).

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (int, int)
    """
    gate = scenario.receiver.gate or scenario.waveform.pulse_width
    return pulse_count(scenario), int(gate * scenario.receiver.adc_rate) + 1


def memory_estimate(scenario: Scenario) -> tuple[float, str]:
    """Peak memory of simulating a scenario, bytes, from its sizes (nothing is built).

    The complex64 signal twice (noise, the dataset), 2 kB per pulse (geometry and the sampling
    check's probes), 48 bytes per scatterer.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (float, str)
        Bytes, and the sizes that drive it (for messages).
    """
    P, N = signal_shape(scenario)
    sc = scenario.scene
    n_scat = len(sc.points)
    if sc.extended is not None:
        n_scat += int((sc.extended.extent[0] / sc.extended.spacing + 1) * (sc.extended.extent[1] / sc.extended.spacing + 1))
    sig = 8.0 * P * N
    need = 2 * sig + 2048.0 * P + 48.0 * n_scat
    return need, f"simulating {P} pulses x {N} samples ({sig / 2 ** 30:.3g} GiB of signal), {n_scat} scatterers"


def signal_scale(scenario: Scenario, collection: Collection, n_samples: int) -> float:
    """Amplitude per sample of a unit-reflectance scatterer, in shot-noise units when noise is on.

    With noise, a unit cell delivers N_s photons over the aperture, i.e. N_s/(N * P_ap) per sample,
    so that the focused cell's carrier-to-noise ratio is eta*N_s.

    Parameters
    ----------
    scenario : Scenario
    collection : Collection
    n_samples : int

    Returns
    -------
    float
    """
    nz = scenario.receiver.noise
    if not nz.enabled:
        return 1.0
    p, w = scenario.platform, scenario.waveform
    if p.mode == "spotlight":
        n_ap = collection.n_pulses
    else:
        res = resolution_theory(scenario, collection)
        n_ap = max(res["aperture_length"] / (p.speed / w.prf), 1.0)
    return math.sqrt(nz.efficiency * nz.signal_photons / (n_samples * n_ap))


def screen_size(scenario: Scenario, col: Collection) -> int:
    """Side of the scenario's phase screens: ``atmosphere.screen_n`` if given, else large enough for
    every ray (and, for ``wave_optics``, for the propagation grid on every layer).

    Parameters
    ----------
    scenario : Scenario
        With an atmosphere.
    col : Collection

    Returns
    -------
    int

    Raises
    ------
    ScenarioError
        When an explicit ``atmosphere.screen_n`` is smaller than what the rays (or the grids) cross.
    """
    atm = scenario.atmosphere
    R, u0, a, b = _los_frame(col)
    probe = scene_probe_points(scenario)
    # extent the rays cover on the layers: scene extent near the target, aperture near the platform
    ends = np.stack([col.positions[0], col.positions[-1], col.positions[col.n_pulses // 2]])
    need = 0.0
    for frac in (0.0, 0.5, 1.0 - 0.5 / atm.layers):
        q = ray_crossings(ends, probe, frac * R, u0)
        need = max(need, float(np.ptp(q @ a)), float(np.ptp(q @ b)))
    what = "the rays cross"
    if atm.model == "wave_optics":  # the propagation grids must lie on the screens on every layer
        plan, _ = wave_optics_plan(scenario, col)
        grids = screen_need(plan, R, _swath(col, a, b))
        if grids > need:
            need, what = grids, "the wave-optics grids cover"
    n_need = int(math.ceil(need / atm.screen_dx)) + 8
    if atm.screen_n is not None and atm.screen_n < n_need:
        raise ScenarioError("atmosphere.screen_n", atm.screen_n,
                            f"{what} {need:.4g} m of a layer; at screen_dx = {atm.screen_dx:g} m the "
                            f"screen needs >= {n_need} samples")
    return atm.screen_n or max(32, n_need)


def turbulent_path(scenario: Scenario, col: Collection):
    """The scenario's frozen-screen path, with screens of :func:`screen_size`.

    Parameters
    ----------
    scenario : Scenario
    col : Collection

    Returns
    -------
    TurbulentPath

    Raises
    ------
    ScenarioError
        When an explicit ``atmosphere.screen_n`` is too small (:func:`screen_size`), or the screens
        need more memory than the machine has.
    """
    atm = scenario.atmosphere
    R = float(np.linalg.norm(col.center_position))
    n = screen_size(scenario, col)
    check_memory(atm.layers * n * n * 4.0, f"{atm.layers} phase screens of {n} x {n}",
                 "use fewer atmosphere.layers or a coarser atmosphere.screen_dx")
    return build_path(atm.cn2, R, scenario.waveform.wavelength, atm.layers, n, atm.screen_dx,
                      col.center_position / R, col.track, seed=atm.seed, outer_scale=atm.outer_scale,
                      inner_scale=atm.inner_scale)


def _los_frame(col: Collection):
    """Slant range R (m), the line of sight u0 (scene centre to aperture centre) and the layer
    planes' axes: a along track (orthogonal to u0), b = u0 x a (the frame of build_path)."""
    R = float(np.linalg.norm(col.center_position))
    u0 = col.center_position / R
    a = col.track - np.dot(col.track, u0) * u0
    a /= np.linalg.norm(a)
    return R, u0, a, np.cross(u0, a)


def _swath(col: Collection, a: np.ndarray, b: np.ndarray) -> float:
    """Largest extent of the antenna positions across the line of sight (along a or b), m."""
    return float(max(np.ptp(col.positions @ a), np.ptp(col.positions @ b)))


def wave_optics_plan(scenario: Scenario, col: Collection):
    """Sampling of the wave-optics transmit beam (:func:`salkit.atmosphere.beam.plan_beam`) for a
    scenario: the path's length, layers and spherical-wave r0; the scene region the larger of the
    scatterers' extent across the line of sight (plus 10 %) and the beam's first-null diameter
    2.44 lambda R / D.

    Parameters
    ----------
    scenario : Scenario
        With an atmosphere.
    col : Collection

    Returns
    -------
    (BeamSampling, float)
        The sampling and the region's diameter, m.

    Raises
    ------
    SamplingError
        When the beam cannot be sampled on a grid of at most 4096^2.
    ScenarioError
        For a stripmap collection.
    """
    atm, lam = scenario.atmosphere, scenario.waveform.wavelength
    if scenario.platform.mode != "spotlight":  # each beam is propagated towards the scene centre
        raise ScenarioError("atmosphere.model", "wave_optics",
                            f"needs a spotlight collection (the beam points at the scene centre), "
                            f"not platform.mode = {scenario.platform.mode}")
    R, _, a, b = _los_frame(col)
    probe = scene_probe_points(scenario)
    radius = float(np.max(np.hypot(probe @ a, probe @ b)))
    region = max(2.2 * radius, 2.44 * lam * R / scenario.platform.real_aperture)
    dz = R / atm.layers
    z = (np.arange(atm.layers) + 0.5) * dz
    r0 = np.broadcast_to(np.asarray(r0_from_cn2(np.asarray(atm.cn2, float), dz, lam), float), (atm.layers,))
    return plan_beam(lam, R, scenario.platform.real_aperture, region, layered_r0_spherical(r0, z, R), z), region


def simulate(scenario, progress: ProgressFn = None, noise: bool | None = None,
             rng: np.random.Generator | None = None) -> xr.Dataset:
    """Simulate the raw data of a scenario, with the simulator its kind names (:data:`SIMULATORS`:
    ``sal`` dechirped stretch echoes for every :class:`~salkit.params.Scenario`, ``downlooking``
    the balanced current of a :class:`~salkit.params.DownlookingScenario`).

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
    progress : callable, optional
        ``progress(done, total)`` in pulses (scans).
    noise : bool, optional
        Override the scenario's noise switch.
    rng : numpy.random.Generator, optional
        Default: seeded from ``scenario.seed``.

    Returns
    -------
    xarray.Dataset
        Raw data in the format of ``docs/data-format.md``.

    Examples
    --------
    >>> from salkit.params import load_scenario
    >>> raw = simulate(load_scenario("examples/spotlight_points.yaml",
    ...                              ["platform.aperture_length=0.5"]))  # doctest: +SKIP
    """
    kind = "downlooking" if scenario.is_downlooking else "sal"
    return SIMULATORS[kind](scenario, progress=progress, noise=noise, rng=rng)


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


#: scenario kind -> simulator, all ``f(scenario, progress=, noise=, rng=) -> xr.Dataset``.
SIMULATORS = {"sal": simulate_sal, "downlooking": simulate_downlooking}

from .._callable import make_callable as _make_callable  # noqa: E402
from ..errors import ScenarioError
from ..geometry.collection import pulse_count
from ..atmosphere.path import ray_crossings, build_path
from ..atmosphere.beam import layered_r0_spherical, plan_beam, screen_need, two_way_gains
from ..atmosphere.turbulence import r0_from_cn2
from ..geometry.sampling import scene_probe_points
from ..signals.chirp import reference_beat
from ..geometry.sampling import delay_spread

_make_callable(__name__, "simulate")
