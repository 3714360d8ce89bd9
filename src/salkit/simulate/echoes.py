"""SAL stretch echoes: the fast-time axis, the echo of scatterers seen from a collection (the
kernels' driver), photon noise, the signal scale and the size of the raw data."""
from __future__ import annotations

import math
from typing import Callable, Optional

import numpy as np

from ..constants import SPEED_OF_LIGHT
from ..errors import ScenarioError
from ..geometry.collection import Collection, beam_gain_table, build_collection, pulse_count
from ..geometry.sampling import resolution_theory
from ..params.models import Noise, Scenario
from .linewidth import NO_PHASE_NOISE
from .fast import applies, fast_echoes
from .kernels import simulate_exact, simulate_linear
from .targets import sample_count
from .views import look_segments

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


#: ``simulation.method = "auto"`` takes the fast simulator from this many scatterer-samples a pulse.
AUTO_FAST = 1 << 20


def _delays(collection: Collection, scatter_pos: np.ndarray, fast_time: np.ndarray) -> tuple[float, float]:
    """Smallest and largest delay offset 2 (R - R_ref) / c of the scatterers over the collection's
    first, middle and last pulses, s."""
    d = []
    for p in sorted({0, collection.n_pulses // 2, collection.n_pulses - 1}):
        R = np.linalg.norm(scatter_pos - collection.positions[p], axis=1)
        d.append(2.0 * (R - collection.reference_range[p]) / SPEED_OF_LIGHT)
    d = np.concatenate(d) if d else np.zeros(1)
    return float(d.min()), float(d.max())


def echo_signal(collection: Collection, scatter_pos: np.ndarray, scatter_amp: np.ndarray,
                scenario: Scenario, fast_time: np.ndarray, chunk: int = 256,
                progress: ProgressFn = None, path=None, gains: np.ndarray | None = None,
                phase_noise=None) -> np.ndarray:
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
    phase_noise : PhaseNoise, optional
        The laser's phase noise for these pulses (:func:`salkit.simulate.linewidth.phase_noise`).

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
    exact = (not w.is_linear) or p.intra_pulse_motion or phase_noise is not None
    coeffs = np.asarray(w.nonlinearity, dtype=np.float64)
    if w.phase_error is not None:
        try:
            et, ev = w.phase_error.table(w.pulse_width)
        except ValueError as err:
            raise ScenarioError("waveform.phase_error", w.phase_error.file or w.phase_error.kind, str(err)) from None
        etab = (float(et[0]), float(et[1] - et[0]), np.ascontiguousarray(ev, dtype=np.float64))
    else:
        etab = (0.0, 1.0, np.zeros(0))
    method = scenario.simulation.method
    if method != "direct" and not exact:
        why = applies(scenario, _delays(collection, scatter_pos, fast_time), fast_time)
        if why and method == "nufft":
            raise ScenarioError("simulation.method", "nufft", f"the fast simulator does not hold here: {why}")
        if not why and (method == "nufft" or scatter_pos.shape[0] * N >= AUTO_FAST):
            return fast_echoes(collection, scatter_pos, scatter_amp, scenario, fast_time, table, dsin, pargs,
                               gains=gains, accuracy_db=scenario.simulation.accuracy_db, progress=progress)
    elif method == "nufft":
        raise ScenarioError("simulation.method", "nufft", "the fast simulator needs a linear chirp, no intra-pulse "
                            "motion and no laser phase noise")
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
                           table, dsin, re, im, *pargs, g, *etab,
                           *(NO_PHASE_NOISE if phase_noise is None else phase_noise.rows(a, b)))
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


#: Peak bytes a point or extended-scene scatterer takes while simulated: its position and amplitude,
#: the lattice it is drawn from, the kernels' float64 copies, the fast simulator's coefficients and
#: points in each thread (measured by peak RSS over the baseline: 137 B a scatterer at 10^6, 167 B at
#: 4 x 10^6, `salkit simulate`, 2026-11-26).
BYTES_A_SCATTERER = 176.0
#: Peak bytes an object's surface sample takes: position, normal, area, speckle and owner, a look's
#: amplitudes, the seen samples' copies, and a scatterer's share in the kernels (measured: 262 B a
#: sample at 2 x 10^6, one look, `salkit simulate`, 2026-11-26; docs/targets.md).
BYTES_A_SAMPLE = 320.0
#: Bytes a seen sample keeps for each further look (its position and amplitude).
BYTES_A_LOOK = 40.0


def scene_memory(scenario: Scenario) -> tuple[float, int]:
    """Peak memory of a scenario's scatterers while simulated, bytes, and their count (the objects'
    samples counted from their meshes, nothing sampled).

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (float, int)
    """
    sc = scenario.scene
    n_scat = len(sc.points)
    if sc.extended is not None:
        n_scat += int((sc.extended.extent[0] / sc.extended.spacing + 1) * (sc.extended.extent[1] / sc.extended.spacing + 1))
    n_obj, per_obj = 0, 0.0
    if sc.objects:
        col = build_collection(scenario)
        res = resolution_theory(scenario, col)
        n_obj = sample_count(sc.objects, min(res["azimuth"], res["slant_range"]) / 2.0)
        looks = len(look_segments(col.positions, col.slow_time, sc.objects))
        per_obj = BYTES_A_SAMPLE + BYTES_A_LOOK * (looks - 1)
    return BYTES_A_SCATTERER * n_scat + per_obj * n_obj, n_scat + n_obj


def memory_estimate(scenario: Scenario) -> tuple[float, str]:
    """Peak memory of simulating a scenario, bytes, from its sizes (nothing is built).

    The complex64 signal twice (noise, the dataset), 2 kB per pulse (geometry and the sampling
    check's probes), the scatterers (:func:`scene_memory`); with laser phase noise and a reference
    channel, its beat of every pulse (complex64) and its phase noise (float32).

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (float, str)
        Bytes, and the sizes that drive it (for messages).
    """
    P, N = signal_shape(scenario)
    scene, n_scat = scene_memory(scenario)
    sig = 8.0 * P * N
    need = 2 * sig + 2048.0 * P + scene
    if scenario.waveform.linewidth > 0 and scenario.receiver.reference_channel is not None:
        need += 1.5 * sig  # a reference beat a pulse (complex64) and its phase noise (float32)
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


