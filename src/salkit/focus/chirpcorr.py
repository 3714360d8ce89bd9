"""Nonlinear-chirp corrections from a reference channel (seed 002 and established methods).

The transmitted phase is Phi(t) = 2 pi (f0 t + k t^2 / 2) + e(t), with e the nonlinear part. A
dechirped channel with differential delay D (echo minus LO) carries
Phi(t - D) - Phi(t) = -2 pi (f0 + k t) D + pi k D^2 + [e(t - D) - e(t)]. A reference channel
(a delay line of known D_r) measures the bracket at D_r, from which

* :func:`estimate_nonlinear_phase` recovers e(t) (least squares on a polynomial basis);
* :func:`correct_deskew` (Meta, Hoogeboom & Ligthart 2007) removes it for every range at once:
  multiply by exp(+j e(t)), deskew (exp(-j pi f^2 / k), which moves each echo's e(t - D) to
  e(t) and removes the RVP), multiply by exp(-j e(t));
* :func:`correct_resample` resamples each pulse to uniform optical frequency (the auxiliary-
  interferometer method): exact to first order in D, leaving the small D^2 e''/2 term;
* :func:`remove_reference_noise` removes the laser's phase noise: with a finite linewidth the
  reference records, pulse by pulse, the noise phi(t - D_r) - phi(t) its delay sees, which is the
  target channel's for an echo of the same delay (:mod:`salkit.simulate.linewidth`);
* :func:`correct_paper` is seed 002's method for one target delay D_z: the reference phase's
  Fourier coefficients are mapped to D_z with the phase-shift formula (eq 7) and the target
  channel is multiplied by the conjugate (the spectral convolution of eqs 15-18).
"""
from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

from ..errors import SalkitError
from .dechirp import deskew

from ..signals.chirp import TWO_PI, nonlinear_phase, reference_beat  # noqa: F401  (re-exported)
from .interp import resample_rows


class PhaseUnwrapError(SalkitError):
    """The reference beat is too weak or too fast to unwrap reliably."""


def _basis(t: np.ndarray, order: int, delay: float, scale: float) -> np.ndarray:
    """Columns ((t - D)^n - t^n) / scale^n for n = 2 .. order (normalised time)."""
    u, v = t / scale, (t - delay) / scale
    return np.stack([v ** n - u ** n for n in range(2, order + 1)], axis=1)


def estimate_nonlinear_phase(ref: np.ndarray, t: np.ndarray, f0: float, k: float, delay: float,
                             order: int = 8, min_snr_check: float = 0.25, method: str = "poly",
                             bandwidth: float = 10e6) -> np.ndarray:
    """Estimate e(t) (rad, on ``t``) from a reference beat at known delay ``delay``.

    The unwrapped reference phase minus its linear-chirp model is e(t - D) - e(t); e is fitted as
    sum_n a_n (t / T)^n, n = 2 .. ``order`` (constant and linear terms are unobservable and
    irrelevant), by least squares on ((t - D)^n - t^n). ``method="fourier"`` then also solves the
    residual e(t - D) - e(t) = r(t) in the Fourier domain (regularised below one cycle per pulse),
    for arbitrary (measured or random) chirp errors, keeping frequencies up to ``bandwidth`` (Hz).

    Raises
    ------
    PhaseUnwrapError
        When the reference is too noisy to unwrap (phase steps beyond pi/2 RMS or a fit residual
        above ``min_snr_check`` rad RMS).

    Parameters
    ----------
    ref : complex (N,)
        Dechirped reference-channel beat.
    t : float64 (N,)
        Fast time, s.
    f0 : float
        Optical frequency at t = 0, Hz.
    k : float
        Chirp rate, Hz/s.
    delay : float
        Reference delay D, s.
    order : int
        Highest polynomial order.
    min_snr_check : bool
        Refuse a reference whose phase cannot be unwrapped.
    method : {"polynomial", "fourier"}
    bandwidth : float, optional
        Highest frequency of the error kept by ``fourier``, Hz.

    Returns
    -------
    float64 (N,)
        e(t), rad.
    """
    if delay == 0:
        raise PhaseUnwrapError("the reference delay equals the LO delay (zero-length reference): "
                               "it carries no information about the chirp")
    ph = np.unwrap(np.angle(ref))
    steps = np.diff(ph)
    lin = -TWO_PI * (f0 + k * t) * delay + math.pi * k * delay ** 2
    z = ph - lin
    z -= z.mean()
    dstep = np.diff(z)
    if np.sqrt(np.mean((dstep - np.median(dstep)) ** 2)) > math.pi / 2:
        raise PhaseUnwrapError(f"reference phase steps have {np.std(steps):.3g} rad RMS: too weak to unwrap")
    scale = float(np.max(np.abs(t)))
    A = _basis(t, order, delay, scale)
    A = np.c_[A, np.ones_like(t)]
    coef, *_ = np.linalg.lstsq(A, z, rcond=None)
    resid = z - A @ coef
    if method == "poly" and np.sqrt(np.mean(resid ** 2)) > min_snr_check:
        raise PhaseUnwrapError(f"reference phase fit residual {np.sqrt(np.mean(resid ** 2)):.3g} rad RMS: "
                               "the reference is too weak (or the delay too short) to estimate the chirp")
    u = t / scale
    e = sum(c * u ** n for c, n in zip(coef[:-1], range(2, order + 1)))
    if method == "fourier":  # an arbitrary error: solve e(t - D) - e(t) = r(t) for the residual
        n = t.size
        f = sfft.fftfreq(2 * n, t[1] - t[0])
        H = np.exp(-1j * TWO_PI * f * delay) - 1.0
        eps = (TWO_PI * delay / (t[-1] - t[0])) ** 2  # regularise below one cycle per pulse
        R = sfft.fft(np.r_[resid, resid[::-1]])  # even extension: no jump at the ends
        # below the first zero of H (f = 1/D) and within the error's assumed bandwidth
        keep = (np.abs(f) < 0.5 / abs(delay)) & (np.abs(f) <= bandwidth)
        er = np.real(sfft.ifft(np.where(keep, R * np.conj(H) / (np.abs(H) ** 2 + eps), 0.0)))[:n]
        e = e + er - np.polyval(np.polyfit(t, er, 1), t)
    return e


