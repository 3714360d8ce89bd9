"""Fast factorised backprojection (Ulander, Hellsten and Stenström 2003).

The aperture is split into sub-apertures of a few pulses; each is backprojected onto a polar
grid of its own (range r from its centre c and direction cosine u = (x - c).e_a / r along the
plane's azimuth axis), whose angular spacing only has to resolve what a short aperture can
resolve. Neighbouring sub-images are then merged, four at a time, onto the polar grid of their union
(four times the angular samples, a quarter as many images), until a few remain; those are interpolated onto
the output grid. Each level costs about one output image of work, so the whole costs
N^2 log N instead of the N^3 of direct backprojection.

Sub-images are stored at baseband: g(x) = v(x) exp(-j k |x - c|), v the backprojected value and
k = 4 pi f_c / c, so g is smooth (its range bandwidth is the pulse's, its angular bandwidth
L / lambda per unit u for a sub-aperture of length L) and can be interpolated; the phase
k (|x - c_child| - |x - c_parent|) is put back exactly, in float64, at every merge. A point in the
plane is found from (r, u) in closed form, so the antenna may follow any trajectory; the polar
grids of each level are sized from the image's extent as seen from each sub-aperture centre.

Interpolation: least-squares optimal kernels (``interpolation_table``) designed for each grid's
oversampling, 8 taps in angle and 6 in range, 4 taps on the leaves' range profiles. Each merge
interpolates separably: the parent's line of points crosses the child's range bins in order, so
the child is first cut along the line in angle at its own range bins, then the cut is
interpolated in range (14 taps instead of 48).

Accuracy knobs: ``oversample_angle`` and ``oversample_range`` (samples per Nyquist interval of
the polar grids) and ``leaf`` (pulses backprojected directly into each first-level sub-image).
docs/performance.md gives the accuracy-speed curve.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..constants import SPEED_OF_LIGHT
from ..errors import ScenarioError
from ..signals.windows import Window
from .backprojection import _sincos_cycles, range_profiles
from .formers import ImageGrid, ImageResult, register_former
from .phasehistory import PhaseHistory

#: Default accuracy settings (image error about -40 dB against direct backprojection).
LEAF_PULSES = 32
#: Sub-images merged into each parent (4: fewer levels, the same accuracy, 11 % faster at 2048^2 than 2).
MERGE_FACTOR = 4
OVERSAMPLE_ANGLE = 1.75
OVERSAMPLE_RANGE = 1.75
#: Range-profile oversampling of the first level (4-tap table interpolation).
LEAF_UPSAMPLE = 4
#: Taps of the angular interpolation (the range one has 6).
ANGLE_TAPS = 8
MARGIN = 4  # samples kept outside the image's extent on each side of a polar grid


#: Fractional positions tabulated per interpolation kernel (nearest entry: a position error of
#: 1/4096 sample, a phase error below 5e-4 rad at the band edge).
TABLE_STEPS = 2048


def interpolation_table(taps: int, oversample: float, steps: int = TABLE_STEPS) -> np.ndarray:
    """Least-squares optimal interpolation weights for a signal band-limited to 1/oversample of
    the sampling rate.

    For each fraction t in [0, 1] the ``taps`` weights minimise the error of interpolating
    exp(j 2 pi f t) over the band |f| <= 1 / (2 oversample) cycles per sample, flat weighting:
    the normal equations of that fit are a Toeplitz system of sinc functions. At the same
    oversampling this kernel is 10 to 20 dB better than Lagrange interpolation (6 taps at 1.75x:
    -50 dB against -33 dB, for a flat spectrum).

    Parameters
    ----------
    taps : int
        Even number of samples, at offsets -(taps/2 - 1) .. taps/2 from the sample below t.
    oversample : float
        Sampling rate over the signal's bandwidth, > 1.
    steps : int
        Table entries per sample interval.

    Returns
    -------
    float32 (steps + 1, taps)
        Weights; row i is for t = i / steps.

    Examples
    --------
    >>> w = interpolation_table(6, 1.75)
    >>> w.shape, bool(abs(w[0, 2] - 1.0) < 1e-6), bool(abs(w[-1, 3] - 1.0) < 1e-6)
    ((2049, 6), True, True)
    """
    offs = np.arange(-(taps // 2 - 1), taps // 2 + 1, dtype=np.float64)
    band = 1.0 / oversample  # two-sided bandwidth, cycles per sample
    A = band * np.sinc(band * (offs[:, None] - offs[None, :]))
    t = np.arange(steps + 1) / steps
    rhs = band * np.sinc(band * (t[:, None] - offs[None, :]))
    return np.linalg.solve(A, rhs.T).T.astype(np.float32)


@njit(cache=True, inline="always", fastmath=True)
def _rotate(vr, vi, cyc):
    """(vr + j vi) exp(j 2 pi cyc), the cycles reduced in float64 before the float32 sin/cos."""
    y = np.float32(cyc - math.floor(cyc + 0.5))
    s, c = _sincos_cycles(y)
    return vr * c - vi * s, vr * s + vi * c


@njit(cache=True, inline="always", fastmath=True)
def _plane_point(o, ea, er, cen, r, u):
    """The point of the image plane at distance r from ``cen`` with direction cosine u along ea,
    on the far side of the antenna along er; (nan, nan, nan) when there is none."""
    d0 = o[0] - cen[0]
    d1 = o[1] - cen[1]
    d2 = o[2] - cen[2]
    da = d0 * ea[0] + d1 * ea[1] + d2 * ea[2]
    dr = d0 * er[0] + d1 * er[1] + d2 * er[2]
    h2 = d0 * d0 + d1 * d1 + d2 * d2 - da * da - dr * dr
    rad = r * r * (1.0 - u * u) - h2
    if rad < 0.0:
        return np.nan, np.nan, np.nan
    s = r * u - da
    t = -dr + math.sqrt(rad)
    return o[0] + s * ea[0] + t * er[0], o[1] + s * ea[1] + t * er[1], o[2] + s * ea[2] + t * er[2]


@njit(cache=True, fastmath=True, inline="always")
def _polar_line(o, ea, er, cen, r0, dr, n, u):
    """The plane points of one polar line (direction cosine u, ranges r0 + k dr from ``cen``), their
    ranges, and the first and last index that lie in the plane (top < lo: none)."""
    X0 = np.empty(n)
    X1 = np.empty(n)
    X2 = np.empty(n)
    rl = np.empty(n)
    lo = n
    top = -1
    for ir in range(n):
        r = r0 + ir * dr
        rl[ir] = r
        X0[ir], X1[ir], X2[ir] = _plane_point(o, ea, er, cen, r, u)
        if X0[ir] == X0[ir]:
            lo = min(lo, ir)
            top = ir
    return X0, X1, X2, rl, lo, top


@njit(cache=True, fastmath=True, boundscheck=False)
def _leaf_line(prof, rp0, inv_drp, hi, pos, ref, weight, first, count, X0, X1, X2, r_line, cyc_per_m, tp,
               acc_r, acc_i, idx_b, row_b, sn_b, cs_b):
    """Backproject a leaf's pulses onto one polar line of points (baseband), two passes per
    pulse: range, profile index, table row and phase for the whole line (vectorises); then the
    4-tap gathers."""
    n = X0.shape[0]
    T = tp.shape[0] - 1
    for p in range(first, first + count):
        px = pos[p, 0]
        py = pos[p, 1]
        pz = pos[p, 2]
        rp = ref[p] + rp0
        wp = weight[p]
        for k in range(n):
            e0 = X0[k] - px
            e1 = X1[k] - py
            e2 = X2[k] - pz
            R = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            xi = (R - rp) * inv_drp
            ok = (xi >= 1.0) & (xi <= hi)
            xi = min(max(xi, 1.0), hi)
            fl = math.floor(xi)
            idx_b[k] = np.int32(fl)
            row_b[k] = np.int32((xi - fl) * T + 0.5)
            cyc = (R - r_line[k] - ref[p]) * cyc_per_m
            y = np.float32(cyc - math.floor(cyc + 0.5))
            s, c = _sincos_cycles(y)
            g = np.float32(ok) * wp
            sn_b[k] = s * g
            cs_b[k] = c * g
        for k in range(n):
            i0 = idx_b[k] - 1
            w = tp[row_b[k]]
            vr = np.float32(0.0)
            vi = np.float32(0.0)
            for b in range(4):
                z = prof[p, i0 + b]
                vr += w[b] * z.real
                vi += w[b] * z.imag
            s = sn_b[k]
            c = cs_b[k]
            acc_r[k] += vr * c - vi * s
            acc_i[k] += vr * s + vi * c


@njit(parallel=True, cache=True, fastmath=True)
def _leaf_kernel(prof, rp0, inv_drp, pos, ref, weight, first, count, cen, o, ea, er,
                 u0, du, nu, r0, dr, nr, cyc_per_m, tp, out):
    """Backproject each leaf's pulses onto its polar grid, at baseband (4-tap table interpolation
    of the oversampled range profiles)."""
    S, NU, NR = out.shape
    hi = prof.shape[1] - 3.0
    for job in prange(S * NU):
        s = job // NU
        iu = job % NU
        if iu >= nu[s]:
            continue
        X0, X1, X2, rl, lo, top = _polar_line(o, ea, er, cen[s], r0[s], dr, nr[s], u0[s] + iu * du[s])
        if top < lo:
            continue
        m = top + 1 - lo
        acc_r = np.zeros(m, np.float32)
        acc_i = np.zeros(m, np.float32)
        _leaf_line(prof, rp0, inv_drp, hi, pos, ref, weight, first[s], count[s], X0[lo:top + 1], X1[lo:top + 1],
                   X2[lo:top + 1], rl[lo:top + 1], cyc_per_m, tp, acc_r, acc_i, np.empty(m, np.int32),
                   np.empty(m, np.int32), np.empty(m, np.float32), np.empty(m, np.float32))
        for k in range(m):
            out[s, iu, lo + k] = complex(acc_r[k], acc_i[k])


@njit(cache=True, fastmath=True, boundscheck=False)
def _accumulate_child(G, c, u0c, duc, nuc, r0c, nrc, cx, cy, cz, dr_child, ea, X0, X1, X2, r_line, cyc_per_m,
                      tu, tr, acc_r, acc_i, fr_b, uc_b, sn_b, cs_b, h_r, h_i, uj_b, s_b):
    """Add child ``c`` (baseband, interpolated, phase restored) along one parent line of points.

    The parent line crosses the child's range bins in order, so the 2-D interpolation separates
    (12 taps instead of 36): pass 1 finds, for every point, the child range bin (fraction) and
    direction cosine, and the phase k (r_c - r) as float32 sin/cos after a float64 reduction;
    pass 2 interpolates the child in angle at each of its own range bins the line crosses, at the
    line's direction cosine there (linear in the bin between points: its curvature is
    d (1 - u^2) / r^3, far below a sample); pass 3 interpolates that 1-D cut in range at every
    point. Points are assumed valid (the caller trims the line to its points in the plane).
    """
    n = X0.shape[0]
    inv_dr = 1.0 / dr_child
    T = tr.shape[0] - 1
    for k in range(n):
        e0 = X0[k] - cx
        e1 = X1[k] - cy
        e2 = X2[k] - cz
        rc = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        fr_b[k] = (rc - r0c) * inv_dr
        uc_b[k] = (e0 * ea[0] + e1 * ea[1] + e2 * ea[2]) / rc
        cyc = (rc - r_line[k]) * cyc_per_m
        y = np.float32(cyc - math.floor(cyc + 0.5))
        sn, cs = _sincos_cycles(y)
        sn_b[k] = sn
        cs_b[k] = cs
    if n < 2:
        return
    # pass 2: the child cut along the line, on the child's range bins j_lo .. j_hi
    j_lo = max(int(math.floor(fr_b[0])) - 2, 0)
    j_hi = min(int(math.floor(fr_b[n - 1])) + 3, nrc - 1)
    if j_hi < j_lo:
        return
    inv_du = 1.0 / duc
    na = tu.shape[1]
    ha = na // 2 - 1
    k = 0
    j = j_lo
    while j <= j_hi:  # the angle index at each crossed bin, linear between points
        f0 = fr_b[k]
        slope = (uc_b[k + 1] - uc_b[k]) / (fr_b[k + 1] - f0)
        j_end = j_hi if k + 2 >= n else min(int(math.floor(fr_b[k + 1])), j_hi)
        while j <= j_end:
            uj_b[j - j_lo] = (uc_b[k] + slope * (j - f0) - u0c) * inv_du
            j += 1
        k += 1
    # the angular interpolation in segments of one angle index where the fraction moves by at
    # most 1/32 sample: weights linear in the fraction between the segment's ends (error below
    # -70 dB), so the inner loops run along contiguous rows and vectorise
    j = j_lo
    while j <= j_hi:
        f0 = uj_b[j - j_lo]
        iu = int(math.floor(f0))
        e = j
        while e < j_hi and e - j < 512:
            f1 = uj_b[e + 1 - j_lo]
            if int(math.floor(f1)) != iu or abs(f1 - f0) > 0.03125:
                break
            e += 1
        m = e + 1 - j
        b0 = j - j_lo
        if iu < ha or iu + na - ha > nuc:
            for q in range(m):
                h_r[b0 + q] = np.float32(0.0)
                h_i[b0 + q] = np.float32(0.0)
        else:
            t0 = f0 - iu
            t1 = uj_b[e - j_lo] - iu
            i0 = int(t0 * T + 0.5)
            i1 = int(t1 * T + 0.5)
            inv = 1.0 / (t1 - t0) if t1 != t0 else 0.0
            for q in range(m):
                s_b[q] = np.float32((uj_b[b0 + q] - iu - t0) * inv)
                h_r[b0 + q] = np.float32(0.0)
                h_i[b0 + q] = np.float32(0.0)
            for a in range(na):
                ra = iu - ha + a
                wa = tu[i0, a]
                dwa = tu[i1, a] - wa
                for q in range(m):
                    z = G[c, ra, j + q]
                    w = wa + dwa * s_b[q]
                    h_r[b0 + q] += w * z.real
                    h_i[b0 + q] += w * z.imag
        j = e + 1
    # pass 3: range interpolation of the cut at every point, phase restored
    for k in range(n):
        fr = fr_b[k]
        fr_f = math.floor(fr)
        ir = int(fr_f)
        if ir - 2 < j_lo or ir + 3 > j_hi:
            continue
        it = int((fr - fr_f) * T + 0.5)
        b0 = ir - 2 - j_lo
        vr = np.float32(0.0)
        vi = np.float32(0.0)
        for b in range(6):
            vr += tr[it, b] * h_r[b0 + b]
            vi += tr[it, b] * h_i[b0 + b]
        sn = sn_b[k]
        cs = cs_b[k]
        acc_r[k] += vr * cs - vi * sn
        acc_i[k] += vr * sn + vi * cs


@njit(parallel=True, cache=True, fastmath=True)
def _merge_kernel(G, cu0, cdu, cnu, cr0, cnr, ccen, dr_child, factor, o, ea, er, cen, u0, du, nu, r0, dr, nr,
                  cyc_per_m, tu, tr, out):
    """Merge ``factor`` consecutive child sub-images into each parent's polar grid."""
    S, NU, NR = out.shape
    n_child = G.shape[0]
    for job in prange(S * NU):
        s = job // NU
        iu = job % NU
        if iu >= nu[s]:
            continue
        X0, X1, X2, rl, lo, top = _polar_line(o, ea, er, cen[s], r0[s], dr, nr[s], u0[s] + iu * du[s])
        if top < lo:
            continue
        m = top + 1 - lo
        acc_r = np.zeros(m, np.float32)
        acc_i = np.zeros(m, np.float32)
        fr_b = np.empty(m)
        uc_b = np.empty(m)
        sn_b = np.empty(m, np.float32)
        cs_b = np.empty(m, np.float32)
        h_r = np.empty(G.shape[2], np.float32)
        h_i = np.empty(G.shape[2], np.float32)
        uj_b = np.empty(G.shape[2])
        s_b = np.empty(G.shape[2], np.float32)
        for c in range(s * factor, min(s * factor + factor, n_child)):
            _accumulate_child(G, c, cu0[c], cdu[c], cnu[c], cr0[c], cnr[c], ccen[c, 0], ccen[c, 1], ccen[c, 2],
                              dr_child, ea, X0[lo:top + 1], X1[lo:top + 1], X2[lo:top + 1], rl[lo:top + 1],
                              cyc_per_m, tu, tr, acc_r, acc_i, fr_b, uc_b, sn_b, cs_b, h_r, h_i, uj_b, s_b)
        for k in range(m):
            out[s, iu, lo + k] = complex(acc_r[k], acc_i[k])


