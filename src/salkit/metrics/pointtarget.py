"""Point-target analysis: peak position and phase, IRW, PSLR and ISLR in range and azimuth.

The neighbourhood of the brightest pixel is demodulated by its spectral centroid (SAL images carry
a strong spatial carrier), upsampled by FFT zero-padding, analysed along cuts through the peak,
and the carrier is put back for the peak phase.
"""
from __future__ import annotations

import math
from functools import lru_cache

import lazy_loader as _lazy
import numpy as np

from ..constants import SPEED_OF_LIGHT
from ..signals.windows import window
from ..tolerances import GRID_SPACING_OF_RESOLUTION

# loaded on first use, as salkit.signals.windows does (scipy.signal costs 0.5 s to import)
_signal = _lazy.load("scipy.signal", suppress_warning=True)

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


#: Powers (of the profile's peak) below which a spectral bin counts as empty in :func:`_carrier`,
#: tried in turn (a truncated chip's leakage fills a narrow gap to -20 dB).
CARRIER_GAP_LEVELS = (1e-3, 1e-2, 1e-1)


def _carrier(chip: np.ndarray, axis: int) -> float:
    """Centre (cycles/sample) of the band ``chip`` occupies along ``axis``: opposite the middle of
    the widest run of empty bins (under one of :data:`CARRIER_GAP_LEVELS` of the peak), so that zero
    padding falls in that gap; with no empty bin (noise over the whole band), the circular mean of
    the power. (The circular mean alone fails for a band wider than half the sampling rate whose
    power sits at its edges, as a wide aperture's annular support projects: the mean's angle then
    points into the gap, and the padding would split the band.)"""
    spec = np.abs(np.fft.fft(chip, axis=axis)) ** 2
    prof = spec.sum(axis=1 - axis)
    n = prof.size
    for level in CARRIER_GAP_LEVELS:  # the deepest level that leaves a gap (leakage fills a narrow one)
        empty = prof < level * prof.max()
        if empty.sum() >= 2 and not empty.all():
            start = int(np.argmin(empty))  # an occupied bin: runs of empty bins after it do not wrap
            e = np.roll(empty, -start)
            edges = np.diff(np.concatenate(([0], e.astype(np.int8), [0])))
            lo, hi = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
            k = int(np.argmax(hi - lo))
            if hi[k] - lo[k] >= 2:
                middle = (start + 0.5 * (lo[k] + hi[k] - 1)) / n  # of the widest gap, cycles/sample
                return float((middle + 0.5 + 0.5) % 1.0 - 0.5)
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


#: Bins of the K-space support's projection onto an axis (:func:`support_ipr`): the response it
#: gives repeats every this many cells of the support's extent, far outside the +-15 analysed.
SUPPORT_BINS = 2048
#: Samples a resolution cell of the theoretical cuts (:func:`support_ipr`).
SUPPORT_SAMPLES_PER_CELL = 64
#: Pulses and frequencies each that :func:`support_ipr` reads at most (every k-th): the response near
#: its peak is then that of the whole collection to 0.01 dB.
SUPPORT_MAX_SAMPLES = 1024


