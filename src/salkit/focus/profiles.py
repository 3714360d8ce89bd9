"""Range profiles for backprojection: the upsampled profiles of a block of pulses, packed for the
kernel, and the interpolations that read them between bins (:data:`INTERPOLATIONS`: linear,
nearest, Keys cubic, and a four-tap kernel fitted to the profile's band), each with its mean
frequency response, divided out of the spectrum before the profiles are formed (the largest part
of an interpolation's error).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.fft as sfft
from numba import njit, prange

from .._blas import serial_blas
from ..constants import FFT_WORKERS, SPEED_OF_LIGHT
from ..errors import ScenarioError

WORKERS = FFT_WORKERS

@njit(parallel=True, nogil=True, cache=True)
def _pack_kernel(prof, out):
    P, nb = prof.shape
    for p in prange(P):
        for b in range(nb - 1):
            z = prof[p, b]
            d = prof[p, b + 1] - z
            out[p, b, 0] = z.real
            out[p, b, 1] = z.imag
            out[p, b, 2] = d.real
            out[p, b, 3] = d.imag
        z = prof[p, nb - 1]
        out[p, nb - 1, 0] = z.real
        out[p, nb - 1, 1] = z.imag
        out[p, nb - 1, 2] = 0.0
        out[p, nb - 1, 3] = 0.0


def pack_profiles(prof: np.ndarray) -> np.ndarray:
    """(P, Nb) complex -> (P, Nb, 4) float32 (re, im, forward differences).

    Parameters
    ----------
    prof : complex64 (P, Nb)
        Range profiles.

    Returns
    -------
    float32 (P, Nb, 4)
        Real part, imaginary part and their forward differences (0 at the last bin), for linear
        interpolation.

    Examples
    --------
    >>> pack_profiles(np.array([[1 + 2j, 3 + 1j]], np.complex64))[0].tolist()
    [[1.0, 2.0, 2.0, -1.0], [3.0, 1.0, 0.0, 0.0]]
    """
    prof = np.ascontiguousarray(prof, np.complex64)
    out = np.empty(prof.shape + (4,), np.float32)
    _pack_kernel(prof, out)
    return out


#: Zero bins before and after each profile in the four-tap kernels' layout (:func:`pad_profiles`,
#: :func:`range_profiles_into`): taps from bin - 1 to bin + 2 stay inside for every bin.
FOUR_TAP_PADDING = (1, 2)


def pad_profiles(prof: np.ndarray) -> np.ndarray:
    """(P, Nb) complex -> (P, 2 (Nb + 3)) float32: interleaved (re, im), one zero bin before and two
    after, so that four taps from bin - 1 to bin + 2 stay inside for every bin.

    Parameters
    ----------
    prof : complex64 (P, Nb)
        Range profiles.

    Returns
    -------
    float32 (P, 2 (Nb + 3))

    Examples
    --------
    >>> pad_profiles(np.array([[1 + 2j]], np.complex64))[0].tolist()
    [0.0, 0.0, 1.0, 2.0, 0.0, 0.0, 0.0, 0.0]
    """
    P, nb = prof.shape
    lead, trail = FOUR_TAP_PADDING
    out = np.zeros((P, lead + nb + trail), np.complex64)
    out[:, lead:lead + nb] = prof
    return out.view(np.float32)


def linear_interp_gain(m: np.ndarray, nfft: int) -> np.ndarray:
    """Mean response of linear interpolation between profile bins to frequency offset ``m``
    (samples from the reference frequency) in an ``nfft``-point profile: sinc^2(m / nfft).

    Linear interpolation of exp(j 2 pi nu x) (nu in cycles per bin), averaged over the position
    between two bins, multiplies it by sinc^2(nu); dividing the spectrum by it beforehand removes
    that mean attenuation of the band's edges, the largest part of the interpolation error (its
    remainder varies with the position: about 8 dB less error energy).

    Parameters
    ----------
    m : int ndarray
        Frequency sample offsets.
    nfft : int
        Profile length.

    Returns
    -------
    float64 ndarray

    Examples
    --------
    >>> float(linear_interp_gain(np.array([0]), 64)[0])
    1.0
    """
    return np.sinc(np.asarray(m, np.float64) / nfft) ** 2


def nearest_interp_gain(m: np.ndarray, nfft: int) -> np.ndarray:
    """Mean response of nearest-bin interpolation to frequency offset ``m`` in an ``nfft``-point
    profile: sinc(m / nfft) (the box kernel's transform).

    Parameters
    ----------
    m : int ndarray
        Frequency sample offsets.
    nfft : int
        Profile length.

    Returns
    -------
    float64 ndarray

    Examples
    --------
    >>> round(float(nearest_interp_gain(np.array([32]), 64)[0]), 4)
    0.6366
    """
    return np.sinc(np.asarray(m, np.float64) / nfft)


def keys_kernel(x: np.ndarray) -> np.ndarray:
    """Keys' cubic convolution kernel (a = -1/2), support |x| < 2 bins.

    Parameters
    ----------
    x : float ndarray
        Offsets, bins.

    Returns
    -------
    float64 ndarray

    Examples
    --------
    >>> keys_kernel(np.array([0.0, 1.0, 2.0])).tolist()
    [1.0, 0.0, 0.0]
    """
    a = np.abs(np.asarray(x, np.float64))
    inner = 1.5 * a ** 3 - 2.5 * a ** 2 + 1.0
    outer = -0.5 * a ** 3 + 2.5 * a ** 2 - 4.0 * a + 2.0
    return np.where(a <= 1.0, inner, np.where(a < 2.0, outer, 0.0))


#: Quadrature of the cubic kernel's transform: samples per bin over its support of 4 bins.
_KEYS_SAMPLES = 2048
_KEYS_X = (np.arange(4 * _KEYS_SAMPLES) + 0.5) / _KEYS_SAMPLES - 2.0
_KEYS_W = keys_kernel(_KEYS_X) / _KEYS_SAMPLES


def cubic_interp_gain(m: np.ndarray, nfft: int) -> np.ndarray:
    """Mean response of Keys' cubic interpolation to frequency offset ``m`` in an ``nfft``-point
    profile: the kernel's Fourier transform at m / nfft cycles per bin (midpoint quadrature,
    2048 points a bin: error below 1e-7).

    Parameters
    ----------
    m : int ndarray
        Frequency sample offsets.
    nfft : int
        Profile length.

    Returns
    -------
    float64 ndarray

    Examples
    --------
    >>> round(float(cubic_interp_gain(np.array([0]), 64)[0]), 6)
    1.0
    """
    nu = np.asarray(m, np.float64).ravel() / nfft
    out = np.cos(2.0 * np.pi * np.outer(nu, _KEYS_X)) @ _KEYS_W
    return out.reshape(np.shape(m))


#: Keys' cubic convolution (a = -1/2) as four taps (bins -1, 0, 1, 2 from the pixel's bin), each
#: weight a cubic in the fraction t: row k holds the coefficients of t^0 .. t^3.
KEYS_COEFFICIENTS = np.array([[0.0, -0.5, 1.0, -0.5], [1.0, 0.0, -2.5, 1.5], [0.0, 0.5, 2.0, -1.5],
                              [0.0, 0.0, -0.5, 0.5]])
#: Offsets of the four taps from the pixel's bin.
TAP_OFFSETS = np.arange(-1, 3)
#: Quadrature of a four-tap kernel's mean response: Gauss-Legendre nodes in t (exact for the
#: polynomial part; the exponential's error below 1e-12 at any band inside Nyquist).
_T_NODES, _T_WEIGHTS = np.polynomial.legendre.leggauss(24)
_T_NODES, _T_WEIGHTS = 0.5 * (_T_NODES + 1.0), 0.5 * _T_WEIGHTS


def _tap_phases(nu, t) -> np.ndarray:
    """exp(j 2 pi nu (k - t)) for the four taps k, fractions t and frequencies nu: complex (4, nt, nnu)."""
    nu = np.asarray(nu, np.float64).ravel()
    t = np.asarray(t, np.float64).ravel()
    return np.exp(2j * np.pi * nu[None, None, :] * (TAP_OFFSETS[:, None, None] - t[None, :, None]))


def taps4_response(coefficients: np.ndarray, nu: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Response of a four-tap kernel to exp(j 2 pi nu x) read at fraction ``t`` past a bin.

    Parameters
    ----------
    coefficients : float (4, 4)
        Tap k's weight is sum_d coefficients[k, d] t^d (taps at bins -1, 0, 1, 2).
    nu : float ndarray
        Frequencies, cycles per bin.
    t : float ndarray
        Fractions in [0, 1).

    Returns
    -------
    complex128 (t.size, nu.size)
        sum_k w_k(t) exp(j 2 pi nu (k - t)): 1 for an exact interpolator.

    Examples
    --------
    >>> r = taps4_response(KEYS_COEFFICIENTS, np.array([0.0, 0.1]), np.array([0.0]))
    >>> np.round(np.abs(r), 6).tolist()
    [[1.0, 1.0]]
    """
    t = np.asarray(t, np.float64).ravel()
    w = np.asarray(coefficients, np.float64) @ np.vander(t, 4, increasing=True).T  # (4, nt)
    return np.einsum("kt,ktn->tn", w, _tap_phases(nu, t))


