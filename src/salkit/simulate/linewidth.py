"""Lasers of finite linewidth: the phase noise of a laser with a Lorentzian line of FWHM
``linewidth`` (Hz) is a Wiener process, E[(phi(t + tau) - phi(t))^2] = 2 pi linewidth |tau|.

An echo of round-trip delay tau carries the laser's phase from when it left, phi(t - tau); the
local oscillator (LO) the phase from tau_LO ago, phi(t - tau_LO). Their beat keeps
phi(t - tau) - phi(t - tau_LO): a Gaussian phase error of variance 2 pi linewidth |tau - tau_LO|
(:func:`phase_noise_variance`), nothing where the LO's delay matches the echo's (a delay-line LO
matched to the dechirp reference range, ``receiver.lo_delay`` unset), the whole round trip with an
undelayed LO (``lo_delay: 0``). Its expected effect on a coherent image is a loss of peak power
exp(-sigma^2) (:func:`peak_power_loss`), the power going into a pedestal.

A reference channel (seed 002's delay line, ``receiver.reference_channel``, its reference LO tapped
where the target channel's LO is) records phi(t_LO - D) - phi(t_LO) for each pulse, D its delay
(:meth:`PhaseNoise.reference_phase`); range compression with ``processing.phase_noise_correction:
reference`` removes it from the target channel (:func:`salkit.focus.chirpcorr.remove_reference_noise`),
which cancels the noise of an echo whose delay difference tau - tau_LO equals D and leaves
phi(t_LO - (tau - tau_LO)) - phi(t_LO - D), of variance 2 pi linewidth |tau - tau_LO - D|, elsewhere.

The simulator evaluates the noise exactly at each echo's and the LO's time: per pulse, one Wiener
path sampled at the ADC spacing over the window the echoes read and the window the LO reads (one
path over both where they are close; two windows and the Gaussian increment across the gap
between them where they are far apart, as with an undelayed LO at 200 km), drawn from a stream of
its own (the scenario's seed and the pulse index), so a pulse's noise is the same whichever block
it is simulated in. Pulses draw independent paths: exact when the window of one pulse (its delay
and length) is shorter than the pulse repetition interval, as in every seed geometry; at longer
delays (GEO) the correlation between neighbouring pulses' noise is not modelled.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import SPEED_OF_LIGHT

#: Stream key of the phase noise (with the scenario's seed and the pulse index).
STREAM = 0x1A5E
#: Windows closer than this many times their length are drawn as one path.
JOIN = 4.0


def phase_noise_variance(linewidth: float, delay_difference: float) -> float:
    """Variance of the beat's phase error, 2 pi linewidth |tau - tau_LO|, rad^2.

    Parameters
    ----------
    linewidth : float
        Lorentzian FWHM, Hz.
    delay_difference : float
        tau - tau_LO, s.

    Returns
    -------
    float

    Examples
    --------
    >>> round(phase_noise_variance(10e3, 2 * 5000 / 299792458.0), 4)
    2.0958
    """
    return 2.0 * math.pi * float(linewidth) * abs(float(delay_difference))


def peak_power_loss(linewidth: float, delay_difference: float) -> float:
    """Expected peak power of a point target's image with phase noise over the coherent one,
    exp(-sigma^2) (its amplitude exp(-sigma^2 / 2)).

    Parameters
    ----------
    linewidth : float
        Hz.
    delay_difference : float
        s.

    Returns
    -------
    float
    """
    return math.exp(-phase_noise_variance(linewidth, delay_difference))


def expected_peak_power_loss(linewidth: float, delay_difference: float, dt: float, range_weights: np.ndarray,
                             pulse_weights: np.ndarray) -> float:
    """Ensemble mean of a point target's intensity with phase noise over the coherent one, with the
    pedestal the noise leaves: the image at the target sums e^{j dphi} over pulses (independent
    draws: E = e^{-sigma^2} between two pulses) and over a pulse's samples, whose phase errors
    t apart differ by a Gaussian of variance 2 x 2 pi linewidth min(t, |tau - tau_LO|). So

        E = e^{-sigma^2} (1 - s_p) + s_p C,   s_p = sum w_p^2 / (sum w_p)^2,
        C = sum_ij v_i v_j exp(-2 pi linewidth min(|i - j| dt, D)) / (sum v)^2,

    which is exp(-sigma^2) (:func:`peak_power_loss`) until that falls to about 1 / pulses.

    Parameters
    ----------
    linewidth : float
        Hz.
    delay_difference : float
        tau - tau_LO, s.
    dt : float
        Fast-time sample spacing, s.
    range_weights : float (n,)
        The weights of a pulse's samples that hold the echo (the range window).
    pulse_weights : float (P,)
        The weights of the pulses (the azimuth window).

    Returns
    -------
    float

    Examples
    --------
    >>> expected_peak_power_loss(0.0, 1e-5, 1e-8, np.ones(100), np.ones(50))
    1.0
    """
    v = np.asarray(range_weights, np.float64)
    w = np.asarray(pulse_weights, np.float64)
    D = abs(float(delay_difference))
    lags = np.arange(v.size) * float(dt)
    corr = np.exp(-2.0 * math.pi * float(linewidth) * np.minimum(lags, D))  # E e^{j(dphi_i - dphi_j)}, |i - j| = k
    auto = np.correlate(v, v, mode="full")[v.size - 1:]  # sum_i v_i v_{i+k}
    C = float((auto[0] * corr[0] + 2.0 * np.sum(auto[1:] * corr[1:])) / v.sum() ** 2)
    s_p = float(np.sum(w ** 2) / w.sum() ** 2)
    return peak_power_loss(linewidth, D) * (1.0 - s_p) + s_p * C


def lo_shift(reference_range: np.ndarray, lo_delay: float | None) -> np.ndarray:
    """Where the LO reads the laser's phase, in the simulator's fast time (relative to the dechirp
    reference delay): t + tau_ref - tau_LO; 0 for an LO matched to the reference (``lo_delay``
    None).

    Parameters
    ----------
    reference_range : float64 (P,)
        Dechirp reference range of each pulse, m.
    lo_delay : float or None
        The LO's delay, s.

    Returns
    -------
    float64 (P,)
    """
    ref = np.asarray(reference_range, np.float64)
    if lo_delay is None:
        return np.zeros_like(ref)
    return 2.0 * ref / SPEED_OF_LIGHT - float(lo_delay)


@dataclass(frozen=True)
class PhaseNoise:
    """Tabulated laser phase noise of a run of pulses (the arguments of
    :func:`salkit.simulate.kernels.simulate_exact`).

    Attributes
    ----------
    dt : float
        Table spacing, s.
    echo_t0 : float
        Time of the echo tables' first sample, s.
    echo : float64 (P, G)
        The path where the echoes read it.
    lo_t0 : float64 (P,)
        Time of each LO table's first sample, s.
    lo : float64 (P, H)
        The path where the LO reads it (the same array as ``echo`` when one path covers both).
    shift : float64 (P,)
        :func:`lo_shift`, s.
    """

    dt: float
    echo_t0: float
    echo: np.ndarray
    lo_t0: np.ndarray
    lo: np.ndarray
    shift: np.ndarray

    def lo_phase(self, i: int, times: np.ndarray) -> np.ndarray:
        """The path of pulse ``i`` (of this run) at ``times`` (s) within its LO window, rad (linear
        interpolation, as the kernel reads it).

        Parameters
        ----------
        i : int
        times : float64 (M,)

        Returns
        -------
        float64 (M,)
        """
        grid = self.lo_t0[i] + self.dt * np.arange(self.lo.shape[1])
        return np.interp(times, grid, self.lo[i])

    def reference_phase(self, fast_time: np.ndarray, reference_delay: float) -> np.ndarray:
        """The phase noise a reference channel of delay D records for each pulse of this run: the
        laser through the reference path against it through a reference LO of the target LO's
        delay, phi(t_LO - D) - phi(t_LO), rad (P, N).

        Parameters
        ----------
        fast_time : float64 (N,)
            s.
        reference_delay : float
            D, s (the window was drawn for it: :func:`phase_noise`'s ``reference_delay``).

        Returns
        -------
        float64 (P, N)
        """
        t = np.asarray(fast_time, np.float64)
        out = np.empty((self.lo.shape[0], t.size))
        for i in range(out.shape[0]):
            at = t + self.shift[i]
            out[i] = self.lo_phase(i, at - reference_delay) - self.lo_phase(i, at)
        return out

    def rows(self, a: int, b: int) -> tuple:
        """The kernel's arguments for pulses ``a`` to ``b`` of this run.

        Parameters
        ----------
        a, b : int

        Returns
        -------
        tuple
        """
        return (self.dt, self.echo_t0, np.ascontiguousarray(self.echo[a:b]), np.ascontiguousarray(self.lo_t0[a:b]),
                np.ascontiguousarray(self.lo[a:b]), np.ascontiguousarray(self.shift[a:b]))


#: The kernel's arguments without phase noise.
NO_PHASE_NOISE = (1.0, 0.0, np.zeros((0, 1)), np.zeros(0), np.zeros((0, 1)), np.zeros(0))


def substeps(dt: float, delay_differences) -> int:
    """Table points a fast-time sample for the phase noise of the given delay differences: a Wiener
    path tabulated at spacing h and read by linear interpolation gives an increment over tau < h
    the variance 2 pi linewidth tau^2 / h instead of tau, so the table resolves the largest delay
    difference in :data:`POINTS_A_DELAY` steps (at most :data:`MAX_SUBSTEPS` a sample).

    Parameters
    ----------
    dt : float
        Fast-time sample spacing, s.
    delay_differences : sequence of float
        The delay differences tau - tau_LO the noise matters at (echoes, reference channel), s.

    Returns
    -------
    int

    Examples
    --------
    >>> substeps(50e-9, [33e-6])
    1
    >>> substeps(50e-9, [10e-9])
    64
    """
    big = max((abs(float(d)) for d in delay_differences), default=0.0)
    if big <= 0.0:
        return 1
    return int(min(MAX_SUBSTEPS, max(1, math.ceil(POINTS_A_DELAY * float(dt) / big))))


#: Table steps over the largest delay difference (:func:`substeps`): an increment's variance low by
#: about h / 3 tau, 2 %.
POINTS_A_DELAY = 16
#: Most table points a fast-time sample.
MAX_SUBSTEPS = 64


def phase_noise(linewidth: float, fast_time: np.ndarray, delays: tuple[float, float], shift: np.ndarray,
                seed: int, pulses: np.ndarray, reference_delay: float = 0.0, steps: int = 1) -> PhaseNoise:
    """Wiener phase-noise paths of the given pulses, tabulated where the echoes and the LO read them.

    Parameters
    ----------
    linewidth : float
        Lorentzian FWHM, Hz (> 0).
    fast_time : float64 (N,)
        Sample times relative to the dechirp reference delay, s (uniform).
    delays : (float, float)
        Smallest and largest delay offset d = tau - tau_ref of the scene's echoes, s.
    shift : float64 (P,)
        :func:`lo_shift` of the pulses, s.
    seed : int
        The scenario's seed.
    pulses : int (P,)
        The pulses' indices in the collection (each draws from its own stream).
    reference_delay : float
        A reference channel's delay D, s: each LO window also covers D before it
        (:meth:`PhaseNoise.reference_phase`); 0 without one (the same draws).
    steps : int
        Table points a fast-time sample (:func:`substeps`).

    Returns
    -------
    PhaseNoise
    """
    t = np.asarray(fast_time, np.float64)
    dt = (float(t[1] - t[0]) if t.size > 1 else 1e-9) / int(steps)
    d0, d1 = float(delays[0]), float(delays[1])
    a0, a1 = t[0] - d1 - 2 * dt, t[-1] - d0 + 2 * dt  # the echoes' window
    shift = np.asarray(shift, np.float64)
    D = float(reference_delay)
    b0, b1 = t[0] + shift - max(D, 0.0) - 2 * dt, t[-1] + shift - min(D, 0.0) + 2 * dt  # each pulse's LO window
    step = math.sqrt(2.0 * math.pi * float(linewidth) * dt)
    length = a1 - a0
    lo0, hi = min(a0, float(b0.min())), max(a1, float(b1.max()))
    P = len(pulses)
    if hi - lo0 <= JOIN * length:  # one path covers both windows
        g = int(math.ceil((hi - lo0) / dt)) + 2
        path = np.empty((P, g))
        for i, p in enumerate(pulses):
            inc = np.random.default_rng([int(seed), STREAM, int(p)]).standard_normal(g) * step
            inc[0] = 0.0
            path[i] = np.cumsum(inc)
        return PhaseNoise(dt, lo0, path, np.full(P, lo0), path, shift)
    ga = int(math.ceil(length / dt)) + 2
    gb = int(math.ceil(float((b1 - b0).max()) / dt)) + 2
    echo, lo = np.empty((P, ga)), np.empty((P, gb))
    for i, p in enumerate(pulses):  # two windows far apart: the first, the increment across the gap, the second
        rng = np.random.default_rng([int(seed), STREAM, int(p)])
        echo_first = a0 <= b0[i]
        (t_first, g_first), (t_second, g_second) = ((a0, ga), (b0[i], gb)) if echo_first else ((b0[i], gb), (a0, ga))
        inc = rng.standard_normal(g_first) * step
        inc[0] = 0.0
        first = np.cumsum(inc)
        gap = max(float(t_second) - (float(t_first) + (g_first - 1) * dt), 0.0)
        inc = rng.standard_normal(g_second) * step
        inc[0] = math.sqrt(2.0 * math.pi * float(linewidth) * gap) * rng.standard_normal()
        second = first[-1] + np.cumsum(inc)
        echo[i], lo[i] = (first, second) if echo_first else (second, first)
    return PhaseNoise(dt, a0, echo, b0.astype(np.float64), lo, shift)
