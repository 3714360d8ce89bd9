"""Point-target analysis: peak position and phase, IRW, PSLR and ISLR in range and azimuth.

The neighbourhood of the brightest pixel is demodulated by its spectral centroid (SAL images carry
a strong spatial carrier), upsampled by FFT zero-padding, analysed along cuts through the peak,
and the carrier is put back for the peak phase.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..signals.windows import window

SIDELOBE_SPAN = 10.0  # resolution cells either side counted in PSLR/ISLR


def _crossing(y: np.ndarray, level: float, i_from: int, step: int) -> float:
    """Fractional index where y falls below ``level`` walking from i_from by step."""
    i = i_from
    n = y.size
    while 0 <= i + step < n and y[i + step] >= level:
        i += step
    if not 0 <= i + step < n:
        return float("nan")
    y0, y1 = y[i], y[i + step]
    frac = (y0 - level) / (y0 - y1) if y0 != y1 else 0.0
    return i + step * frac


def _first_null(p: np.ndarray, i_peak: int, step: int) -> int:
    i = i_peak
    n = p.size
    while 0 <= i + step < n and p[i + step] < p[i]:
        i += step
    return i


def ipr_1d(h: np.ndarray, dx: float, resolution: float) -> dict:
    """Figures of a 1-D impulse response sampled finely.

    Parameters
    ----------
    h : ndarray
        Complex or real samples through the peak, spacing ``dx`` (m).
    dx : float
        Sample spacing, m.
    resolution : float
        Nominal resolution (m), fixes the +-10 cell span of the sidelobe integrals.

    Returns
    -------
    dict
        ``irw`` (3 dB width, m), ``pslr_db``, ``islr_db``, ``peak_index`` (fractional),
        ``null_left``, ``null_right`` (indices).
    """
    p = np.abs(np.asarray(h)) ** 2
    i_pk = int(np.argmax(p))
    pk = p[i_pk]
    # parabolic refinement of the peak
    frac = 0.0
    if 0 < i_pk < p.size - 1:
        a, b, c = p[i_pk - 1], p[i_pk], p[i_pk + 1]
        den = a - 2 * b + c
        if den != 0:
            frac = 0.5 * (a - c) / den
    left = _crossing(p, 0.5 * pk, i_pk, -1)
    right = _crossing(p, 0.5 * pk, i_pk, +1)
    irw = (right - left) * dx
    nl = _first_null(p, i_pk, -1)
    nr = _first_null(p, i_pk, +1)
    span = int(round(SIDELOBE_SPAN * resolution / dx))
    lo, hi = max(i_pk - span, 0), min(i_pk + span + 1, p.size)
    main = p[nl:nr + 1].sum()
    side = p[lo:nl].sum() + p[nr + 1:hi].sum()
    sidelobes = np.concatenate([p[lo:nl], p[nr + 1:hi]])
    pslr = 10 * math.log10(sidelobes.max() / pk) if sidelobes.size and sidelobes.max() > 0 else -np.inf
    islr = 10 * math.log10(side / main) if side > 0 else -np.inf
    return {"irw": irw, "pslr_db": pslr, "islr_db": islr, "peak_index": i_pk + frac,
            "null_left": nl, "null_right": nr}


def _carrier(chip: np.ndarray, axis: int) -> float:
    """Spectral centroid (cycles/sample) of ``chip`` along ``axis`` by circular mean of power."""
    spec = np.abs(np.fft.fft(chip, axis=axis)) ** 2
    prof = spec.sum(axis=1 - axis)
    n = prof.size
    z = np.sum(prof * np.exp(2j * np.pi * np.arange(n) / n))
    return float(np.angle(z) / (2 * np.pi))


def analyse_point(image: np.ndarray, az: np.ndarray, rg: np.ndarray, res_az: float, res_rg: float,
                  peak: tuple[int, int] | None = None, upsample: int = 16, phase_fn=None) -> dict:
    """Analyse the point target at ``peak`` (pixel indices; default the brightest pixel).

    Parameters
    ----------
    image : complex (nx, ny)
    az, rg : float64
        Uniform pixel coordinates, m.
    res_az, res_rg : float
        Nominal resolutions, m (set the neighbourhood size and sidelobe span).
    upsample : int
    phase_fn : callable(az, rg) -> ndarray, optional
        The image's deterministic phase (rad) at plane coordinates; removed from the
        neighbourhood before upsampling (it holds the pixel-range curvature a focused SAL image
        carries) and restored for the peak phase.

    Returns
    -------
    dict
        Peak position (m), amplitude and phase (rad); IRW (m), PSLR and ISLR (dB) per axis.
    """
    nx, ny = image.shape
    dx, dy = float(az[1] - az[0]), float(rg[1] - rg[0])
    if peak is None:
        peak = np.unravel_index(int(np.argmax(np.abs(image))), image.shape)
    i0, j0 = int(peak[0]), int(peak[1])
    hx = max(int(math.ceil(1.5 * SIDELOBE_SPAN * res_az / dx)), 16)
    hy = max(int(math.ceil(1.5 * SIDELOBE_SPAN * res_rg / dy)), 16)
    chip = np.zeros((2 * hx, 2 * hy), np.complex128)
    a0, a1 = max(i0 - hx, 0), min(i0 + hx, nx)
    b0, b1 = max(j0 - hy, 0), min(j0 + hy, ny)
    chip[a0 - (i0 - hx):a1 - (i0 - hx), b0 - (j0 - hy):b1 - (j0 - hy)] = image[a0:a1, b0:b1]
    ca = az[0] + (np.arange(2 * hx) + i0 - hx) * dx
    cr = rg[0] + (np.arange(2 * hy) + j0 - hy) * dy
    if phase_fn is not None:
        chip = chip * np.exp(-1j * phase_fn(ca[:, None], cr[None, :]))
    fa, fr = _carrier(chip, 0), _carrier(chip, 1)
    na = np.arange(2 * hx)[:, None]
    nr = np.arange(2 * hy)[None, :]
    bb = chip * np.exp(-2j * np.pi * (fa * na + fr * nr))
    U = upsample
    spec = np.fft.fftshift(np.fft.fft2(bb))
    big = np.zeros((2 * hx * U, 2 * hy * U), np.complex128)
    ox, oy = (big.shape[0] - spec.shape[0]) // 2, (big.shape[1] - spec.shape[1]) // 2
    big[ox:ox + spec.shape[0], oy:oy + spec.shape[1]] = spec
    up = np.fft.ifft2(np.fft.ifftshift(big)) * (U * U)
    k = np.unravel_index(int(np.argmax(np.abs(up))), up.shape)
    cut_az = up[:, k[1]]
    cut_rg = up[k[0], :]
    m_az = ipr_1d(cut_az, dx / U, res_az)
    m_rg = ipr_1d(cut_rg, dy / U, res_rg)
    pa = m_az["peak_index"] / U  # in chip samples
    pr = m_rg["peak_index"] / U
    val = up[k]
    phase = float(np.angle(val * np.exp(2j * np.pi * (fa * k[0] / U + fr * k[1] / U))))
    flat_phase = phase
    if phase_fn is not None:
        pk_a = az[0] + (i0 - hx + k[0] / U) * dx
        pk_r = rg[0] + (j0 - hy + k[1] / U) * dy
        phase = float(np.angle(np.exp(1j * (phase + float(np.asarray(phase_fn(pk_a, pk_r)))))))
    return {
        "peak_azimuth_m": float(az[0] + (i0 - hx + pa) * dx),
        "peak_range_m": float(rg[0] + (j0 - hy + pr) * dy),
        "peak_amplitude": float(np.abs(val)),
        "peak_phase_rad": phase,
        "peak_phase_flat_rad": flat_phase,
        "irw_azimuth_m": m_az["irw"], "irw_range_m": m_rg["irw"],
        "pslr_azimuth_db": m_az["pslr_db"], "pslr_range_db": m_rg["pslr_db"],
        "islr_azimuth_db": m_az["islr_db"], "islr_range_db": m_rg["islr_db"],
        "_cut_azimuth": np.abs(cut_az), "_cut_range": np.abs(cut_rg),
        "_cut_dx": dx / U, "_cut_dy": dy / U,
        "_cut_origin_az": float(az[0] + (i0 - hx) * dx), "_cut_origin_rg": float(rg[0] + (j0 - hy) * dy),
    }


@lru_cache(maxsize=64)
def window_ipr(name: str, nbar: int = 4, sll: float = 35.0, n: int = 512, up: int = 64) -> dict:
    """Theoretical IRW factor, PSLR and ISLR of a window's impulse response.

    The IRW factor multiplies the unweighted resolution (1/bandwidth): 0.886 for no window.
    ISLR integrates over +-10 resolution cells outside the main lobe (between first nulls),
    the same span that :func:`ipr_1d` uses.

    Parameters
    ----------
    name : {"none", "hamming", "taylor"}
    nbar, sll : int, float
        Taylor parameters.
    n, up : int
        Window length and upsampling of the computed response.

    Returns
    -------
    dict
        ``irw_factor`` (dimensionless), ``pslr_db``, ``islr_db`` (dB).
    """
    w = window(name, n, nbar, sll)
    spec = np.zeros(n * up, complex)
    spec[:n] = w
    h = np.fft.fftshift(np.fft.ifft(spec))
    m = ipr_1d(h, dx=1.0 / up, resolution=1.0)
    return {"irw_factor": m["irw"], "pslr_db": m["pslr_db"], "islr_db": m["islr_db"]}


def theory_ipr(window_name: str, x: np.ndarray, resolution: float, nbar: int = 4,
               sll: float = 35.0) -> np.ndarray:
    """Theoretical |IPR|^2 (peak 1) of a window at offsets ``x`` (m) for a resolution (m).

    Parameters
    ----------
    window_name : {"none", "hamming", "taylor"}
    x : ndarray
        Offsets from the peak, m.
    resolution : float
        Unweighted resolution (1/bandwidth), m.
    nbar, sll : int, float
        Taylor parameters.

    Returns
    -------
    ndarray
        Normalised intensity.
    """
    n = 256
    w = window(window_name, n, nbar, sll)
    t = (np.arange(n) - (n - 1) / 2) / n  # normalised aperture coordinate
    h = np.abs(np.exp(2j * np.pi * np.outer(np.asarray(x) / resolution, t)) @ w)
    return (h / h.max()) ** 2


def cut_curves(details: dict, attrs: dict, span: float = 8.0) -> dict:
    """The measured cuts through the brightest target and their theory, ready to draw.

    Parameters
    ----------
    details : dict
        From :func:`salkit.metrics.measure` with ``details=True`` (``_cut_range``, ``_cut_dy``, ...).
    attrs : dict
        Image attributes (``resolution_range``, ``resolution_azimuth``, ``window``).
    span : float
        Half-width kept, resolution cells.

    Returns
    -------
    dict
        ``{"range": (x m, measured dB, theory dB), "azimuth": (...)}``.
    """
    out = {}
    for name, d0, key in (("range", details["_cut_dy"], "_cut_range"), ("azimuth", details["_cut_dx"], "_cut_azimuth")):
        y = np.asarray(details[key], np.float64) ** 2
        y = y / y.max()
        i = int(np.argmax(y))
        x = (np.arange(y.size) - i) * d0
        res = float(attrs.get(f"resolution_{name}", np.nan))
        keep = np.abs(x) <= span * res
        th = theory_ipr(attrs.get("window", "none"), x[keep], res)
        out[name] = (x[keep], 10 * np.log10(np.maximum(y[keep], 1e-8)), 10 * np.log10(np.maximum(th, 1e-8)))
    return out