def taps4_gain(coefficients: np.ndarray, m: np.ndarray, nfft: int) -> np.ndarray:
    """Mean response of a four-tap kernel (:func:`taps4_response` averaged over the fraction) to
    frequency offset ``m`` in an ``nfft``-point profile.

    Parameters
    ----------
    coefficients : float (4, 4)
    m : int ndarray
        Frequency sample offsets.
    nfft : int
        Profile length.

    Returns
    -------
    float64 ndarray
        Real part (the imaginary part of a symmetric kernel's mean is zero).

    Examples
    --------
    >>> m = np.array([0, 40]); np.allclose(taps4_gain(KEYS_COEFFICIENTS, m, 256), cubic_interp_gain(m, 256))
    True
    """
    nu = np.asarray(m, np.float64).ravel() / nfft
    g = _T_WEIGHTS @ taps4_response(coefficients, nu, _T_NODES)
    return g.real.reshape(np.shape(m))


@functools.lru_cache(maxsize=32)
def fitted_coefficients(M: int, nfft: int) -> np.ndarray:
    """The four-tap kernel, each weight a cubic in the fraction, closest in least squares to exact
    interpolation over the band a profile occupies (M of its nfft bins' frequencies: |nu| <= M / 2
    nfft cycles a bin), over all fractions.

    Keys' cubic is fitted to no band; this one is, for each upsampling: at 8 bins a resolution cell
    its error (after its mean response is divided out) is -97.6 dB against Keys' -71.2 dB and
    4-point Lagrange's -84.9 dB (white band, all fractions), at 4 -73 dB, at 16 -122 dB.

    Parameters
    ----------
    M : int
        Frequencies.
    nfft : int
        Profile length.

    Returns
    -------
    float64 (4, 4)
        Row k: coefficients of t^0 .. t^3 of tap k (bins -1, 0, 1, 2), read-only.

    Examples
    --------
    >>> c = fitted_coefficients(100, 800)
    >>> bool(abs(np.vander([0.5], 4, increasing=True) @ c.sum(axis=0) - 1.0)[0] < 1e-3)
    True
    """
    half = 0.5 * M / nfft
    nu = np.linspace(-half, half, 129)
    t = (np.arange(64) + 0.5) / 64.0
    ph = _tap_phases(nu, t)  # (k, t, nu)
    powers = np.vander(t, 4, increasing=True)  # (t, d)
    cols = (ph[:, :, None, :] * powers[None, :, :, None]).transpose(1, 3, 0, 2).reshape(t.size * nu.size, 16)
    a = np.vstack([cols.real, cols.imag])
    b = np.concatenate([np.ones(t.size * nu.size), np.zeros(t.size * nu.size)])
    with serial_blas():  # none of BLAS's threads left spinning beside the kernel (:mod:`salkit._blas`)
        c = np.linalg.lstsq(a, b, rcond=None)[0].reshape(4, 4)
    c.setflags(write=False)
    return c


