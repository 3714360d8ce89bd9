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
from ..tolerances import GRID_SPACING_OF_RESOLUTION

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


CHIP_SAMPLES_PER_CELL = 4.0  # the analysed neighbourhood keeps at least this many samples per resolution cell
CHIP_MIN_HALF = 16  # half-width of the neighbourhood, samples, at least


def analysis_extent(dx: float, dy: float, res_az: float, res_rg: float) -> dict:
    """Where :func:`analyse_point` reads around a peak: strides and half-widths, in pixels.

    The neighbourhood spans +-15 resolution cells (1.5 x the sidelobe span) in each direction. A
    grid finer than ``CHIP_SAMPLES_PER_CELL`` pixels a resolution cell is read every ``stride``-th
    pixel (the response is band-limited to about one cycle a resolution cell, so 4 samples a cell
    keep it free of aliasing), so the neighbourhood holds about 120 x 120 samples at any pixel size
    and the analysis' memory is bounded (a few MiB) however fine the grid.

    Parameters
    ----------
    dx, dy : float
        Pixel spacings in azimuth and range, m.
    res_az, res_rg : float
        Nominal resolutions, m.

    Returns
    -------
    dict
        ``stride`` (sx, sy) pixels between samples; ``half`` (hx, hy) samples either side;
        ``pixels`` (px, py) = stride x half, the half-extent in pixels that the analysis reads.

    Examples
    --------
    >>> analysis_extent(0.001, 0.001, 0.02, 0.02)["stride"]  # 20 pixels a cell -> every 5th
    (5, 5)
    """
    out = {"stride": [], "half": [], "pixels": []}
    for d, res in ((dx, res_az), (dy, res_rg)):
        d, res = abs(float(d)), float(res)
        # rounded with a margin: a window's coordinates give the spacing a few ulps off the image's
        s = max(1, int(math.floor(res / (CHIP_SAMPLES_PER_CELL * d) + 1e-6))) if np.isfinite(res) and res > 0 else 1
        h = max(int(math.ceil(1.5 * SIDELOBE_SPAN * res / (s * d) - 1e-6)), CHIP_MIN_HALF)
        out["stride"].append(s)
        out["half"].append(h)
        out["pixels"].append(s * h)
    return {k: tuple(v) for k, v in out.items()}


def _zoom_matrix(freqs: np.ndarray, positions: np.ndarray, n: int, up: int) -> np.ndarray:
    """Rows evaluating the zero-padded inverse DFT (``up`` times finer) of an n-point centred
    spectrum at fine sample ``positions``: the values ``ifft(pad(spectrum)) * up`` would hold there."""
    return np.exp(2j * np.pi * np.outer(positions, freqs) / (n * up)) / n


