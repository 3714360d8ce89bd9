"""The fast simulator of many scatterers: each pulse's dechirped echoes as one non-uniform FFT.

For a linear chirp and stop-and-go geometry, a scatterer of delay offset d = 2 (R - R_ref) / c
adds to fast-time sample n (t = t0 + n dt)

    a g exp(j [pi k d^2 - 2 pi f0 d - 2 pi k d t0]) exp(j x n),   x = -2 pi k d dt,

(:mod:`salkit.simulate.kernels`: the residual video phase, the carrier, the beat), so a pulse's
samples are the type-1 non-uniform FFT of the scatterers' coefficients at the points x (finufft):
O(S + N log N) a pulse instead of the direct sum's O(S N). The coefficients (ranges in float64,
the beam, the turbulence's two-way path phase or the wave-optics gains) come from a numba kernel,
the transform from finufft at a tolerance from the requested accuracy (:data:`EPS_OF_DB`). It
holds where every echo covers the ADC gate (a stretch receiver's gate inside the pulse: the echo
window |t - d| <= T/2 is then 1 at every sample) and the chirp is linear, without intra-pulse
motion or laser phase noise; :func:`applies` says whether, and the direct sum stays the reference
(``scenario.simulation.method``).
"""
from __future__ import annotations

import math
import threading
from concurrent.futures import ThreadPoolExecutor

import lazy_loader as _lazy
import numpy as np
from numba import get_num_threads, njit

from ..atmosphere.path import path_phase
from ..constants import SPEED_OF_LIGHT
from ..signals.phase import sincos_cycles
from .kernels import _beam

_finufft = _lazy.load("finufft", suppress_warning=True)

_TWO_PI = 2.0 * math.pi


def eps_of_db(accuracy_db: float) -> float:
    """finufft's tolerance for an image error energy of ``accuracy_db`` (dB) against the direct
    sum: its relative l2 error is about its tolerance, and the error energy its square; a factor 3
    of margin.

    Parameters
    ----------
    accuracy_db : float
        Target error energy, dB (negative).

    Returns
    -------
    float

    Examples
    --------
    >>> eps_of_db(-80.0)
    3.3333333333333335e-05
    """
    return 10.0 ** (accuracy_db / 20.0) / 3.0


#: Accuracy settings (dB) at or above which the coefficients' sine and cosine come from the float32
#: polynomial (:func:`salkit.signals.phase.sincos_cycles`, error below 5e-6: about -106 dB).
FAST_TRIG_DB = -90.0


def applies(scenario, delays: tuple[float, float], fast_time: np.ndarray) -> str:
    """Why the fast simulator does not hold for ``scenario`` ("" when it does).

    Parameters
    ----------
    scenario : Scenario
    delays : (float, float)
        Smallest and largest delay offset of the scene's echoes, s.
    fast_time : float64 (N,)
        Sample times relative to the reference delay, s.

    Returns
    -------
    str
    """
    w = scenario.waveform
    if not w.is_linear:
        return "the chirp is not linear"
    if scenario.platform.intra_pulse_motion:
        return "intra-pulse motion"
    if w.linewidth > 0:
        return "laser phase noise (waveform.linewidth)"
    half = 0.5 * w.pulse_width
    if fast_time[0] < delays[1] - half or fast_time[-1] > delays[0] + half:
        return (f"the ADC gate ({fast_time[0]:.4g} .. {fast_time[-1]:.4g} s from the reference delay) is not inside "
                f"every echo (delays {delays[0]:.4g} .. {delays[1]:.4g} s, pulse {w.pulse_width:.4g} s)")
    return ""