@njit(parallel=True, cache=True, fastmath=True)
def _final_kernel(G, cu0, cdu, cnu, cr0, cnr, ccen, dr_child, o, ea, er, az, rg, cyc_per_m, tu, tr, out):
    """Every remaining sub-image interpolated onto the output grid (6 x 6 table weights), its
    phase k |x - c| restored."""
    nx, ny = out.shape
    T = tr.shape[0] - 1
    na = tu.shape[1]
    ha = na // 2 - 1
    for i in prange(nx):
        for j in range(ny):
            x0 = o[0] + az[i] * ea[0] + rg[j] * er[0]
            x1 = o[1] + az[i] * ea[1] + rg[j] * er[1]
            x2 = o[2] + az[i] * ea[2] + rg[j] * er[2]
            acc_r = np.float32(0.0)
            acc_i = np.float32(0.0)
            for c in range(G.shape[0]):
                e0 = x0 - ccen[c, 0]
                e1 = x1 - ccen[c, 1]
                e2 = x2 - ccen[c, 2]
                rc = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                fu = ((e0 * ea[0] + e1 * ea[1] + e2 * ea[2]) / rc - cu0[c]) / cdu[c]
                fr = (rc - cr0[c]) / dr_child
                iu = int(math.floor(fu))
                ir = int(math.floor(fr))
                if iu < ha or ir < 2 or iu + na - ha > cnu[c] or ir + 3 >= cnr[c]:
                    continue
                wu = tu[int((fu - iu) * T + 0.5)]
                wr = tr[int((fr - ir) * T + 0.5)]
                vr = np.float32(0.0)
                vi = np.float32(0.0)
                for a in range(na):
                    rr = np.float32(0.0)
                    ri = np.float32(0.0)
                    for b in range(6):
                        z = G[c, iu - ha + a, ir - 2 + b]
                        rr += wr[b] * z.real
                        ri += wr[b] * z.imag
                    vr += wu[a] * rr
                    vi += wu[a] * ri
                vr, vi = _rotate(vr, vi, rc * cyc_per_m)
                acc_r += vr
                acc_i += vi
            out[i, j] = complex(acc_r, acc_i)