def analyse_point(image: np.ndarray, az: np.ndarray, rg: np.ndarray, res_az: float, res_rg: float,
                  peak: tuple[int, int] | None = None, upsample: int = 16, phase_fn=None) -> dict:
    """Analyse the point target at ``peak`` (pixel indices; default the brightest pixel).

    The neighbourhood (:func:`analysis_extent`: +-15 resolution cells, every k-th pixel of a grid
    finer than 4 pixels a cell) is demodulated by its spectral centroid and interpolated by
    zero-padding its spectrum ``upsample`` times: only the rows and columns needed are evaluated
    (the neighbourhood of the coarse peak, then the two cuts through the fine peak), so memory is a
    few MiB at any pixel size and the figures equal a full 2-D upsampling's to rounding.

    Parameters
    ----------
    image : complex (nx, ny)
    az, rg : float64
        Uniform pixel coordinates, m.
    res_az, res_rg : float
        Nominal resolutions, m (set the neighbourhood size and sidelobe span).
    upsample : int
        Interpolation factor of the cuts over the analysed samples.
    phase_fn : callable(az, rg) -> ndarray, optional
        The image's deterministic phase (rad) at plane coordinates; removed from the
        neighbourhood before upsampling (it holds the pixel-range curvature a focused SAL image
        carries) and restored for the peak phase.

    Returns
    -------
    dict
        Peak position (m), amplitude and phase (rad); IRW (m), PSLR and ISLR (dB) per axis (NaN where
        they cannot be measured: ``_unmeasured`` maps those names to the reason).
    """
    nx, ny = image.shape
    dx, dy = float(az[1] - az[0]), float(rg[1] - rg[0])
    if peak is None:
        peak = np.unravel_index(int(np.argmax(np.abs(image))), image.shape)
    i0, j0 = int(peak[0]), int(peak[1])
    ext = analysis_extent(dx, dy, res_az, res_rg)
    (sx, sy), (hx, hy) = ext["stride"], ext["half"]
    N, M = 2 * hx, 2 * hy
    ia = i0 + (np.arange(N) - hx) * sx  # image rows and columns of the samples
    jr = j0 + (np.arange(M) - hy) * sy
    oka, okr = (ia >= 0) & (ia < nx), (jr >= 0) & (jr < ny)
    chip = np.zeros((N, M), np.complex128)
    chip[np.ix_(oka, okr)] = image[ia[oka][0]:ia[oka][-1] + 1:sx, jr[okr][0]:jr[okr][-1] + 1:sy]
    Dx, Dy = sx * dx, sy * dy  # sample spacings of the neighbourhood, m
    ca = az[0] + ia * dx
    cr = rg[0] + jr * dy
    if phase_fn is not None:
        chip = chip * np.exp(-1j * phase_fn(ca[:, None], cr[None, :]))
    fa, fr = _carrier(chip, 0), _carrier(chip, 1)
    na = np.arange(N)[:, None]
    nr = np.arange(M)[None, :]
    bb = chip * np.exp(-2j * np.pi * (fa * na + fr * nr))
    U = int(upsample)
    spec = np.fft.fftshift(np.fft.fft2(bb))
    # frequencies of the centred spectrum as placed in the padded one (fftshift layout)
    fq_a = (N * U - N) // 2 + np.arange(N) - (N * U) // 2
    fq_r = (M * U - M) // 2 + np.arange(M) - (M * U) // 2
    # the fine peak: the interpolated image within +-2 samples of the coarse peak
    c = np.unravel_index(int(np.argmax(np.abs(bb))), bb.shape)
    za = np.arange((c[0] - 2) * U, (c[0] + 2) * U + 1) % (N * U)
    zr = np.arange((c[1] - 2) * U, (c[1] + 2) * U + 1) % (M * U)
    # products by einsum's own loops, not BLAS: a threaded BLAS sums in an order that follows its
    # thread count, and a Dask worker (one thread) must measure what this process does, bit for bit
    zoom = np.einsum("ik,lk->il", np.einsum("ij,jk->ik", _zoom_matrix(fq_a, za, N, U), spec),
                     _zoom_matrix(fq_r, zr, M, U))
    kz = np.unravel_index(int(np.argmax(np.abs(zoom))), zoom.shape)
    k = (int(za[kz[0]]), int(zr[kz[1]]))
    col = np.einsum("ij,j->i", spec, _zoom_matrix(fq_r, np.array([k[1]]), M, U)[0])  # through the fine peak's range
    row = np.einsum("j,jk->k", _zoom_matrix(fq_a, np.array([k[0]]), N, U)[0], spec)
    cut_az = np.einsum("ij,j->i", _zoom_matrix(fq_a, np.arange(N * U), N, U), col)
    cut_rg = np.einsum("ij,j->i", _zoom_matrix(fq_r, np.arange(M * U), M, U), row)
    m_az = ipr_1d(cut_az, Dx / U, res_az)
    m_rg = ipr_1d(cut_rg, Dy / U, res_rg)
    pa = m_az["peak_index"] / U  # in neighbourhood samples
    pr = m_rg["peak_index"] / U
    why = {}
    for ax, m, res in (("azimuth", m_az, res_az), ("range", m_rg, res_rg)):
        step = dx if ax == "azimuth" else dy
        reason = None
        if step > res * GRID_SPACING_OF_RESOLUTION:  # the sampling check's own limit
            reason = (f"the {100 * step:.3g} cm pixel undersamples the {100 * res:.3g} cm {ax} resolution "
                      f"(a pixel must be at most {GRID_SPACING_OF_RESOLUTION:g} x the resolution)")
        elif not np.isfinite(m["irw"]):
            reason = (f"the response's half-power points fall outside the +-{1.5 * SIDELOBE_SPAN:g} cells analysed "
                      "(a target at the image's edge, or no point target there)")
        if reason:
            for key in ("irw", "pslr_db", "islr_db"):  # an undersampled response has no IRW, PSLR or ISLR
                m[key] = float("nan")
            for key in (f"irw_{ax}_m", f"pslr_{ax}_db", f"islr_{ax}_db"):
                why[key] = reason
    val = zoom[kz]
    phase = float(np.angle(val * np.exp(2j * np.pi * (fa * k[0] / U + fr * k[1] / U))))
    flat_phase = phase
    a_org, r_org = float(ca[0]), float(cr[0])  # coordinates of the first sample, m
    if phase_fn is not None:
        pk_a = a_org + k[0] / U * Dx
        pk_r = r_org + k[1] / U * Dy
        phase = float(np.angle(np.exp(1j * (phase + float(np.asarray(phase_fn(pk_a, pk_r)))))))
    return {
        "_unmeasured": why,
        "peak_azimuth_m": float(a_org + pa * Dx),
        "peak_range_m": float(r_org + pr * Dy),
        "peak_amplitude": float(np.abs(val)),
        "image_phase_at_peak_rad": phase,
        "peak_phase_flat_rad": flat_phase,
        "irw_azimuth_m": m_az["irw"], "irw_range_m": m_rg["irw"],
        "pslr_azimuth_db": m_az["pslr_db"], "pslr_range_db": m_rg["pslr_db"],
        "islr_azimuth_db": m_az["islr_db"], "islr_range_db": m_rg["islr_db"],
        "_cut_azimuth": np.abs(cut_az), "_cut_range": np.abs(cut_rg),
        "_cut_dx": Dx / U, "_cut_dy": Dy / U,
        "_cut_origin_az": a_org, "_cut_origin_rg": r_org,
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
