"""Fast factorised backprojection (Ulander, Hellsten and Stenström 2003).

The aperture is split into sub-apertures of a few pulses; each is backprojected onto a polar
grid of its own (range r from its centre c and direction cosine u = (x - c).e_a / r along the
plane's azimuth axis), whose angular spacing only has to resolve what a short aperture can
resolve. Neighbouring sub-images are then merged, two by two, onto the polar grid of their union
(twice the angular samples, half as many images), until a few remain; those are interpolated onto
the output grid. Each level costs about one output image of work, so the whole costs
N^2 log N instead of the N^3 of direct backprojection.

Sub-images are stored at baseband: g(x) = v(x) exp(-j k |x - c|), v the backprojected value and
k = 4 pi f_c / c, so g is smooth (its range bandwidth is the pulse's, its angular bandwidth
L / lambda per unit u for a sub-aperture of length L) and can be interpolated; the phase
k (|x - c_child| - |x - c_parent|) is put back exactly, in float64, at every merge. A point in the
plane is found from (r, u) in closed form, so the antenna may follow any trajectory; the polar
grids of each level are sized from the image's extent as seen from each sub-aperture centre.

Accuracy knobs: ``oversample_angle`` and ``oversample_range`` (samples per Nyquist interval of
the polar grids, with 4-point Lagrange interpolation) and ``leaf`` (pulses backprojected directly
into each first-level sub-image). docs/performance.md gives the accuracy-speed curve.
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
LEAF_PULSES = 16
OVERSAMPLE_ANGLE = 3.0
OVERSAMPLE_RANGE = 2.5
#: Range-profile upsampling of the first level over the one asked of direct backprojection.
LEAF_UPSAMPLE_FACTOR = 1
MARGIN = 3  # samples kept outside the image's extent on each side of a polar grid


@njit(cache=True, inline="always", fastmath=True)
def _lagrange4(t):
    """Weights of samples -1, 0, 1, 2 for cubic Lagrange interpolation at 0 <= t < 1."""
    tm1 = t - 1.0
    tm2 = t - 2.0
    tp1 = t + 1.0
    return (-t * tm1 * tm2 / 6.0, tp1 * tm1 * tm2 / 2.0, -tp1 * t * tm2 / 2.0, tp1 * t * tm1 / 6.0)


@njit(cache=True, inline="always", fastmath=True)
def _lagrange6(t):
    """Weights of samples -2 .. 3 for quintic Lagrange interpolation at 0 <= t < 1."""
    a = t + 2.0
    b = t + 1.0
    c = t - 1.0
    d = t - 2.0
    e = t - 3.0
    return (-t * b * c * d * e / 120.0, a * t * c * d * e / 24.0, -a * b * c * d * e / 12.0,
            a * b * t * d * e / 12.0, -a * b * t * c * e / 24.0, a * b * t * c * d / 120.0)


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
def _gather66(G, sub, iu, ir, wu, wr):
    """Sum of the 6 x 6 neighbourhood of sample (iu, ir) of sub-image ``sub`` with weights wu (angle)
    and wr (range): float32 (re, im)."""
    vr = np.float32(0.0)
    vi = np.float32(0.0)
    for a in range(6):
        row = G[sub, iu - 2 + a]
        rr = np.float32(0.0)
        ri = np.float32(0.0)
        for b in range(6):
            z = row[ir - 2 + b]
            w = np.float32(wr[b])
            rr += w * z.real
            ri += w * z.imag
        w = np.float32(wu[a])
        vr += w * rr
        vi += w * ri
    return vr, vi


@njit(cache=True, fastmath=True, inline="always")
def _sample(G, sub, u0, du, nu, r0, dr, nr, x0, x1, x2, cen, ea):
    """Interpolate sub-image ``sub`` (baseband) at the plane point x; returns (re, im, r_child)
    or zeros outside its grid."""
    e0 = x0 - cen[sub, 0]
    e1 = x1 - cen[sub, 1]
    e2 = x2 - cen[sub, 2]
    rc = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    uc = (e0 * ea[0] + e1 * ea[1] + e2 * ea[2]) / rc
    fu = (uc - u0[sub]) / du[sub]
    fr = (rc - r0[sub]) / dr
    iu = int(math.floor(fu))
    ir = int(math.floor(fr))
    if iu < 2 or ir < 2 or iu + 3 >= nu[sub] or ir + 3 >= nr[sub]:
        return np.float32(0.0), np.float32(0.0), rc
    vr, vi = _gather66(G, sub, iu, ir, _lagrange6(fu - iu), _lagrange6(fr - ir))
    return vr, vi, rc


@njit(parallel=True, cache=True, fastmath=True)
def _leaf_kernel(prof, rp0, inv_drp, pos, ref, weight, first, count, cen, o, ea, er,
                 u0, du, nu, r0, dr, nr, cyc_per_m, out):
    """Backproject each leaf's pulses onto its polar grid, at baseband (cubic interpolation of the
    range profiles)."""
    S, NU, NR = out.shape
    hi = prof.shape[1] - 3.0
    for job in prange(S * NU):
        s = job // NU
        iu = job % NU
        if iu >= nu[s]:
            continue
        u = u0[s] + iu * du[s]
        for ir in range(nr[s]):
            r = r0[s] + ir * dr
            x0, x1, x2 = _plane_point(o, ea, er, cen[s], r, u)
            if x0 != x0:
                continue
            acc_r = np.float32(0.0)
            acc_i = np.float32(0.0)
            for p in range(first[s], first[s] + count[s]):
                e0 = x0 - pos[p, 0]
                e1 = x1 - pos[p, 1]
                e2 = x2 - pos[p, 2]
                R = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                xi = (R - ref[p] - rp0) * inv_drp
                if xi < 1.0 or xi > hi:
                    continue
                i0 = int(xi)
                w = _lagrange4(xi - i0)
                vr = np.float32(0.0)
                vi = np.float32(0.0)
                for b in range(4):
                    z = prof[p, i0 - 1 + b]
                    wb = np.float32(w[b])
                    vr += wb * z.real
                    vi += wb * z.imag
                vr, vi = _rotate(vr * weight[p], vi * weight[p], (R - r - ref[p]) * cyc_per_m)
                acc_r += vr
                acc_i += vi
            out[s, iu, ir] = complex(acc_r, acc_i)


@njit(cache=True, fastmath=True, boundscheck=False)
def _accumulate_child(G, c, u0c, duc, nuc, r0c, nrc, cx, cy, cz, dr_child, ea, X0, X1, X2, r_line, cyc_per_m,
                      acc_r, acc_i, iu_b, ir_b, tu_b, tr_b, sn_b, cs_b):
    """Add child ``c`` (baseband, interpolated, phase restored) along one parent line of points.

    Pass 1 works on whole arrays with no gathers, so it vectorises: child coordinates, the
    interpolation indices and fractions, and the phase k (r_c - r) as float32 sin/cos after a
    float64 reduction. Pass 2 gathers the 6 x 6 neighbourhood of each point."""
    n = X0.shape[0]
    inv_du = 1.0 / duc
    inv_dr = 1.0 / dr_child
    for k in range(n):
        e0 = X0[k] - cx
        e1 = X1[k] - cy
        e2 = X2[k] - cz
        rc = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        uc = (e0 * ea[0] + e1 * ea[1] + e2 * ea[2]) / rc
        fu = (uc - u0c) * inv_du
        fr = (rc - r0c) * inv_dr
        fu_f = math.floor(fu)
        fr_f = math.floor(fr)
        iu_b[k] = np.int32(fu_f)
        ir_b[k] = np.int32(fr_f)
        tu_b[k] = np.float32(fu - fu_f)
        tr_b[k] = np.float32(fr - fr_f)
        cyc = (rc - r_line[k]) * cyc_per_m
        y = np.float32(cyc - math.floor(cyc + 0.5))
        sn, cs = _sincos_cycles(y)
        sn_b[k] = sn
        cs_b[k] = cs
    for k in range(n):
        iu = iu_b[k]
        ir = ir_b[k]
        if iu < 2 or ir < 2 or iu + 3 >= nuc or ir + 3 >= nrc or X0[k] != X0[k]:
            continue
        vr, vi = _gather66(G, c, iu, ir, _lagrange6(tu_b[k]), _lagrange6(tr_b[k]))
        sn = sn_b[k]
        cs = cs_b[k]
        acc_r[k] += vr * cs - vi * sn
        acc_i[k] += vr * sn + vi * cs


@njit(parallel=True, cache=True, fastmath=True)
def _merge_kernel(G, cu0, cdu, cnu, cr0, cnr, ccen, dr_child, factor, o, ea, er, cen, u0, du, nu, r0, dr, nr,
                  cyc_per_m, out):
    """Merge ``factor`` consecutive child sub-images into each parent's polar grid."""
    S, NU, NR = out.shape
    n_child = G.shape[0]
    for job in prange(S * NU):
        s = job // NU
        iu = job % NU
        if iu >= nu[s]:
            continue
        n = nr[s]
        u = u0[s] + iu * du[s]
        X0 = np.empty(n)
        X1 = np.empty(n)
        X2 = np.empty(n)
        rl = np.empty(n)
        for ir in range(n):
            r = r0[s] + ir * dr
            rl[ir] = r
            X0[ir], X1[ir], X2[ir] = _plane_point(o, ea, er, cen[s], r, u)
        acc_r = np.zeros(n, np.float32)
        acc_i = np.zeros(n, np.float32)
        iu_b = np.empty(n, np.int32)
        ir_b = np.empty(n, np.int32)
        tu_b = np.empty(n, np.float32)
        tr_b = np.empty(n, np.float32)
        sn_b = np.empty(n, np.float32)
        cs_b = np.empty(n, np.float32)
        for c in range(s * factor, min(s * factor + factor, n_child)):
            _accumulate_child(G, c, cu0[c], cdu[c], cnu[c], cr0[c], cnr[c], ccen[c, 0], ccen[c, 1], ccen[c, 2],
                              dr_child, ea, X0, X1, X2, rl, cyc_per_m, acc_r, acc_i, iu_b, ir_b, tu_b, tr_b,
                              sn_b, cs_b)
        for ir in range(n):
            out[s, iu, ir] = complex(acc_r[ir], acc_i[ir])