def _image_boundary(grid: ImageGrid, n: int = 64) -> np.ndarray:
    """Points (K, 3) on the edge of the pixel rectangle, half a pixel outside it."""
    az, rg = grid.azimuth, grid.range
    da = (az[1] - az[0]) if az.size > 1 else 0.0
    dg = (rg[1] - rg[0]) if rg.size > 1 else 0.0
    a = np.linspace(az[0] - da, az[-1] + da, n)
    g = np.linspace(rg[0] - dg, rg[-1] + dg, n)
    A = np.concatenate([a, a, np.full(n, a[0]), np.full(n, a[-1])])
    R = np.concatenate([np.full(n, g[0]), np.full(n, g[-1]), g, g])
    return grid.plane.points(A, R)


def _polar_grids(centres: np.ndarray, lengths: np.ndarray, grid: ImageGrid, wavelength: float, dr: float,
                 oversample_angle: float):
    """Per sub-aperture: u origin, u step, u count, r origin, r count (r step ``dr`` for all)."""
    pts = _image_boundary(grid)
    ea = grid.plane.azimuth
    S = centres.shape[0]
    u0 = np.empty(S)
    du = np.empty(S)
    nu = np.empty(S, np.int64)
    r0 = np.empty(S)
    nr = np.empty(S, np.int64)
    # the rectangle's nearest point to each centre bounds r from below
    o, er = grid.plane.origin, grid.plane.range
    az, rg = grid.azimuth, grid.range
    for s in range(S):
        d = pts - centres[s]
        R = np.linalg.norm(d, axis=1)
        U = d @ ea / R
        rel = centres[s] - o
        ca = np.clip(rel @ ea, az[0], az[-1])
        cg = np.clip(rel @ er, rg[0], rg[-1])
        rmin = min(float(np.linalg.norm(o + ca * ea + cg * er - centres[s])), float(R.min()))
        du[s] = wavelength / (2.0 * max(lengths[s], 1e-9) * oversample_angle)
        lo, hi = float(U.min()), float(U.max())
        n_u = int(math.ceil((hi - lo) / du[s])) + 1 + 2 * MARGIN
        u0[s] = lo - MARGIN * du[s]
        nu[s] = n_u
        r0[s] = rmin - MARGIN * dr
        nr[s] = int(math.ceil((float(R.max()) - rmin) / dr)) + 1 + 2 * MARGIN
    return u0, du, nu, r0, nr