def _support_cut(s: np.ndarray, freq: np.ndarray, wp: np.ndarray, wf: np.ndarray, resolution: float,
                 half_cells: float) -> tuple[np.ndarray, float]:
    """|response|, and its sample spacing (m), along an image axis of a unit point at the scene
    centre, from the projection of the weighted K-space support onto that axis (projection-slice):
    the support's samples 4 pi f s_p / c, deposited linearly onto :data:`SUPPORT_BINS` bins (the
    deposit's sinc^2 taper divided out), Fourier transformed onto offsets +-``half_cells``
    resolution cells."""
    lo = min(freq[0] * s.min(), freq[-1] * s.min())
    hi = max(freq[0] * s.max(), freq[-1] * s.max())
    nb = SUPPORT_BINS
    if not hi > lo:
        return np.zeros(1), float("nan")
    step = (hi - lo) / (nb - 1)  # Hz of f s a bin
    H = np.zeros(nb + 1)
    rows = max(1, (1 << 20) // freq.size)
    for p0 in range(0, s.size, rows):
        pos = (s[p0:p0 + rows, None] * freq[None, :] - lo) / step
        i = np.clip(np.floor(pos).astype(np.int64), 0, nb - 1)
        frac = pos - i
        w = wp[p0:p0 + rows, None] * wf[None, :]
        H += np.bincount(i.ravel(), (w * (1.0 - frac)).ravel(), nb + 1)
        H += np.bincount((i + 1).ravel(), (w * frac).ravel(), nb + 1)
    # offset x (m) turns bin b by 4 pi (b step) x / c: an L-point transform samples x every c/(2 L step)
    L = 1 << int(math.ceil(math.log2(max(nb + 1, SUPPORT_SAMPLES_PER_CELL * SPEED_OF_LIGHT / (2 * step * resolution)))))
    dx = SPEED_OF_LIGHT / (2 * L * step)
    return _offsets_transform(H, L, dx, half_cells * resolution), dx


def _offsets_transform(H: np.ndarray, L: int, dx: float, reach: float) -> np.ndarray:
    """|the L-point transform of ``H``| at the offsets j dx within ``reach`` (m) of 0, j from -L/2,
    divided by the deposit's taper sinc^2(j / L). Those offsets are a few per cent of the L: a
    chirp-z transform gives them alone (the FFT of all L, then the cut, where they are most)."""
    J = min(int(math.floor(reach / dx)) + 1, L // 2)
    while J > 0 and J * dx > reach:
        J -= 1
    if 8 * J < L:
        j = np.arange(-J, J + 1)
        h = _signal.czt(H, 2 * J + 1, np.exp(-2j * np.pi / L), np.exp(-2j * np.pi * J / L))
    else:
        j = np.arange(L) - L // 2
        h = np.fft.fftshift(np.fft.fft(H, L))
        keep = np.abs(j) * dx <= reach
        j, h = j[keep], h[keep]
    return np.abs(h) / np.sinc(j / L) ** 2


def _support_samples(positions: np.ndarray, freq: np.ndarray, window_name: str, nbar: int, sll: float):
    """The pulses' unit directions, the frequencies and the two windows' weights that the support
    theory reads: every k-th pulse and frequency, at most :data:`SUPPORT_MAX_SAMPLES` each."""
    P, M = positions.shape[0], freq.size
    pi = np.unique(np.round(np.linspace(0, P - 1, min(P, SUPPORT_MAX_SAMPLES))).astype(np.int64))
    fi = np.unique(np.round(np.linspace(0, M - 1, min(M, SUPPORT_MAX_SAMPLES))).astype(np.int64))
    u = positions[pi] / np.linalg.norm(positions[pi], axis=1)[:, None]
    return (u, np.asarray(freq, np.float64)[fi], window(window_name, P, nbar, sll)[pi],
            window(window_name, M, nbar, sll)[fi])


def support_ipr(positions: np.ndarray, freq: np.ndarray, azimuth: np.ndarray, range_axis: np.ndarray,
                resolution_azimuth: float, resolution_range: float, window_name: str = "none", nbar: int = 4,
                sll: float = 35.0) -> dict:
    """Theoretical IRW, PSLR and ISLR of a spotlight collection along each image axis, from its own
    K-space support: each pulse p and frequency f give a wavenumber 4 pi f / c along the pulse's
    direction u_p, weighted by the window over the pulses and over the frequencies, as the
    backprojection formers apply them. The response of a point at the scene centre along an axis
    e is the Fourier transform of the support projected onto e (projection-slice), measured by
    :func:`ipr_1d` with the same sidelobe span as an image.

    A narrow aperture's support is a rectangle and this gives the window's figures
    (:func:`window_ipr`) times c/(2B) and lambda/(2 dtheta). A wide one's is an annular sector: its
    range response is narrower than c/(2B) and its sidelobes differ (-16 dB at 60 degrees, no
    window); a full circle's is a disc, with a J0-like response on both axes.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre, m.
    freq : float64 (M,)
        Frequencies of the phase history, Hz, increasing.
    azimuth, range_axis : float64 (3,)
        Unit axes of the image plane.
    resolution_azimuth, resolution_range : float
        The resolutions (m) that set the +-10 cell sidelobe span, as the image is measured with.
    window_name : {"none", "hamming", "taylor"}
    nbar, sll : int, float
        Taylor parameters.

    Returns
    -------
    dict
        ``irw_range``, ``irw_azimuth`` (m), ``pslr_range``, ``pslr_azimuth``, ``islr_range``,
        ``islr_azimuth`` (dB); NaN on an axis the support does not extend along.

    Examples
    --------
    >>> x = np.linspace(-10.0, 10.0, 201)  # a straight track 1 km away: the support is a rectangle
    >>> pos = np.stack([x, np.zeros_like(x), np.full_like(x, 1000.0)], axis=1)
    >>> f = 1e10 + np.arange(256) * (1e9 / 256)
    >>> t = support_ipr(pos, f, np.array([1.0, 0, 0]), np.array([0, 0, -1.0]), 0.7463, 0.1499)
    >>> round(t["irw_range"] / 0.1499, 3), round(t["pslr_range"], 2)  # the sinc's
    (0.886, -13.26)
    >>> round(t["pslr_azimuth"], 2)  # a 10 % band blurs the azimuth sidelobes: a sum of sincs
    -13.33
    """
    u, f, wp, wf = _support_samples(positions, freq, window_name, nbar, sll)
    out = {}
    for ax, e, res in (("range", range_axis, resolution_range), ("azimuth", azimuth, resolution_azimuth)):
        h, dx = _support_cut(u @ np.asarray(e, np.float64), f, wp, wf, res, 1.5 * SIDELOBE_SPAN)
        m = ipr_1d(h, dx, res) if np.isfinite(dx) else {"irw": np.nan, "pslr_db": np.nan, "islr_db": np.nan}
        out[f"irw_{ax}"], out[f"pslr_{ax}"], out[f"islr_{ax}"] = (float(m["irw"]), float(m["pslr_db"]),
                                                                  float(m["islr_db"]))
    return out


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


def support_curve(positions: np.ndarray, freq: np.ndarray, axis: np.ndarray, x: np.ndarray, resolution: float,
                  window_name: str = "none", nbar: int = 4, sll: float = 35.0) -> np.ndarray:
    """Theoretical |IPR|^2 (peak 1) at offsets ``x`` (m) along an image axis, from the collection's
    K-space support (:func:`support_ipr`'s response).

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre, m.
    freq : float64 (M,)
        Frequencies, Hz, increasing.
    axis : float64 (3,)
        Unit image axis.
    x : ndarray
        Offsets from the peak, m.
    resolution : float
        The axis' resolution, m (the response's sampling: 64 samples a cell).
    window_name : {"none", "hamming", "taylor"}
    nbar, sll : int, float
        Taylor parameters.

    Returns
    -------
    ndarray
        Normalised intensity.
    """
    u, f, wp, wf = _support_samples(positions, freq, window_name, nbar, sll)
    x = np.asarray(x, np.float64)
    half = float(np.max(np.abs(x))) / resolution + 1.0 if x.size else 1.0
    h, dx = _support_cut(u @ np.asarray(axis, np.float64), f, wp, wf, resolution, half)
    p = h ** 2
    xs = (np.arange(p.size) - p.size // 2) * dx
    return np.interp(x, xs, p / p.max())


def cut_curves(details: dict, attrs: dict, span: float = 8.0, positions: np.ndarray | None = None) -> dict:
    """The measured cuts through the brightest target and their theory, ready to draw.

    Parameters
    ----------
    details : dict
        From :func:`salkit.metrics.measure` with ``details=True`` (``_cut_range``, ``_cut_dy``, ...).
    attrs : dict
        Image attributes (``resolution_range``, ``resolution_azimuth``, ``window``; for an image
        judged against its collection's support, ``ipr_theory``, ``azimuth_axis``, ``range_axis``,
        ``frequency_min``, ``frequency_max``).
    span : float
        Half-width kept, resolution cells.
    positions : float64 (P, 3), optional
        The collection's antenna positions (the image's ``collection_position``): with them, an
        image whose theory is its support (``ipr_theory = support``) is drawn against that support's
        response (:func:`support_curve`), else against the window's.

    Returns
    -------
    dict
        ``{"range": (x m, measured dB, theory dB), "azimuth": (...)}``.
    """
    support = (positions is not None and attrs.get("ipr_theory") == "support"
               and all(k in attrs for k in ("azimuth_axis", "range_axis", "frequency_min", "frequency_max")))
    if support:  # the band's end points and as many samples as the theory reads (the window's shape)
        freq = np.linspace(float(attrs["frequency_min"]), float(attrs["frequency_max"]), SUPPORT_MAX_SAMPLES)
    out = {}
    for name, d0, key in (("range", details["_cut_dy"], "_cut_range"), ("azimuth", details["_cut_dx"], "_cut_azimuth")):
        y = np.asarray(details[key], np.float64) ** 2
        y = y / y.max()
        i = int(np.argmax(y))
        x = (np.arange(y.size) - i) * d0
        res = float(attrs.get(f"resolution_{name}", np.nan))
        keep = np.abs(x) <= span * res
        if support:
            th = support_curve(np.asarray(positions, np.float64), freq, np.asarray(attrs[f"{name}_axis"], np.float64),
                               x[keep], res, attrs.get("window", "none"))
        else:  # the window's response at the resolution its IRW theory implies (polar format: its rectangle's)
            width = res
            if f"irw_{name}_theory" in attrs and float(attrs.get("window_irw_factor", 0)) > 0:
                width = float(attrs[f"irw_{name}_theory"]) / float(attrs["window_irw_factor"])
            th = theory_ipr(attrs.get("window", "none"), x[keep], width)
        out[name] = (x[keep], 10 * np.log10(np.maximum(y[keep], 1e-8)), 10 * np.log10(np.maximum(th, 1e-8)))
    return out