@njit(parallel=True, cache=True, fastmath=True)
def _final_kernel(G, cu0, cdu, cnu, cr0, cnr, ccen, dr_child, o, ea, er, az, rg, cyc_per_m, out):
    """Every remaining sub-image interpolated onto the output grid, its phase k |x - c| restored."""
    nx, ny = out.shape
    for i in prange(nx):
        for j in range(ny):
            x0 = o[0] + az[i] * ea[0] + rg[j] * er[0]
            x1 = o[1] + az[i] * ea[1] + rg[j] * er[1]
            x2 = o[2] + az[i] * ea[2] + rg[j] * er[2]
            acc_r = np.float32(0.0)
            acc_i = np.float32(0.0)
            for c in range(G.shape[0]):
                vr, vi, rc = _sample(G, c, cu0, cdu, cnu, cr0, dr_child, cnr, x0, x1, x2, ccen, ea)
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
         azimuth_window: np.ndarray, range_window: np.ndarray, upsample: int = 8, leaf: int = LEAF_PULSES,
         factor: int = 2, oversample_angle: float = OVERSAMPLE_ANGLE, oversample_range: float = OVERSAMPLE_RANGE,
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
        Range-profile upsampling for the first level.
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
    prof, rp0, drp, _ = range_profiles(ph, freq, upsample * LEAF_UPSAMPLE_FACTOR, np.asarray(range_window, np.float64))
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
                 u0, du, nu, r0, dr, nr, cyc_per_m, G)
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
                      cyc_per_m, out)
        G, centres, weights = out, pcen, pw
        u0, du, nu, r0, nr = pu0, pdu, pnu, pr0, pnr
        samples.append(int((nu * nr).sum()))
        done += 1
        if progress:
            progress(done, n_levels)
    img = np.zeros((grid.azimuth.size, grid.range.size), np.complex64)
    _final_kernel(G, u0, du, nu, r0, nr, centres, dr, o, ea, er, np.asarray(grid.azimuth, np.float64),
                  np.asarray(grid.range, np.float64), cyc_per_m, img)
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
        Range-profile upsampling of the first level.
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
    img, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, grid, wa, wr, upsample=upsample,
                     progress=progress)
    norm = max(float(wa.sum()), 1e-30) * float(wr.sum())
    info.update({"support_azimuth": P, "support_range": M})
    return ImageResult((img / norm).astype(np.complex64), info)