def _lengths(positions: np.ndarray, groups: list, centres: np.ndarray, ea: np.ndarray, step: float) -> np.ndarray:
    """Effective length of each group of pulses: its span along ea plus twice its largest
    excursion across ea (track curvature widens the angular band too), plus one pulse step."""
    out = np.empty(len(groups))
    for s, (a, b) in enumerate(groups):
        d = positions[a:b] - centres[s]
        along = d @ ea
        across = np.linalg.norm(d - np.outer(along, ea), axis=1)
        out[s] = float(along.max() - along.min()) + 2.0 * float(across.max()) + step
    return out


def ffbp(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray, grid: ImageGrid,
         azimuth_window: np.ndarray, range_window: np.ndarray, upsample: int = LEAF_UPSAMPLE, leaf: int = LEAF_PULSES,
         factor: int = MERGE_FACTOR, oversample_angle: float = OVERSAMPLE_ANGLE, oversample_range: float = OVERSAMPLE_RANGE,
         progress=None) -> tuple[np.ndarray, dict]:
    """Fast factorised backprojection onto ``grid``, unnormalised (as direct backprojection).

    Parameters
    ----------
    ph : complex (P, M)
        Phase history.
    freq : float64 (M,)
        Frequencies, Hz, increasing and uniform.
    positions : float64 (P, 3)
        Antenna positions, m (any trajectory).
    ref_range : float64 (P,)
        Reference ranges, m.
    grid : ImageGrid
    azimuth_window : float (P,)
        Per-pulse weights.
    range_window : float (M,)
    upsample : int
        Range-profile oversampling for the first level (its 4-tap kernel is designed for it).
    leaf : int
        Pulses per first-level sub-image.
    factor : int
        Sub-images merged into each parent.
    oversample_angle, oversample_range : float
        Polar-grid samples per Nyquist interval.
    progress : callable, optional
        ``progress(done, total)`` in levels.

    Returns
    -------
    (complex64 (nx, ny), dict)
        The image and the sizes of the factorisation (levels, polar samples).
    """
    P, M = ph.shape
    c = SPEED_OF_LIGHT
    B = M * float(freq[1] - freq[0])
    lam_min = c / float(freq[-1])
    f_c = float(freq[M // 2])
    cyc_per_m = 2.0 * f_c / c
    dr = c / (2.0 * B * oversample_range)
    plane = grid.plane
    o = np.ascontiguousarray(plane.origin, np.float64)
    ea = np.ascontiguousarray(plane.azimuth, np.float64)
    er = np.ascontiguousarray(plane.range, np.float64)
    step = float(np.median(np.linalg.norm(np.diff(positions, axis=0), axis=1))) if P > 1 else 0.0
    prof, rp0, drp, _ = range_profiles(ph, freq, upsample, np.asarray(range_window, np.float64))
    tp = interpolation_table(4, prof.shape[1] / M)
    tu = interpolation_table(ANGLE_TAPS, oversample_angle)
    tr = interpolation_table(6, oversample_range)
    w = np.asarray(azimuth_window, np.float32)
    # level 0: leaves of `leaf` pulses
    groups = [(a, min(a + leaf, P)) for a in range(0, P, leaf)]
    weights = np.array([max(float(w[a:b].sum()), 1e-30) for a, b in groups])
    centres = np.array([positions[a:b].mean(axis=0) for a, b in groups])
    lengths = _lengths(positions, groups, centres, ea, step)
    n_levels = 1 + max(0, math.ceil(math.log(max(len(groups), 1), factor)) - 1) + 1
    done = 0
    u0, du, nu, r0, nr = _polar_grids(centres, lengths, grid, lam_min, dr, oversample_angle)
    G = np.zeros((len(groups), int(nu.max()), int(nr.max())), np.complex64)
    first = np.array([a for a, _ in groups], np.int64)
    count = np.array([b - a for a, b in groups], np.int64)
    _leaf_kernel(prof, rp0, 1.0 / drp, positions, ref_range, w, first, count, centres, o, ea, er,
                 u0, du, nu, r0, dr, nr, cyc_per_m, tp, G)
    samples = [int((nu * nr).sum())]
    done += 1
    if progress:
        progress(done, n_levels)
    # merge until at most `factor` sub-images remain
    spans = list(groups)
    while G.shape[0] > factor:
        S = G.shape[0]
        parents = [(i, min(i + factor, S)) for i in range(0, S, factor)]
        spans = [(spans[a][0], spans[b - 1][1]) for a, b in parents]
        pw = np.array([weights[a:b].sum() for a, b in parents])
        pcen = np.array([(centres[a:b] * weights[a:b, None]).sum(axis=0) / pw[k] for k, (a, b) in enumerate(parents)])
        plen = _lengths(positions, spans, pcen, ea, step)
        pu0, pdu, pnu, pr0, pnr = _polar_grids(pcen, plen, grid, lam_min, dr, oversample_angle)
        out = np.zeros((len(parents), int(pnu.max()), int(pnr.max())), np.complex64)
        _merge_kernel(G, u0, du, nu, r0, nr, centres, dr, factor, o, ea, er, pcen, pu0, pdu, pnu, pr0, dr, pnr,
                      cyc_per_m, tu, tr, out)
        G, centres, weights = out, pcen, pw
        u0, du, nu, r0, nr = pu0, pdu, pnu, pr0, pnr
        samples.append(int((nu * nr).sum()))
        done += 1
        if progress:
            progress(done, n_levels)
    img = np.zeros((grid.azimuth.size, grid.range.size), np.complex64)
    _final_kernel(G, u0, du, nu, r0, nr, centres, dr, o, ea, er, np.asarray(grid.azimuth, np.float64),
                  np.asarray(grid.range, np.float64), cyc_per_m, tu, tr, img)
    done += 1
    if progress:
        progress(done, done)
    return img, {"ffbp_levels": done, "ffbp_leaf_pulses": leaf, "ffbp_polar_samples": int(np.mean(samples))}


@register_former("ffbp")
def form_ffbp(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = 8,
              progress=None) -> ImageResult:
    """Fast factorised backprojection (the registered ``ffbp`` former), normalised as ``bp``.

    Parameters
    ----------
    ph : PhaseHistory
        Spotlight collection, any trajectory.
    grid : ImageGrid
    window : Window
        Over the pulses and in range.
    upsample : int
        Range-profile upsampling of the first level, at most ``LEAF_UPSAMPLE`` (its 4-tap
        least-squares kernel is exact to -70 dB there).
    progress : callable, optional
        ``progress(done, total)`` in levels.

    Returns
    -------
    ImageResult

    Raises
    ------
    ScenarioError
        For stripmap data (its beam equalisation is done by ``bp``).
    """
    if ph.mode == "stripmap" and ph.real_aperture > 0:
        raise ScenarioError("processing.algorithm", "ffbp", "fast factorised backprojection is for spotlight "
                            "data here; use bp for stripmap (it equalises the beam)")
    P, M = ph.data.shape
    wa = window(P)
    wr = window(M)
    img, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, grid, wa, wr,
                     upsample=min(upsample, LEAF_UPSAMPLE), progress=progress)
    norm = max(float(wa.sum()), 1e-30) * float(wr.sum())
    info.update({"support_azimuth": P, "support_range": M})
    return ImageResult((img / norm).astype(np.complex64), info)