#: Largest asymmetry :func:`symmetric_coefficients` accepts, relative to the largest coefficient
#: (float32 storage's rounding, 6e-8, with room; the kernels are symmetric by construction).
SYMMETRY_TOLERANCE = 1e-5


def symmetric_coefficients(coefficients: np.ndarray, centre: float) -> np.ndarray:
    """A symmetric kernel's weights as the even and odd parts of its pairs of taps, in u = x - ``centre``.

    A kernel of ``taps`` weights, tap b weighing sum_d c[b, d] x^d at the fraction x, is symmetric
    about ``centre`` when tap ``taps - 1 - b`` at u weighs as tap b at -u. Tap b's weight is then
    E_b(u) + O_b(u) and its mirror's E_b(u) - O_b(u), E_b even and O_b odd in u: each a polynomial
    in u^2, half the multiply-adds of the taps' own polynomials (:mod:`salkit.focus.simd`).

    Parameters
    ----------
    coefficients : float (taps, n)
        Tap b's weight sum_d coefficients[b, d] x^d; ``taps`` even.
    centre : float
        The fraction about which the kernel is symmetric (1/2 for x = t the fraction past a bin,
        0 for x = 2 t - 1).

    Returns
    -------
    float64 (taps // 2 * n,)
        For each pair b = 0 .. taps/2 - 1, n values: E_b's coefficients of u^0, u^2, ..., then
        O_b's of u^1, u^3, ... (symmetrised: each the mean of the pair's two).

    Raises
    ------
    ValueError
        If the kernel is not symmetric about ``centre`` within :data:`SYMMETRY_TOLERANCE` of its
        largest coefficient.

    Examples
    --------
    >>> c = symmetric_coefficients(KEYS_COEFFICIENTS, 0.5)
    >>> u = 0.3 - 0.5
    >>> even, odd = c[0] + c[1] * u ** 2, u * (c[2] + c[3] * u ** 2)
    >>> w0 = np.polynomial.polynomial.polyval(0.3, KEYS_COEFFICIENTS[0])
    >>> bool(abs(even + odd - w0) < 1e-12)
    True
    """
    c = np.asarray(coefficients, np.float64)
    taps, n = c.shape
    if taps % 2:
        raise ValueError(f"coefficients: {taps} taps, must be even")
    # x^d = (u + centre)^d = sum_e comb(d, e) centre^(d - e) u^e
    binomial = np.array([[math.comb(d, e) * centre ** (d - e) if e <= d else 0.0 for e in range(n)]
                         for d in range(n)])
    a = c @ binomial  # coefficients in u
    mirror = a[::-1] * (-1.0) ** np.arange(n)  # tap taps-1-b at u as tap b at -u
    scale = np.abs(a).max()
    asym = np.abs(a - mirror).max()
    if asym > SYMMETRY_TOLERANCE * scale:
        raise ValueError(f"coefficients: kernel not symmetric about {centre}: its mirrored taps differ by "
                         f"{asym:.3g}, more than {SYMMETRY_TOLERANCE:g} of its largest coefficient {scale:.3g}")
    a = 0.5 * (a + mirror)
    return np.concatenate([np.concatenate([a[b, 0::2], a[b, 1::2]]) for b in range(taps // 2)])


def _fitted_gain(m: np.ndarray, nfft: int) -> np.ndarray:
    """The fitted kernel's mean response; ``m`` is all the profile's frequency offsets (as
    :func:`range_profiles` passes them), so its size is the band the kernel is fitted to."""
    return taps4_gain(fitted_coefficients(int(np.size(m)), int(nfft)), m, nfft)


@dataclass(frozen=True)
class Interpolation:
    """How backprojection reads its upsampled range profiles between bins.

    Attributes
    ----------
    name : str
    code : int
        The kernel's mode (:func:`bp_kernel`).
    taps : int
        Profile bins read a pixel.
    gain : callable
        ``gain(m, nfft)``: the interpolation's mean response to frequency offset ``m`` (samples
        from the reference) in an ``nfft``-point profile, divided out of the spectrum beforehand
        (the largest part of the interpolation error).
    coefficients : callable or None
        Four-tap kernels: ``coefficients(M, nfft)``, float (4, 4), tap k's weight sum_d c[k, d] t^d.
    """

    name: str
    code: int
    taps: int
    gain: Callable[[np.ndarray, int], np.ndarray]
    coefficients: Callable[[int, int], np.ndarray] | None = None


#: Interpolations of the profiles, by name: the values of backprojection's ``interpolation``.
INTERPOLATIONS = {i.name: i for i in (Interpolation("linear", 0, 2, linear_interp_gain),
                                      Interpolation("nearest", 1, 1, nearest_interp_gain),
                                      Interpolation("cubic", 2, 4, cubic_interp_gain,
                                                    lambda M, nfft: KEYS_COEFFICIENTS),
                                      Interpolation("fitted", 3, 4, _fitted_gain, fitted_coefficients))}


def interpolation_of(name: str) -> Interpolation:
    """The interpolation ``name`` (:data:`INTERPOLATIONS`).

    Parameters
    ----------
    name : str

    Returns
    -------
    Interpolation

    Raises
    ------
    ScenarioError
        For an unknown name (field ``interpolation``).
    """
    try:
        return INTERPOLATIONS[name]
    except (KeyError, TypeError):
        raise ScenarioError("interpolation", name, f"must be one of {', '.join(INTERPOLATIONS)}") from None


@functools.lru_cache(maxsize=32)
def _compensation(interpolation: str, M: int, nfft: int) -> np.ndarray:
    """The interpolation's mean response over the M frequencies of an nfft-point profile (cached:
    every block of a collection has the same)."""
    g = interpolation_of(interpolation).gain(np.arange(M) - M // 2, nfft)
    g.setflags(write=False)
    return g


def profile_length(n_samples: int, upsample: float) -> int:
    """The FFT length of range profiles upsampled ``upsample`` times: the next fast length from
    ``n_samples * upsample``.

    Parameters
    ----------
    n_samples : int
        Frequencies a pulse.
    upsample : float
        Profile samples per frequency sample (at least).

    Returns
    -------
    int

    Examples
    --------
    >>> profile_length(424, 2.0)
    864
    """
    return sfft.next_fast_len(int(n_samples * upsample))


def profile_sampling(freq: np.ndarray, upsample: float) -> tuple[int, float]:
    """The FFT length and bin spacing of :func:`range_profiles` for ``freq`` and ``upsample``,
    known before any transform (for sizing the work that reads them).

    Parameters
    ----------
    freq : float64 (M,)
        Frequencies, Hz, increasing and uniform.
    upsample : float

    Returns
    -------
    nfft : int
    dr : float
        Bin spacing, m of differential range.
    """
    nfft = profile_length(freq.size, upsample)
    return nfft, SPEED_OF_LIGHT / (2.0 * float(freq[1] - freq[0]) * nfft)


def range_profiles(ph: np.ndarray, freq: np.ndarray, upsample: int, range_window: np.ndarray,
                   linear_compensation: bool = False, interpolation: str = "linear"):
    """Upsampled range profiles of a phase-history block.

    Returns
    -------
    profiles : complex64 (P, Nfft)
    r0 : float
        Differential range of bin 0, m.
    dr : float
        Bin spacing, m.
    f_c : float
        Reference frequency (sample M//2), Hz.

    Parameters
    ----------
    ph : complex (P, M)
        Phase history.
    freq : float64 (M,)
        Frequencies, Hz, increasing and uniform.
    upsample : int
        FFT length over M.
    range_window : float (M,)
        Amplitude window over the frequencies.
    linear_compensation : bool
        Divide the spectrum by the interpolation's mean response (:attr:`Interpolation.gain`;
        :func:`linear_interp_gain` for linear), for profiles read by that interpolation.
    interpolation : {"linear", "nearest", "cubic", "fitted"}
        How the profiles will be read (:data:`INTERPOLATIONS`).
    """
    nfft, _ = profile_sampling(freq, upsample)
    prof = np.empty((ph.shape[0], nfft), np.complex64)  # every bin written by range_profiles_into
    r0, dr, f_c = range_profiles_into(prof, ph, freq, upsample, range_window, linear_compensation, interpolation)
    return prof, r0, dr, f_c


def range_profiles_into(work: np.ndarray, ph: np.ndarray, freq: np.ndarray, upsample: int,
                        range_window: np.ndarray, linear_compensation: bool = False,
                        interpolation: str = "linear", lead: int = 0):
    """:func:`range_profiles` written into the rows of a buffer the caller keeps, bins ``lead`` to
    ``lead + Nfft - 1`` of rows 0 to P - 1 (the transform in place): the backprojection kernel's
    blocks of pulses reuse one buffer, already in the padded layout its four-tap reading needs
    (:func:`pad_profiles`), instead of a new spectrum, profile and padded copy a block. The columns
    outside those bins are not written: zeros stay zeros. The same bits as :func:`range_profiles`.

    Parameters
    ----------
    work : complex64 (>= P, >= lead + Nfft), C-contiguous
        The buffer (:func:`profile_sampling` gives Nfft).
    ph, freq, upsample, range_window, linear_compensation, interpolation
        As :func:`range_profiles`.
    lead : int
        Columns before bin 0.

    Returns
    -------
    (r0, dr, f_c) : (float, float, float)
        :func:`range_profiles`' last three: bin 0's differential range (m), the bin spacing (m)
        and the reference frequency (Hz).

    Examples
    --------
    >>> f = 1e10 + np.arange(8) * 1e6
    >>> work = np.zeros((1, 1 + 16 + 2), np.complex64)
    >>> _ = range_profiles_into(work, np.ones((1, 8)), f, 2, np.ones(8), lead=1)
    >>> bool(np.array_equal(work[:, 1:17], range_profiles(np.ones((1, 8)), f, 2, np.ones(8))[0]))
    True
    """
    P, M = ph.shape
    nfft, dr = profile_sampling(freq, upsample)
    if (work.dtype != np.complex64 or work.ndim != 2 or work.shape[0] < P or work.shape[1] < lead + nfft
            or not work.flags.c_contiguous):
        raise ValueError(f"work: complex64, C-contiguous, at least ({P}, {lead + nfft}) needed; got "
                         f"{work.dtype} {work.shape}")
    h = M // 2
    # sample m goes to bin k = (m - h) mod nfft; the ramp exp(-j 2 pi k s / nfft), s = nfft // 2,
    # does the fftshift inside the transform (no scatter with an index array, no shifted copy)
    k = (np.arange(M) - h) % nfft
    wr = np.asarray(range_window, np.float64)
    if linear_compensation:
        wr = wr / _compensation(interpolation, M, nfft)
    ramp = (np.exp(-2j * np.pi * ((k * (nfft // 2)) % nfft) / nfft) * wr).astype(np.complex64)
    buf = work[:P, lead:lead + nfft]
    np.multiply(ph[:, h:], ramp[h:], out=buf[:, :M - h])
    buf[:, M - h:nfft - h] = 0
    np.multiply(ph[:, :h], ramp[:h], out=buf[:, nfft - h:])
    prof = sfft.ifft(buf, axis=1, workers=WORKERS, norm="forward", overwrite_x=True)
    if not np.shares_memory(prof, buf):  # pocketfft wrote elsewhere
        buf[...] = prof
    r0 = -(nfft // 2) * dr
    return r0, dr, float(freq[M // 2])
