"""Phase gradient autofocus (Wahl, Eichel, Ghiglia & Jakowatz, IEEE TAES 30(3), 1994) and
minimum-entropy autofocus, on arrays.

Convention: ``image`` is (n_azimuth, n_range) complex with the azimuth phase error common to all
range lines; ``fft(image, axis=0)`` is the azimuth phase-history domain, where the error is a
multiplicative exp(j phi(k)). The caller removes the image's deterministic phase first
(:func:`salkit.autofocus.autofocus` does), so that this transform really is the aperture domain.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft

from ..metrics.image import entropy

from ..choices import PGA_KERNELS as KERNELS  # noqa: E402
from ..constants import FFT_WORKERS
from numpy.polynomial import legendre
import lazy_loader as _lazy
_scipy_optimize = _lazy.load("scipy.optimize", suppress_warning=True)


@dataclass
class AutofocusResult:
    """Corrected image, total phase correction and per-iteration history."""

    image: np.ndarray
    phase: np.ndarray  # total correction applied in the phase-history domain (rad), FFT order
    history: list = field(default_factory=list)
    converged: bool = False
    best_iteration: int = 0


def _spectrum_and_band(image: np.ndarray, band):
    """Azimuth spectrum of ``image`` and the bins carrying signal (above 1e-3 of the peak of the
    range-summed power) unless ``band`` is given."""
    img = np.asarray(image, dtype=np.complex128)
    spec = sfft.fft(img, axis=0, workers=FFT_WORKERS)
    if band is None:
        p = np.sum(np.abs(spec) ** 2, axis=1)
        band = p > 1e-3 * p.max()
    return img, spec, band


def _detrend(phi: np.ndarray, weight: np.ndarray | None = None) -> np.ndarray:
    """Remove the (weighted) least-squares constant and linear terms."""
    n = phi.size
    k = np.arange(n) - (n - 1) / 2
    w = np.ones(n) if weight is None else weight
    A = np.stack([np.ones(n), k], axis=1) * w[:, None]
    coef, *_ = np.linalg.lstsq(A, phi * w, rcond=None)
    return phi - coef[0] - coef[1] * k


def _centre_shift(img: np.ndarray) -> np.ndarray:
    n = img.shape[0]
    peak = np.argmax(np.abs(img), axis=0)
    rows = (np.arange(n)[:, None] + peak[None, :] - n // 2) % n
    return np.take_along_axis(img, rows, axis=0)


def _window_width(shifted: np.ndarray, previous: int, floor: int) -> int:
    """Window for the next PGA iteration.

    From the centred intensity of the strongest quarter of range lines (by peak-to-mean ratio),
    twice the distance of the farthest sample within 15 dB of the peak (so the paired echoes of a
    high-frequency error stay inside), shrinking at most by half per iteration and never growing.
    """
    a = np.abs(shifted) ** 2
    ratio = a.max(axis=0) / np.maximum(a.mean(axis=0), 1e-300)
    keep = ratio >= np.quantile(ratio, 0.75)
    prof = a[:, keep].sum(axis=1)
    n = prof.size
    c = n // 2
    above = np.flatnonzero(prof >= prof[c] * 10 ** (-1.5))
    reach = int(np.max(np.abs(above - c))) if above.size else 1
    width = 2 * reach + 3
    return int(max(floor, min(previous, max(width, previous // 2))))


def estimate_phase(G: np.ndarray, kernel: str = "lumv", ev_iter: int = 30) -> np.ndarray:
    """Phase-error estimate (rad, per phase-history bin) from range lines G (n_k, n_lines).

    ``pd``: phase difference, arg sum_j G_k G*_(k-1), integrated.
    ``lumv``: linear unbiased minimum variance, sum_j Im(G*_k dG_k) / sum_j |G_k|^2, integrated.
    ``ev``: eigenvector maximum likelihood, phase of the principal eigenvector of sum_j G_j G_j^H
    (power iteration).

    Parameters
    ----------
    G : complex (n_k, n_lines)
        Range lines in the phase-history domain.
    kernel : {"pd", "lumv", "ev"}
    ev_iter : int
        Power iterations of ``ev``.

    Returns
    -------
    float64 (n_k,)
        rad.
    """
    if kernel == "pd":
        d = np.angle(np.sum(G[1:] * np.conj(G[:-1]), axis=1))
        return np.concatenate([[0.0], np.cumsum(d)])
    if kernel == "lumv":
        dG = np.diff(G, axis=0)
        Gm = 0.5 * (G[1:] + G[:-1])
        num = np.sum(np.imag(np.conj(Gm) * dG), axis=1)
        den = np.sum(np.abs(Gm) ** 2, axis=1)
        d = num / np.maximum(den, 1e-30)
        return np.concatenate([[0.0], np.cumsum(d)])
    if kernel == "ev":
        v = np.exp(1j * estimate_phase(G, "pd"))  # start from the PD estimate
        for _ in range(ev_iter):
            v = G @ (np.conj(G).T @ v)
            v /= np.linalg.norm(v)
        return np.unwrap(np.angle(v))
    raise ValueError(f"kernel must be one of {KERNELS}")


def pga(image: np.ndarray, kernel: str = "lumv", max_iter: int = 30, tol: float = 0.01,
        min_window: int = 5, band: np.ndarray | None = None) -> AutofocusResult:
    """Phase gradient autofocus.

    Parameters
    ----------
    image : complex (n_az, n_rg)
    kernel : {"pd", "lumv", "ev"}
    max_iter : int
    tol : float
        Stop when the RMS of an iteration's (detrended) correction is below ``tol`` rad.
    min_window : int
        Smallest window, azimuth samples.
    band : bool array (n_az,), optional
        Phase-history bins that carry signal (FFT order); the estimate is detrended over them and
        applied only there. Default: bins above 1e-3 of the peak of the range-summed spectrum.

    Returns
    -------
    AutofocusResult
        The lowest-entropy iterate (iteration 0 is the input), so it never ends worse.
    """
    img, spec, band = _spectrum_and_band(image, band)
    n = img.shape[0]
    total = np.zeros(n)
    e0 = entropy(img)
    history = [{"iteration": 0, "phase_rms": 0.0, "entropy": e0, "window": n}]
    best = (e0, 0, img, total.copy())
    width = n
    converged = False
    for it in range(1, max_iter + 1):
        shifted = _centre_shift(img)
        width = _window_width(shifted, width, min_window)
        win = np.zeros(n)
        c = n // 2
        win[max(c - width // 2, 0):min(c + width // 2 + 1, n)] = 1.0
        windowed = shifted * win[:, None]
        # weight range lines by dominance: the share of their windowed energy in the centred peak;
        # lines holding several comparable scatterers bias the gradient and get little weight
        e_line = np.sum(np.abs(windowed) ** 2, axis=0)
        dom = np.abs(windowed[n // 2]) ** 2 / np.maximum(e_line, 1e-300)
        windowed = windowed * dom[None, :]
        G = sfft.fft(sfft.ifftshift(windowed, axes=0), axis=0, workers=FFT_WORKERS)
        # estimate over the contiguous band (in centred order so it does not wrap)
        bc = sfft.fftshift(band)
        sel = np.flatnonzero(bc)
        Gc = sfft.fftshift(G, axes=0)[sel]
        est = estimate_phase(Gc, kernel)
        est = _detrend(est)
        phic = np.zeros(n)
        phic[sel] = est
        phi = sfft.ifftshift(phic)
        rms = float(np.sqrt(np.mean(est ** 2)))
        total += phi
        spec = sfft.fft(img, axis=0, workers=FFT_WORKERS) * np.exp(-1j * phi)[:, None]
        img = sfft.ifft(spec, axis=0, workers=FFT_WORKERS)
        e = entropy(img)
        history.append({"iteration": it, "phase_rms": rms, "entropy": e, "window": width})
        if e < best[0]:
            best = (e, it, img, total.copy())
        if rms < tol:
            converged = True
            break
    return AutofocusResult(image=best[2], phase=best[3], history=history, converged=converged,
                           best_iteration=best[1])


def min_entropy(image: np.ndarray, order: int | None = None, band: np.ndarray | None = None,
                max_iter: int = 200, init: str = "pga") -> AutofocusResult:
    """Minimum-entropy autofocus, started from PGA and refined coarse to fine.

    Entropy has local minima that a start from zero phase cannot leave once the error exceeds a
    few radians. So the search starts from the PGA estimate (``init="pga"``; ``"zero"`` for the
    plain search) and refines it with Legendre phases of orders 4, 8, 16, ... up to ``order``
    (default: a quarter of the band, at least 24), each started where the previous one ended,
    then with a free phase per bin. The lowest-entropy result is returned, so it is never worse in
    entropy than PGA nor than its input.

    Parameters
    ----------
    image : complex (n_az, n_rg)
        Image, deterministic phase removed (see :func:`pga`).
    order : int, optional
        Highest Legendre order of the coarse-to-fine stages.
    band : bool array (n_az,), optional
        Phase-history bins carrying signal (FFT order).
    max_iter : int
        L-BFGS iterations per stage at most.
    init : {"pga", "zero"}
        Starting estimate.

    Returns
    -------
    AutofocusResult
        ``phase`` is the total correction (rad, FFT order); ``history`` the entropy of the input,
        of the start and of each stage.
    """
    img0, _, band = _spectrum_and_band(image, band)
    e0 = entropy(img0)
    n = img0.shape[0]
    nsel = int(band.sum())
    if init == "pga":
        start = pga(img0, band=band)
        total, img = start.phase.copy(), start.image
    else:
        total, img = np.zeros(n), img0
    top = order if order is not None else max(24, nsel // 4)
    orders = [o for o in (4, 8, 16, 32, 64, 128, 256) if o < top] + [top, None]
    history = [{"iteration": 0, "phase_rms": 0.0, "entropy": e0, "stage": "input"},
               {"iteration": 1, "phase_rms": float(np.sqrt(np.mean(total[band] ** 2))), "entropy": entropy(img),
                "stage": init}]
    best = (history[-1]["entropy"], img, total.copy(), 1)
    for o in orders:
        r = _min_entropy_stage(img, o, band, max_iter)
        if r.best_iteration == 1:
            img, total = r.image, total + r.phase
        history.append({"iteration": len(history), "phase_rms": float(np.sqrt(np.mean(total[band] ** 2))),
                        "entropy": entropy(img), "stage": f"order {o}" if o else "bins"})
        if history[-1]["entropy"] < best[0]:
            best = (history[-1]["entropy"], img, total.copy(), len(history) - 1)
    if best[0] > e0:  # never worse than the input
        return AutofocusResult(image=img0, phase=np.zeros(n), history=history, converged=True)
    return AutofocusResult(image=best[1], phase=best[2], history=history, converged=True,
                           best_iteration=best[3])


def _min_entropy_stage(image: np.ndarray, order: int | None = 24, band: np.ndarray | None = None,
                       max_iter: int = 200) -> AutofocusResult:
    """Minimum-entropy autofocus: a Legendre-polynomial phase (orders 2..``order``, default 24:
    enough for ~5 cycles of error across the aperture) over the
    phase-history band minimising the image entropy, by L-BFGS with the analytic gradient
    dE/dphi_k = -(2/N) sum_lines Im(H_k conj(FFT(w I)_k)), w = -(ln(|I|^2/S) + 1)/S."""

    img0, G, band = _spectrum_and_band(image, band)
    n = img0.shape[0]
    bc = sfft.fftshift(band)
    sel = np.flatnonzero(bc)
    t = np.linspace(-1, 1, sel.size)
    if order is None or order >= sel.size - 1:  # a free phase per bin (constant and slope removed after)
        B = np.eye(sel.size)
    else:
        B = np.stack([legendre.legval(t, np.eye(order + 1)[k]) for k in range(2, order + 1)], axis=1)
    Bfull = np.zeros((n, B.shape[1]))
    Bfull[sel] = B  # centred order
    Bfft = sfft.ifftshift(Bfull, axes=0)
    S = float(np.sum(np.abs(img0) ** 2))
    hist = []

    def fun(c):
        phi = Bfft @ c
        H = G * np.exp(1j * phi)[:, None]
        I = sfft.ifft(H, axis=0, workers=FFT_WORKERS)
        a = np.abs(I) ** 2
        q = np.maximum(a / S, 1e-300)
        E = float(-(q * np.log(q)).sum())
        w = -(np.log(q) + 1) / S
        Y = sfft.fft(w * I, axis=0, workers=FFT_WORKERS)
        grad_phi = -2 * np.sum(np.imag(H * np.conj(Y)), axis=1) / n
        hist.append(E)
        return E, Bfft.T @ grad_phi

    res = _scipy_optimize.minimize(fun, np.zeros(B.shape[1]), jac=True, method="L-BFGS-B", options={"maxiter": max_iter})
    phi = Bfft @ res.x
    if B.shape[1] == sel.size:  # free phases: remove the constant and slope (a shift), as PGA does
        phc = sfft.fftshift(phi)
        phc[sel] = _detrend(phc[sel])
        phi = sfft.ifftshift(phc)
    img = sfft.ifft(G * np.exp(1j * phi)[:, None], axis=0)
    e0, e1 = entropy(img0), entropy(img)
    history = [{"iteration": 0, "phase_rms": 0.0, "entropy": e0}]
    history.append({"iteration": int(res.nit), "phase_rms": float(np.sqrt(np.mean(phi[band] ** 2))),
                    "entropy": e1})
    if e1 > e0:  # never worse
        return AutofocusResult(image=img0, phase=np.zeros(n), history=history, converged=bool(res.success))
    return AutofocusResult(image=img, phase=-phi, history=history, converged=bool(res.success),
                           best_iteration=1)