def reference_phase(ref: np.ndarray, t: np.ndarray, f0: float, k: float, delay: float) -> np.ndarray:
    """The measured phase of each pulse's reference beat less its linear-chirp model,
    unwrapped along fast time, rad: e(t - D) - e(t) plus the laser's phase noise phi(t - D) - phi(t)
    (up to a whole number of cycles, which no correction sees).

    Parameters
    ----------
    ref : complex (P, N)
        Dechirped reference beat of each pulse.
    t : float64 (N,)
        Fast time, s.
    f0 : float
        Optical frequency at t = 0, Hz.
    k : float
        Chirp rate, Hz/s.
    delay : float
        Reference delay D, s.

    Returns
    -------
    float64 (P, N)

    Raises
    ------
    PhaseUnwrapError
        When a pulse's phase steps exceed pi/2 RMS (too weak or too fast to unwrap).
    """
    model = reference_beat(t, f0, k, (), delay)  # the linear chirp's beat (its phase reduced in cycles)
    z = np.angle(np.asarray(ref) * np.conj(model)[None, :])  # the slow part, then unwrapped
    z = np.unwrap(z, axis=1)
    steps = np.diff(z, axis=1)
    rms = np.sqrt(np.mean((steps - np.median(steps, axis=1, keepdims=True)) ** 2, axis=1))
    if rms.size and float(rms.max()) > math.pi / 2:
        raise PhaseUnwrapError(f"reference phase steps of pulse {int(np.argmax(rms))} have {float(rms.max()):.3g} rad "
                               "RMS: too weak to unwrap")
    return z


def remove_reference_noise(signal: np.ndarray, ref: np.ndarray, t: np.ndarray, f0: float, k: float,
                           delay: float) -> tuple[np.ndarray, np.ndarray]:
    """Remove the laser's phase noise the reference channel recorded, pulse by pulse.

    Each pulse's reference phase (:func:`reference_phase`) less its mean over the pulses given
    (the chirp's deterministic part, e(t - D) - e(t), and a pedestal common to all pulses) is the
    phase noise of that pulse at the reference delay; the target channel is multiplied by its
    conjugate. An echo whose delay difference equals D loses its noise; one of delay difference
    tau keeps phi(t - tau) - phi(t - D), of variance 2 pi linewidth |tau - D|. The mean reference
    beat is returned for the chirp corrections (:func:`estimate_nonlinear_phase`).

    Parameters
    ----------
    signal : complex (P, N)
        Dechirped target channel.
    ref : complex (P, N)
        Its reference channel, one beat a pulse.
    t : float64 (N,)
        Fast time, s.
    f0, k : float
        Optical frequency at t = 0 (Hz), chirp rate (Hz/s).
    delay : float
        Reference delay D, s.

    Returns
    -------
    (complex64 (P, N), complex128 (N,))
        The corrected signal, and the reference beat without the noise (the pulses' mean phase).
    """
    z = reference_phase(ref, t, f0, k, delay)
    mean = z.mean(axis=0)
    out = (np.asarray(signal) * np.exp(-1j * (z - mean[None, :]))).astype(np.complex64)
    return out, reference_beat(t, f0, k, (), delay) * np.exp(1j * mean)


def correct_deskew(signal: np.ndarray, e: np.ndarray, adc_rate: float, k: float) -> np.ndarray:
    """Meta et al. 2007: exp(+j e) -> deskew (RVP removal) -> exp(-j e). Returns RVP-free data.

    Parameters
    ----------
    signal : complex (P, N)
        Dechirped target channel.
    e : float64 (N,)
        Nonlinear phase e(t), rad.
    adc_rate : float
        Hz.
    k : float
        Chirp rate, Hz/s.

    Returns
    -------
    complex64 (P, N)
    """
    w = np.exp(1j * e).astype(np.complex64)
    return (deskew(signal * w[None, :], adc_rate, k) * np.conj(w)[None, :]).astype(np.complex64)


