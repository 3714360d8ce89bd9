"""Fast factorised backprojection's kernels, part two (numba): the merges of child sub-images
into their parent's polar grid, and the last interpolation onto the image's rows. The driver is
:mod:`salkit.focus.ffbp`; the leaves and the range pass are in :mod:`salkit.focus.ffbp_leaves`.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .ffbp_leaves import (RAMP2, SEG_FRACTION, SEG_MAX, _angle_at, _polar_line_terms, _range_pass,
                          _reduced, _rotate, _segment_end, _sincos_pass, _sincos_reduced, _tap_range)
from .simd import WIDTH, taps8_sym7, wide_vectors

#: Taps of the angular interpolation (the range one has 6).
ANGLE_TAPS = 8

#: The merges' first pass computes its points' sin and cos in the same loop as their float64
#: geometry with AVX-512 code, where they overlap the square root's and divisions' latency (a
#: merge 4 % faster than in two loops), and in a float32 loop of their own with AVX2 code, whose
#: 16 registers the fused loop spills (10 % faster in two loops).
FUSED_SINCOS = wide_vectors()


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _cut_bins(fr_b, n, taps, n_bins):
    """The child range bins j_lo .. j_hi a line's cut must cover: every tap of every point's range
    interpolation (points at bin positions ``fr_b[:n]``, increasing), within the child's
    ``n_bins`` (j_hi < j_lo: none)."""
    hb = taps // 2 - 1
    return max(int(math.floor(fr_b[0])) - hb, 0), min(int(math.floor(fr_b[n - 1])) + taps - hb - 1, n_bins - 1)


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _eight_rows(Gf, c, b0, g, n2):
    """Child ``c``'s angle rows b0 .. b0 + 7, floats g .. g + n2 - 1 of each: the eight taps'
    sources of an angle pass, as views."""
    return (Gf[c, b0, g:g + n2], Gf[c, b0 + 1, g:g + n2], Gf[c, b0 + 2, g:g + n2], Gf[c, b0 + 3, g:g + n2],
            Gf[c, b0 + 4, g:g + n2], Gf[c, b0 + 5, g:g + n2], Gf[c, b0 + 6, g:g + n2], Gf[c, b0 + 7, g:g + n2])


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _child_point(k, r_line, t_line, na, nb, nc, aa, ab, ac, inv_dr, r0s, inv_du, u0s, cyc_per_m, dk):
    """A line's point k against a child (:func:`_accumulate_child`'s first pass): its child range
    bin and angle index, and the phase k ((|X - c_child| - rho_child) - (|X - c_line| - rho_line))
    in cycles, from small differences. The point's r and t (:func:`_polar_line_terms`) enter
    |X - c_child|^2 - |X - c_line|^2 = na + nb r + nc t and (X - c_child).a = aa + ab r + ac t."""
    rl = r_line[k]
    tk = t_line[k]
    num = na + nb * rl + nc * tk
    rc = math.sqrt(rl * rl + num)
    return rc * inv_dr - r0s, (aa + ab * rl + ac * tk) / rc * inv_du - u0s, num / (rc + rl) * cyc_per_m - dk


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _accumulate_child(Gf, c, u0c, duc, nuc, r0c, nrc, dr_child, r_line, t_line, na, nb, nc, aa, ab, ac, drho,
                      cyc_per_m, tu, tr, acc2, fr_b, v_b, sn_b, cs_b, h2, t2):
    """Add child ``c`` (baseband, interpolated, phase restored) along one parent line of points.

    ``Gf`` holds the children's grids as float32, (re, im) interleaved along range; ``acc2`` the
    line's accumulator, interleaved too. The parent line crosses the child's range bins in order,
    so the 2-D interpolation separates (14 taps instead of 48). Pass 1 (SIMD): every point's child
    range bin (fraction) and angle index, and the phase k (r_c - r) as float32 sin/cos after a
    float64 reduction. The line's points enter as their ranges ``r_line`` and across-track terms
    ``t_line`` (X - c_line = f + r u e_a + t e_r:
    :func:`~salkit.focus.ffbp_leaves._polar_line_terms`), the child as six numbers
    (:func:`_line_from_children`): |X - c_child|^2 = r^2 + na + nb r + nc t, whose last three terms
    are the numerator of the phase's small difference too, and (X - c_child).a = aa + ab r + ac t
    along the child's angle axis a: two arrays read a point where the point's offsets took five.
    Pass 2: the child cut along the line in angle at each of its own range bins the line crosses;
    pass 3: that cut interpolated in range at every point. Both run in segments
    where the fraction keeps its integer part, moves by at most ``SEG_FRACTION`` and departs from
    linear by at most ``SEG_CURVATURE``: there the weights are linear along the segment and the
    inner loops run over contiguous floats (SIMD). Points are assumed valid (the caller trims the
    line to its points in the plane).
    """
    n = r_line.shape[0]
    inv_dr = 1.0 / dr_child
    inv_du = 1.0 / duc
    r0s = r0c * inv_dr
    u0s = u0c * inv_du
    dk = drho * cyc_per_m
    T = tr.shape[0] - 1
    if FUSED_SINCOS:
        for k in range(n):
            fr_b[k], v_b[k], cyc = _child_point(k, r_line, t_line, na, nb, nc, aa, ab, ac, inv_dr, r0s, inv_du, u0s,
                                                cyc_per_m, dk)
            sn_b[k], cs_b[k] = _sincos_reduced(cyc)
    else:
        for k in range(n):
            fr_b[k], v_b[k], cyc = _child_point(k, r_line, t_line, na, nb, nc, aa, ab, ac, inv_dr, r0s, inv_du, u0s,
                                                cyc_per_m, dk)
            sn_b[k] = _reduced(cyc)
        _sincos_pass(sn_b, cs_b, n, np.float32(1.0))
    if n < 2:
        return
    # pass 2: the child cut along the line, on the child's range bins j_lo .. j_hi, into h2
    j_lo, j_hi = _cut_bins(fr_b, n, tr.shape[1], nrc)
    if j_hi < j_lo:
        return
    ha = ANGLE_TAPS // 2 - 1
    span = fr_b[n - 1] - fr_b[0]
    inv_slope = (n - 1) / span if span > 0.0 else 0.0
    j = j_lo
    while j <= j_hi:
        f0 = _angle_at(j, fr_b, v_b, n, inv_slope)
        iu = int(math.floor(f0))
        e = min(j + SEG_MAX - 1, j_hi)
        if e > j:  # first guess from the local slope, then halve until the segment qualifies
            f1 = _angle_at(j + 1, fr_b, v_b, n, inv_slope)
            d = abs(f1 - f0)
            if d > 0.0:  # room to the integer boundary it moves towards
                room = min(SEG_FRACTION, (iu + 1 - f0) if f1 > f0 else (f0 - iu))
                e = min(e, j + max(int(room / d), 1))
            while e > j:
                fe = _angle_at(e, fr_b, v_b, n, inv_slope)
                fm = _angle_at(0.5 * (j + e), fr_b, v_b, n, inv_slope)
                if _segment_end(f0, fe, fm, 0.5 * (f0 + fe), iu, int(math.floor(fe))):
                    break
                e = j + (e - j) // 2
        m2 = 2 * (e + 1 - j)
        hh = h2[2 * (j - j_lo):2 * (j - j_lo) + m2]
        if iu >= ha and iu + ANGLE_TAPS - ha <= nuc:
            t0 = f0 - iu
            t1 = _angle_at(e, fr_b, v_b, n, inv_slope) - iu
            i0 = int(t0 * T + 0.5)
            i1 = int(t1 * T + 0.5)
            inv_m = np.float32(1.0 / (e - j)) if e > j else np.float32(0.0)
            g = 2 * j
            if ANGLE_TAPS == 8:  # the eight child rows at once: one store a float
                x0, x1, x2, x3, x4, x5, x6, x7 = _eight_rows(Gf, c, iu - ha, g, m2)
                w0, w1, w2, w3 = tu[i0, 0], tu[i0, 1], tu[i0, 2], tu[i0, 3]
                w4, w5, w6, w7 = tu[i0, 4], tu[i0, 5], tu[i0, 6], tu[i0, 7]
                d0 = (tu[i1, 0] - w0) * inv_m
                d1 = (tu[i1, 1] - w1) * inv_m
                d2 = (tu[i1, 2] - w2) * inv_m
                d3 = (tu[i1, 3] - w3) * inv_m
                d4 = (tu[i1, 4] - w4) * inv_m
                d5 = (tu[i1, 5] - w5) * inv_m
                d6 = (tu[i1, 6] - w6) * inv_m
                d7 = (tu[i1, 7] - w7) * inv_m
                if i0 == i1:  # one table row for the whole segment: constant weights
                    for q in range(m2):
                        hh[q] = (w0 * x0[q] + w1 * x1[q] + w2 * x2[q] + w3 * x3[q] + w4 * x4[q] + w5 * x5[q]
                                 + w6 * x6[q] + w7 * x7[q])
                else:
                    for q in range(m2):
                        r = RAMP2[q]
                        hh[q] = ((w0 + d0 * r) * x0[q] + (w1 + d1 * r) * x1[q] + (w2 + d2 * r) * x2[q]
                                 + (w3 + d3 * r) * x3[q] + (w4 + d4 * r) * x4[q] + (w5 + d5 * r) * x5[q]
                                 + (w6 + d6 * r) * x6[q] + (w7 + d7 * r) * x7[q])
            else:
                for q in range(m2):
                    hh[q] = np.float32(0.0)
                for a in range(ANGLE_TAPS):  # one child row at a time: three pointers, so it vectorises
                    row = Gf[c, iu - ha + a, g:g + m2]
                    wa = tu[i0, a]
                    dwa = (tu[i1, a] - wa) * inv_m
                    for q in range(m2):
                        hh[q] += (wa + dwa * RAMP2[q]) * row[q]
        else:
            for q in range(m2):
                hh[q] = np.float32(0.0)
        j = e + 1
    # pass 3: the cut interpolated in range at every point, phase restored
    _range_pass(fr_b, n, h2, j_lo, j_hi, span, tr, sn_b, cs_b, acc2, t2)


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _line_from_children(Gf, c0, c1, cu0, cdu, cnu, cr0, cnr, ccen, crho, lcen, lrho, dr_child, ea, er, cax, own, u, f0,
                        f1, f2, r_line, t_line, cyc_per_m, tu, tr, acc2, fr_b, v_b, sn_b, cs_b, h2, t2):
    """Children c0 .. c1 - 1 summed along one parent's polar line of points into ``acc2`` (the line's
    samples in the parent's grid as float32 (re, im), zeroed by the caller), each interpolated and
    moved from its baseband to the line's: exp(j k ((|X - c_child| - rho_child) - (|X - c_line| -
    rho_line))). The points enter as X - c_line = f + r u e_a + t e_r (direction cosine ``u``, f =
    (f0, f1, f2), each point's r and t in ``r_line`` and ``t_line``:
    :func:`~salkit.focus.ffbp_leaves._polar_line_terms`). With d = c_line - c_child, each child is
    six numbers (:func:`_child_point`): |X - c_child|^2 - |X - c_line|^2 = 2 d.(X - c_line) + |d|^2 =
    (2 d.f + |d|^2) + (2 u d.e_a) r + (2 d.e_r) t, and (X - c_child).a = (f + d).a + (u e_a.a) r +
    (e_r.a) t, a the children's angle axis ``ea``, or with ``own`` each child's own ``cax[c]``
    (leaves on their own axes, :mod:`salkit.focus.ffbp_axes`). The rest are the caller's scratch
    (:func:`_merge_scratch`), sliced here to the line: no allocation per line."""
    m = r_line.shape[0]
    fr_b = fr_b[:m]
    v_b = v_b[:m]
    sn_b = sn_b[:m]
    cs_b = cs_b[:m]
    t2 = t2[:2 * m]
    for c in range(c0, c1):
        d0 = lcen[0] - ccen[c, 0]
        d1 = lcen[1] - ccen[c, 1]
        d2 = lcen[2] - ccen[c, 2]
        a0, a1, a2 = (cax[c, 0], cax[c, 1], cax[c, 2]) if own else (ea[0], ea[1], ea[2])
        na = 2.0 * (d0 * f0 + d1 * f1 + d2 * f2) + (d0 * d0 + d1 * d1 + d2 * d2)
        nb = 2.0 * u * (d0 * ea[0] + d1 * ea[1] + d2 * ea[2])
        nc = 2.0 * (d0 * er[0] + d1 * er[1] + d2 * er[2])
        aa = (f0 + d0) * a0 + (f1 + d1) * a1 + (f2 + d2) * a2
        ab = u * (ea[0] * a0 + ea[1] * a1 + ea[2] * a2)
        ac = er[0] * a0 + er[1] * a1 + er[2] * a2
        _accumulate_child(Gf, c, cu0[c], cdu[c], cnu[c], cr0[c], cnr[c], dr_child, r_line, t_line, na, nb, nc, aa,
                          ab, ac, crho[c] - lrho, cyc_per_m, tu, tr, acc2, fr_b, v_b, sn_b, cs_b, h2, t2)


@njit(cache=True)
def _merge_scratch(n, n_child_bins):
    """Buffers for the lines of one chunk of a merge, each at least ``n`` points long: the points'
    r and t (:func:`~salkit.focus.ffbp_leaves._polar_line_terms`), bin fractions and angle indices
    (float64); sin and cos (float32); the range pass's buffer (2 n float32); a child's cut
    (``n_child_bins`` float32)."""
    return (np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n, np.float32), np.empty(n, np.float32),
            np.empty(2 * n, np.float32), np.empty(n_child_bins, np.float32))


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _merge_kernel(Gf, cu0, cdu, cnu, cr0, cnr, ccen, crho, dr_child, factor, o, ea, er, cen, rho, u0, du, nu, r0, dr,
                  nr, cyc_per_m, tu, tr, outf, chunks, cax, own):
    """Merge ``factor`` consecutive child sub-images into each parent's polar grid, ``outf`` (float32
    (re, im) interleaved along range, (parents, angles, 2 ranges): the children's sums are added into
    it in place). The children's direction cosines are to ``ea``, or with ``own`` to their own axes
    ``cax``, (n_child, 3)."""
    S, NU, NR2 = outf.shape
    NR = NR2 // 2
    n_child = Gf.shape[0]
    n_jobs = S * NU
    n_chunks = max(1, min(n_jobs, chunks))
    for ch in prange(n_chunks):
        rl, tl, fr_b, v_b, sn_b, cs_b, t2, h2 = _merge_scratch(NR, Gf.shape[2])
        for job in range(ch * n_jobs // n_chunks, (ch + 1) * n_jobs // n_chunks):
            s = job // NU
            iu = job % NU
            orow = outf[s, iu]
            for k in range(NR2):  # every sample written (the grids are reused buffers, not zeroed)
                orow[k] = np.float32(0.0)
            if iu >= nu[s]:
                continue
            u = u0[s] + iu * du[s]
            lo, top, f0, f1, f2 = _polar_line_terms(o, ea, er, cen[s], r0[s], dr, nr[s], u, rl, tl)
            if top < lo:
                continue
            m = top + 1 - lo
            _line_from_children(Gf, s * factor, min(s * factor + factor, n_child), cu0, cdu, cnu, cr0, cnr, ccen,
                                crho, cen[s], rho[s], dr_child, ea, er, cax, own, u, f0, f1, f2, rl[:m], tl[:m],
                                cyc_per_m, tu, tr, orow[2 * lo:2 * (top + 1)], fr_b, v_b, sn_b, cs_b, h2, t2)


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _image_cycles(g0, g1, g2, a0, a1, a2, rc, rho, res, cyc_per_m):
    """The phase k (|x - c| - rho_c) in cycles that the last step puts back on a child's value at a
    pixel, from small quantities: g = x - o, a = o - c, rc = |x - c|, ``res`` = |o - c| - rho_c
    (computed exactly by the caller), (x - o).((x - o) + 2 (o - c)) / (|x - c| + rho_c) + res.
    (|x - c| and rho_c, hundreds of kilometres each, differenced directly lose a float64 rounding
    of |x - c| at every pixel: 4.9e-4 rad rms at 560 km and 1.55 um, a -64 dB floor.)"""
    return ((g0 * (g0 + 2.0 * a0) + g1 * (g1 + 2.0 * a1) + g2 * (g2 + 2.0 * a2)) / (rc + rho) + res) * cyc_per_m


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _final_kernel(G, cu0, cdu, cnu, cr0, cnr, ccen, crho, cres, dr_child, o, ea, er, az, rg, cyc_per_m, tu, tr, out):
    """Every remaining sub-image interpolated onto the output grid (table weights), its phase
    k (|x - c| - rho_c) restored from small quantities: (|x - c| - |o - c|) from differences and
    ``cres`` = |o - c| - rho_c, rho_c's rounding, computed exactly by the caller."""
    nx, ny = out.shape
    T = tr.shape[0] - 1
    na = tu.shape[1]
    ha = na // 2 - 1
    nr_taps = tr.shape[1]
    hr = nr_taps // 2 - 1
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
                if iu < ha or ir < hr or iu + na - ha > cnu[c] or ir + nr_taps - hr > cnr[c]:
                    continue
                wu = tu[int((fu - iu) * T + 0.5)]
                wr = tr[int((fr - ir) * T + 0.5)]
                vr = np.float32(0.0)
                vi = np.float32(0.0)
                for a in range(na):
                    rr = np.float32(0.0)
                    ri = np.float32(0.0)
                    for b in range(nr_taps):
                        z = G[c, iu - ha + a, ir - hr + b]
                        rr += wr[b] * z.real
                        ri += wr[b] * z.imag
                    vr += wu[a] * rr
                    vi += wu[a] * ri
                g0 = az[i] * ea[0] + rg[j] * er[0]  # x - o
                g1 = az[i] * ea[1] + rg[j] * er[1]
                g2 = az[i] * ea[2] + rg[j] * er[2]
                a0 = o[0] - ccen[c, 0]
                a1 = o[1] - ccen[c, 1]
                a2 = o[2] - ccen[c, 2]
                vr, vi = _rotate(vr, vi, _image_cycles(g0, g1, g2, a0, a1, a2, rc, crho[c], cres[c], cyc_per_m))
                acc_r += vr
                acc_i += vi
            out[i, j] = complex(acc_r, acc_i)


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _angle_cut_bins(Gf, c, nuc, fb, j_lo, m, cps, h2, s2):
    """The child cut in angle at its range bins j_lo .. j_lo + m - 1, each at its own angle index
    ``fb[q]`` (float64), into ``h2`` (float32 (re, im) interleaved; zero where the taps leave the
    grid). The weights are evaluated at every bin from their polynomials, given as the symmetric
    kernel's even and odd parts ``cps`` (float32 (28,):
    :func:`~salkit.focus.profiles.symmetric_coefficients` about s = 0 of
    :func:`~salkit.focus.ffbp_leaves.polynomial_weights`, 8 taps, degree 6), in runs of one integer
    angle index whose inner loop runs over contiguous floats (SIMD): no segments, for cuts
    whose angle moves by a sizeable part of a sample within a few bins. (In the merges, where
    segments of linear weights are long, this was slower: 0.95 s against 0.88 s for the four
    merges at 4096^2 on the wide-angle arc.) ``s2`` (float32, 2 m) is scratch.
    """
    ha = ANGLE_TAPS // 2 - 1
    # the kernel is symmetric (tap 7 - b at -s weighs as tap b at s: c[7 - b, d] = (-1)^d c[b, d]),
    # so sum_b c[b, d] x_b = sum_{b < 4} c[b, d] (x_b +- x_{7 - b}): the pairs' sums for even d,
    # differences for odd d, 28 multiply-adds a float where the eight taps took 56. The coefficients
    # as scalars (loop invariants): pair b's even ones cps[7 b] .. cps[7 b + 3], odd ones after
    e00, e02, e04, e06, o01, o03, o05 = cps[0], cps[1], cps[2], cps[3], cps[4], cps[5], cps[6]
    e10, e12, e14, e16, o11, o13, o15 = cps[7], cps[8], cps[9], cps[10], cps[11], cps[12], cps[13]
    e20, e22, e24, e26, o21, o23, o25 = cps[14], cps[15], cps[16], cps[17], cps[18], cps[19], cps[20]
    e30, e32, e34, e36, o31, o33, o35 = cps[21], cps[22], cps[23], cps[24], cps[25], cps[26], cps[27]
    q = 0
    while q < m:
        iu = int(math.floor(fb[q]))
        e = q
        while e + 1 < m and int(math.floor(fb[e + 1])) == iu:
            e += 1
        n2 = 2 * (e + 1 - q)
        hh = h2[2 * q:2 * q + n2]
        if iu < ha or iu + ANGLE_TAPS - ha > nuc:
            for r in range(n2):
                hh[r] = np.float32(0.0)
            q = e + 1
            continue
        ss = s2[:n2]
        fq = fb[q:e + 1]
        for p in range(e + 1 - q):  # s = 2 t - 1 for both floats of the bin
            v = np.float32(2.0 * (fq[p] - iu) - 1.0)
            ss[2 * p] = v
            ss[2 * p + 1] = v
        g = 2 * (j_lo + q)
        x0, x1, x2, x3, x4, x5, x6, x7 = _eight_rows(Gf, c, iu - ha, g, n2)
        for r in range(n2):  # sum_d s^d sum_b c[b, d] x_b: Horner over d, the taps in mirrored pairs
            p0 = x0[r] + x7[r]
            p1 = x1[r] + x6[r]
            p2 = x2[r] + x5[r]
            p3 = x3[r] + x4[r]
            m0 = x0[r] - x7[r]
            m1 = x1[r] - x6[r]
            m2 = x2[r] - x5[r]
            m3 = x3[r] - x4[r]
            y6 = e06 * p0 + e16 * p1 + e26 * p2 + e36 * p3
            y5 = o05 * m0 + o15 * m1 + o25 * m2 + o35 * m3
            y4 = e04 * p0 + e14 * p1 + e24 * p2 + e34 * p3
            y3 = o03 * m0 + o13 * m1 + o23 * m2 + o33 * m3
            y2 = e02 * p0 + e12 * p1 + e22 * p2 + e32 * p3
            y1 = o01 * m0 + o11 * m1 + o21 * m2 + o31 * m3
            y0 = e00 * p0 + e10 * p1 + e20 * p2 + e30 * p3
            t = ss[r]
            hh[r] = y0 + t * (y1 + t * (y2 + t * (y3 + t * (y4 + t * (y5 + t * y6)))))
        q = e + 1


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _angle_cut_row(Gf, c, nuc, along, r0c, dr, u0c, inv_du, j_lo, j_hi, cps, h2, fb, s2):
    """A child cut along an image row in angle, at each of the child's range bins j_lo .. j_hi,
    into ``h2`` (:func:`_angle_cut_bins`).

    On a row (a line along the plane's range axis, orthogonal to its azimuth axis) the direction
    cosine from the child's centre is exactly u = ``along`` / r, ``along`` = (x - c).e_a for the
    whole row, so each bin's angle index is (along / r_j - u0) / du: no search. Away from the
    middle rows it changes by a sizeable part of a sample within a few bins (a row at the image's
    edge crosses about 90 angle samples: segments of 1/32 sample were two bins long there and
    cost half the last step). ``fb`` (float64) is scratch of at least the cut's length.
    """
    m = j_hi + 1 - j_lo
    for q in range(m):
        fb[q] = (along / (r0c + (j_lo + q) * dr) - u0c) * inv_du
    _angle_cut_bins(Gf, c, nuc, fb, j_lo, m, cps, h2, s2)


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _row_range_pass(fr_b, n, h2, j_lo, j_hi, cr, crs, sn_b, cs_b, acc_re, acc_im, idx, sv):
    """Interpolate a cut (``h2``: float32 (re, im) interleaved, bins j_lo .. j_hi) in range at each
    pixel's bin position ``fr_b`` (increasing), rotate by (cs, sn) and add to ``acc_re, acc_im``;
    pixels whose taps leave j_lo .. j_hi are skipped. For an image row, whose pixels step about
    one bin each, so that the fraction changes at every pixel: the weights are evaluated at each
    pixel from their polynomials ``cr`` (taps, degree + 1) in s = 2 t - 1
    (:func:`~salkit.focus.ffbp_leaves.polynomial_weights`), eight pixels at a time in vector
    registers for eight taps and degree 6 (:data:`~salkit.focus.simd.taps8_sym7`, from the
    kernel's even and odd parts ``crs``: :func:`~salkit.focus.profiles.symmetric_coefficients`
    of ``cr`` about s = 0), the rest one by one. ``idx`` (uint32) and ``sv`` (float32) are
    scratch of at least ``n``.
    """
    taps = cr.shape[0]
    nc = cr.shape[1]
    hb = taps // 2 - 1
    k_lo, k_hi = _tap_range(fr_b, n, taps, j_lo, j_hi)
    for k in range(k_lo, k_hi + 1):  # each pixel's first float and weights' argument
        fr = fr_b[k]
        ir = np.floor(fr)
        idx[k] = np.uint32(2.0 * (ir - (hb + j_lo)))
        sv[k] = np.float32(2.0 * (fr - ir) - 1.0)
    k = k_lo
    if taps == 8 and nc == 7:
        n8 = k_lo + (k_hi + 1 - k_lo) // WIDTH * WIDTH
        for j in range(k_lo, n8, WIDTH):
            taps8_sym7(h2, idx, sv, sn_b, cs_b, acc_re, acc_im, j, crs)
        k = n8
    for j in range(k, k_hi + 1):
        s = sv[j]
        b0 = idx[j]
        vr = np.float32(0.0)
        vi = np.float32(0.0)
        for b in range(taps):
            w = cr[b, nc - 1]
            for d in range(nc - 2, -1, -1):
                w = cr[b, d] + s * w
            vr += w * h2[b0 + 2 * b]
            vi += w * h2[b0 + 2 * b + 1]
        acc_re[j] += vr * cs_b[j] - vi * sn_b[j]
        acc_im[j] += vr * sn_b[j] + vi * cs_b[j]


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _final_rows(Gf, cu0, cdu, cnu, cr0, cnr, ccen, crho, cres, dr_child, o, ea, er, az, rg, cyc_per_m, cps, cr, crs,
                out, chunks):
    """Every remaining sub-image interpolated onto the output grid row by row, separably (as a
    merge: a row along the range axis crosses each child's range bins in order when every child
    centre lies on the near side of the image, which the caller checks): per child, the cut along
    the row in angle at the child's range bins (:func:`_angle_cut_row`), then that cut in range at
    every pixel (:func:`_row_range_pass`), its phase k (|x - c| - rho_c) restored from small
    quantities (:func:`_image_cycles`; ``cres`` = |o - c| - rho_c, computed exactly by the
    caller). ``cps``: the angle weights' polynomials as their even and odd parts
    (:func:`_angle_cut_bins`); ``cr``: the range weights' polynomials, ``crs`` their even and odd
    parts (:func:`_row_range_pass`)."""
    nx, ny = out.shape
    n_bins = Gf.shape[2] // 2
    n_chunks = max(1, min(nx, chunks))
    for ch in prange(n_chunks):
        # a chunk's buffers: the row's bin positions, sin and cos, accumulators, first floats and
        # weights' arguments; the cut, its angle indices and fractions
        fr_b = np.empty(ny)
        sn_b = np.empty(ny, np.float32)
        cs_b = np.empty(ny, np.float32)
        acc_re = np.empty(ny, np.float32)
        acc_im = np.empty(ny, np.float32)
        idx = np.empty(ny, np.uint32)
        sv = np.empty(ny, np.float32)
        h2 = np.empty(2 * n_bins, np.float32)
        fb = np.empty(n_bins)
        s2 = np.empty(2 * n_bins, np.float32)
        for i in range(ch * nx // n_chunks, (ch + 1) * nx // n_chunks):
            for k in range(ny):
                acc_re[k] = np.float32(0.0)
                acc_im[k] = np.float32(0.0)
            for c in range(Gf.shape[0]):
                a0 = o[0] - ccen[c, 0]
                a1 = o[1] - ccen[c, 1]
                a2 = o[2] - ccen[c, 2]
                for k in range(ny):
                    g0 = az[i] * ea[0] + rg[k] * er[0]  # x - o
                    g1 = az[i] * ea[1] + rg[k] * er[1]
                    g2 = az[i] * ea[2] + rg[k] * er[2]
                    rc = math.sqrt((g0 + a0) ** 2 + (g1 + a1) ** 2 + (g2 + a2) ** 2)
                    fr_b[k] = (rc - cr0[c]) / dr_child
                    sn_b[k] = _reduced(_image_cycles(g0, g1, g2, a0, a1, a2, rc, crho[c], cres[c], cyc_per_m))
                _sincos_pass(sn_b, cs_b, ny, np.float32(1.0))
                if ny < 2:
                    continue
                j_lo, j_hi = _cut_bins(fr_b, ny, cr.shape[0], cnr[c])
                if j_hi < j_lo:
                    continue
                along = a0 * ea[0] + a1 * ea[1] + a2 * ea[2] + az[i]  # (x - c).e_a on the whole row
                _angle_cut_row(Gf, c, cnu[c], along, cr0[c], dr_child, cu0[c], 1.0 / cdu[c], j_lo, j_hi, cps, h2,
                               fb, s2)
                _row_range_pass(fr_b, ny, h2, j_lo, j_hi, cr, crs, sn_b, cs_b, acc_re, acc_im, idx, sv)
            for k in range(ny):
                out[i, k] = complex(acc_re[k], acc_im[k])