@njit(nogil=True, cache=True, fastmath=False)
def _coefficients(pos, ref, bore, scat, amp_re, amp_im, t0, dt, n_half, f0, k, table, dsin,
                  scr, scr_z, scr_org, scr_dx, u0, ax_a, ax_b, gain, c_out, x_out, fast_trig):
    """One pulse's NUFFT coefficients and points (the phase in cycles reduced in float64; its sine
    and cosine by the float32 polynomial, error below 5e-6, when ``fast_trig``)."""
    S = scat.shape[0]
    for s in range(S):
        dx = scat[s, 0] - pos[0]
        dy = scat[s, 1] - pos[1]
        dz = scat[s, 2] - pos[2]
        R = math.sqrt(dx * dx + dy * dy + dz * dz)
        if gain.shape[0] > 0:
            gr, gi = gain[s].real, gain[s].imag
        else:
            gr, gi = _beam(dx, dy, dz, R, bore[0], bore[1], bore[2], table, dsin), 0.0
        ar = amp_re[s] * gr - amp_im[s] * gi
        ai = amp_re[s] * gi + amp_im[s] * gr
        d = 2.0 * (R - ref) / SPEED_OF_LIGHT
        beat = -k * d * dt  # cycles a sample
        cyc = 0.5 * k * d * d - f0 * d - k * d * t0 + beat * n_half  # modes -N/2 .. N/2-1 are samples 0 .. N-1
        if scr.shape[0] > 0:
            cyc += 2.0 * path_phase(pos[0], pos[1], pos[2], scat[s, 0], scat[s, 1], scat[s, 2],
                                    scr, scr_z, scr_org, scr_dx, u0, ax_a, ax_b) / _TWO_PI
        cyc -= math.floor(cyc + 0.5)  # in [-0.5, 0.5)
        if fast_trig:
            sn, c = sincos_cycles(np.float32(cyc))
        else:
            c, sn = math.cos(_TWO_PI * cyc), math.sin(_TWO_PI * cyc)
        c_out[s] = complex(ar * c - ai * sn, ar * sn + ai * c)
        b = beat - math.floor(beat + 0.5)  # in [-0.5, 0.5) cycles a sample
        x_out[s] = _TWO_PI * b


def fast_echoes(collection, scatter_pos: np.ndarray, scatter_amp: np.ndarray, scenario, fast_time: np.ndarray,
                table: np.ndarray, dsin: float, path_args: tuple, gains: np.ndarray | None = None,
                accuracy_db: float = -80.0, progress=None, threads: int | None = None) -> np.ndarray:
    """Dechirped echoes (P, N) complex64 by one non-uniform FFT a pulse (the conditions of
    :func:`applies` assumed).

    Parameters
    ----------
    collection : Collection
    scatter_pos : float64 (S, 3)
        m.
    scatter_amp : complex (S,)
    scenario : Scenario
    fast_time : float64 (N,)
        s, relative to the reference delay, uniform.
    table, dsin : ndarray, float
        The beam gain table (:func:`salkit.geometry.collection.beam_gain_table`).
    path_args : tuple
        The turbulent path's screens (:func:`salkit.simulate.echoes._path_args`).
    gains : complex (P, S), optional
        Two-way gains in place of the beam (wave optics).
    accuracy_db : float
        Error energy against the direct sum, dB (:func:`eps_of_db`).
    progress : callable, optional
        ``progress(done, total)`` in pulses.
    threads : int, optional
        Pulses in work at once, each in a thread of its own with a one-thread finufft plan
        (default: numba's threads).

    Returns
    -------
    complex64 (P, N)
    """
    w = scenario.waveform
    P, N = collection.n_pulses, fast_time.size
    t0 = float(fast_time[0])
    dt = float(fast_time[1] - fast_time[0]) if N > 1 else 1.0
    pos = np.ascontiguousarray(scatter_pos, np.float64)
    are = np.ascontiguousarray(scatter_amp.real, np.float64)
    aim = np.ascontiguousarray(scatter_amp.imag, np.float64)
    S = pos.shape[0]
    out = np.empty((P, N), np.complex64)
    eps = eps_of_db(accuracy_db)
    fast_trig = accuracy_db >= FAST_TRIG_DB
    no_gain = np.zeros(0, np.complex128)
    workers = max(1, min(threads or get_num_threads(), P))
    done = [0]
    lock = threading.Lock()
    Plan = _finufft.Plan  # loaded here, once, before the threads

    def pulses(first: int) -> None:  # every workers-th pulse from ``first``, in this thread
        # one thread a plan (no OpenMP overhead); no sorting of the points: the fine grid of one pulse
        # (2N samples) stays in cache, and sorting a million points took as long as spreading them
        plan = Plan(1, (N,), eps=eps, isign=1, nthreads=1, spread_sort=0)
        c = np.empty(S, np.complex128)
        x = np.empty(S, np.float64)
        for p in range(first, P, workers):
            g = no_gain if gains is None else np.ascontiguousarray(gains[p], np.complex128)
            _coefficients(np.ascontiguousarray(collection.positions[p]), float(collection.reference_range[p]),
                          np.ascontiguousarray(collection.boresight[p]), pos, are, aim, t0, dt, float(N // 2),
                          w.carrier_frequency, w.rate, table, dsin, *path_args, g, c, x, fast_trig)
            plan.setpts(x)
            out[p] = plan.execute(c)
            if progress is not None:
                with lock:
                    done[0] += 1
                    if done[0] % 32 == 0 or done[0] == P:
                        progress(done[0], P)

    with ThreadPoolExecutor(max_workers=workers) as pool:  # numba and finufft release the GIL
        for f in [pool.submit(pulses, k) for k in range(workers)]:
            f.result()
    return out