def correct_resample(signal: np.ndarray, e: np.ndarray, t: np.ndarray, k: float) -> np.ndarray:
    """Resample each pulse to uniform optical frequency nu(t) = f0 + k t + e'(t) / 2 pi.

    The target sample at linear-sweep time t_lin is taken where nu(t) = f0 + k t_lin (sinc
    interpolation of the oversampled beat). First order in the delay; RVP is not removed.

    Parameters
    ----------
    signal : complex (P, N)
        Dechirped target channel.
    e : float64 (N,)
        Nonlinear phase e(t), rad.
    t : float64 (N,)
        Fast time, s.
    k : float
        Chirp rate, Hz/s.

    Returns
    -------
    complex64 (P, N)
    """
    de = np.gradient(e, t) / TWO_PI  # Hz
    nu = k * t + de  # optical frequency offset from f0
    if np.any(np.diff(nu) <= 0):
        raise SalkitError("the optical frequency is not monotonic over the pulse: cannot resample")
    want = k * t
    tpos = np.interp(want, nu, t)  # times at which the sweep reaches the linear frequencies
    dt = t[1] - t[0]
    pos = (tpos - t[0]) / dt
    return resample_rows(signal, np.broadcast_to(pos, signal.shape).copy(), half=8)


def paper_transfer(n: int, dfreq: float, delay_target: tuple[float, float],
                   delay_reference: tuple[float, float]) -> np.ndarray:
    """Seed 002 eq 7: H_m = exp(-i pi m (tzLo + tz) df) sin(pi m (tzLo - tz) df) /
    [exp(-i pi m (trLo + tr) df) sin(pi m (trLo - tr) df)], m the DFT index (signed).

    Parameters
    ----------
    n : int
        DFT length.
    dfreq : float
        DFT bin spacing, Hz.
    delay_target : (float, float)
        (tz, tzLo), s.
    delay_reference : (float, float)
        (tr, trLo), s.

    Returns
    -------
    complex128 (n,)
    """
    m = sfft.fftfreq(n, 1.0 / n)
    tz, tzlo = delay_target
    tr, trlo = delay_reference
    num = np.exp(-1j * math.pi * m * (tzlo + tz) * dfreq) * np.sin(math.pi * m * (tzlo - tz) * dfreq)
    den = np.exp(-1j * math.pi * m * (trlo + tr) * dfreq) * np.sin(math.pi * m * (trlo - tr) * dfreq)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = np.where(np.abs(den) > 1e-12, num / den, (tzlo - tz) / (trlo - tr))
    return h


def correct_paper(signal: np.ndarray, ref: np.ndarray, t: np.ndarray, adc_rate: float,
                  delay_target: tuple[float, float], delay_reference: tuple[float, float]) -> np.ndarray:
    """Seed 002's method for one target delay (as written): unwrap the reference beat phase, DFT,
    map to the target delays with eq 7 (df = adc_rate / N), inverse DFT, and multiply the target
    channel by the conjugate signal exp(-j zeta_zz(t)) (the spectral convolution of eq 15-18).
    Only the target at ``delay_target`` is matched; the beat moves to near zero frequency.

    Parameters
    ----------
    signal : complex (P, N)
        Dechirped target channel.
    ref : complex (N,)
        Reference beat.
    t : float64 (N,)
        Fast time, s.
    adc_rate : float
        Hz.
    delay_target, delay_reference : (float, float)
        As :func:`paper_transfer`, s.

    Returns
    -------
    complex64 (P, N)
    """
    n = t.size
    zeta = np.unwrap(np.angle(ref))
    Z = sfft.fft(zeta)
    H = paper_transfer(n, adc_rate / n, delay_target, delay_reference)  # df: the DFT bin spacing
    zz = np.real(sfft.ifft(Z * H))
    return (signal * np.exp(-1j * zz)[None, :]).astype(np.complex64)


def spectral_width(profile: np.ndarray, df: float, level_db: float = -3.0) -> float:
    """Width (Hz) of a power spectrum's main peak at ``level_db`` (the seed's figure of merit).

    Parameters
    ----------
    profile : complex or float (N,)
        Spectrum (amplitude).
    df : float
        Bin spacing, Hz.
    level_db : float
        Level below the peak, dB (negative).

    Returns
    -------
    float
        Hz.
    """
    p = np.abs(profile) ** 2
    i = int(np.argmax(p))
    thr = p[i] * 10 ** (level_db / 10)
    lo = i
    while lo > 0 and p[lo - 1] >= thr:
        lo -= 1
    hi = i
    while hi < p.size - 1 and p[hi + 1] >= thr:
        hi += 1
    return (hi - lo + 1) * df
