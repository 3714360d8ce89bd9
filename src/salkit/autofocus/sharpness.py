"""Per-pulse autofocus by maximum image sharpness (Ash, "An autofocus method for backprojection
imagery in synthetic aperture radar", IEEE GRSL 9(1), 2012), on arrays.

The image over a set of pixels is linear in one complex weight per pulse: I = sum_n a_n b_n,
with b_n what pulse n backprojects onto the pixels. With a_n = exp(j theta_n) and the other pulses
held, |I|^2 = alpha + Re(beta exp(j theta)) per pixel (alpha = |r|^2 + |b_n|^2, beta = 2 conj(r) b_n,
r = I - a_n b_n), so the sharpness S = sum |I|^4 is a trigonometric polynomial of order two in
theta_n:

    S(theta) = C + Re(A exp(j theta)) + Re(Q exp(2 j theta)),  A = 2 sum alpha beta,  Q = sum beta^2 / 2.

Coordinate ascent sets each theta_n to the global maximum of that polynomial in turn (a coarse
scan of 64 angles refined by Newton steps), so S never decreases. Any phase per pulse, white or
smooth, is within reach: nothing assumes a low-order error.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit, prange


@dataclass
class PulseAutofocusResult:
    """Per-pulse phase correction (rad) and the sharpness after each sweep."""

    phase: np.ndarray
    history: list = field(default_factory=list)
    converged: bool = False
    n_pixels: int = 0


@njit(cache=True, fastmath=True)
def _best_angle(A, Q):
    """argmax over theta of Re(A e^{j theta}) + Re(Q e^{2 j theta})."""
    best, tb = -1e300, 0.0
    n = 64
    for i in range(n):
        t = 2.0 * math.pi * i / n
        v = (A * complex(math.cos(t), math.sin(t))).real + (Q * complex(math.cos(2 * t), math.sin(2 * t))).real
        if v > best:
            best, tb = v, t
    t = tb
    for _ in range(6):  # Newton on dS/dtheta
        e1 = complex(math.cos(t), math.sin(t))
        e2 = e1 * e1
        d1 = -(A * e1).imag - 2.0 * (Q * e2).imag
        d2 = -(A * e1).real - 4.0 * (Q * e2).real
        if d2 >= 0.0:
            break
        t = t - d1 / d2
    return t


@njit(cache=True, fastmath=True)
def _sweep(B, a, I):
    """One coordinate-ascent sweep over all pulses; B (P, K) complex64, a (P,), I (K,) in place."""
    P, K = B.shape
    for n in range(P):
        an = a[n]
        A = 0.0 + 0.0j
        Q = 0.0 + 0.0j
        for k in range(K):
            b = complex(B[n, k].real, B[n, k].imag)
            r = I[k] - an * b
            alpha = r.real * r.real + r.imag * r.imag + b.real * b.real + b.imag * b.imag
            beta = 2.0 * (r.conjugate() * b)
            A += 2.0 * alpha * beta
            Q += 0.5 * beta * beta
        t = _best_angle(A, Q)
        new = complex(math.cos(t), math.sin(t))
        for k in range(K):
            b = complex(B[n, k].real, B[n, k].imag)
            I[k] += (new - an) * b
        a[n] = new


#: Pixels a thread sums at once in :func:`_image` (their float64 sums stay in cache).
IMAGE_CHUNK = 2048


@njit(parallel=True, cache=True)
def _image(B, a):
    """I_k = sum_n a_n B[n, k] in complex128, B read once as it is (complex64: no float64 copy of
    what can be gigabytes)."""
    P, K = B.shape
    out = np.empty(K, np.complex128)
    for c in prange((K + IMAGE_CHUNK - 1) // IMAGE_CHUNK):
        k0 = c * IMAGE_CHUNK
        k1 = min(k0 + IMAGE_CHUNK, K)
        sr = np.zeros(k1 - k0)
        si = np.zeros(k1 - k0)
        for n in range(P):
            ar = a[n].real
            ai = a[n].imag
            row = B[n, k0:k1]
            for k in range(k1 - k0):
                br = np.float64(row[k].real)
                bi = np.float64(row[k].imag)
                sr[k] += ar * br - ai * bi
                si[k] += ar * bi + ai * br
        for k in range(k1 - k0):
            out[k0 + k] = complex(sr[k], si[k])
    return out


def sharpness(image: np.ndarray) -> float:
    """Image sharpness sum |I|^4 / (sum |I|^2)^2 (dimensionless; larger is sharper).

    Parameters
    ----------
    image : complex ndarray

    Returns
    -------
    float

    Examples
    --------
    >>> sharpness(np.array([1.0, 0, 0, 0]))  # all power in one pixel
    1.0
    """
    p = np.abs(image).astype(np.float64) ** 2
    s = p.sum()
    return float((p ** 2).sum() / s ** 2) if s > 0 else 0.0


def pulse_sharpness(contributions: np.ndarray, max_sweeps: int = 10, tol: float = 1e-3,
                    initial: np.ndarray | None = None) -> PulseAutofocusResult:
    """Maximise the sharpness of sum_n exp(j theta_n) b_n over one phase per pulse.

    Parameters
    ----------
    contributions : complex (P, K)
        b_n over K pixels (:func:`salkit.focus.bp_kernel.pulse_contributions`).
    max_sweeps : int
        Coordinate-ascent sweeps over all pulses at most.
    tol : float
        Stop when the RMS change of the phases in a sweep (rad) falls below ``tol``.
    initial : float (P,), optional
        Starting phases, rad (default zero).

    Returns
    -------
    PulseAutofocusResult
        ``phase`` (rad, per pulse) multiplies pulse n by exp(j phase_n), with its circular mean
        removed. Sharpness cannot see a linear phase either (an azimuth shift of the image): the
        error it removes is -phase up to a constant and a linear term.
    """
    B = np.ascontiguousarray(contributions, dtype=np.complex64)
    P, K = B.shape
    th = np.zeros(P) if initial is None else np.asarray(initial, np.float64).copy()
    a = np.exp(1j * th)
    I = _image(B, a)
    hist = [{"iteration": 0, "sharpness": sharpness(I), "phase_change_rms": 0.0}]
    converged = False
    for it in range(1, max_sweeps + 1):
        prev = np.angle(a)
        I = _image(B, a)  # fresh each sweep: no drift
        _sweep(B, a, I)
        a /= np.abs(a)
        d = np.angle(a * np.exp(-1j * prev))
        ch = float(np.sqrt(np.mean((d - d.mean()) ** 2)))
        hist.append({"iteration": it, "sharpness": sharpness(I), "phase_change_rms": ch})
        if ch < tol:
            converged = True
            break
    z = a * np.conj(a.sum()) / max(abs(a.sum()), 1e-300)  # constant phase removed
    phi = np.unwrap(np.angle(z))
    return PulseAutofocusResult(phase=phi, history=hist, converged=converged, n_pixels=K)


__all__ = ["PulseAutofocusResult", "pulse_sharpness", "sharpness"]
