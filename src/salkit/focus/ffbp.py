"""Fast factorised backprojection (Ulander, Hellsten and Stenström 2003).

The aperture is split into sub-apertures of a few pulses; each is backprojected onto a polar
grid of its own (range r from its centre c and direction cosine u = (x - c).e_a / r along the
plane's azimuth axis), whose angular spacing only has to resolve what a short aperture can
resolve. Neighbouring sub-images are then merged, four at a time, onto the polar grid of their
union (four times the angular samples, a quarter as many images), the last merge by two, until
two remain; those are interpolated onto the output grid. Each level costs about one output image
of work, so the whole costs N^2 log N instead of the N^3 of direct backprojection.

Sub-images are stored at baseband: g(x) = v(x) exp(-j k |x - c|), v the backprojected value and
k = 4 pi f_c / c, so g is smooth (its range bandwidth is the pulse's, its angular bandwidth
L / lambda per unit u for a sub-aperture of length L) and can be interpolated; the phase
k (|x - c_child| - |x - c_parent|) is put back exactly, in float64, at every merge. A point in the
plane is found from (r, u) in closed form, so the antenna may follow any trajectory; the polar
grids of each level are sized from the image's extent as seen from each sub-aperture centre.

Interpolation: least-squares optimal kernels (``interpolation_table``) designed for each grid's
oversampling: 8 taps in angle, 8 in range, 8 on the pulses' range profiles. The profiles are
sampled at the polar grids' range spacing, so every step is a range pass along lines that move
one source bin per point. Each merge interpolates separably: the parent's line of points crosses
the child's range bins in order, so the child is first cut along the line in angle at its own
range bins, then the cut is interpolated in range (16 taps instead of 64); the last step does the
same along the image's rows. Both passes run in segments where the interpolation fraction moves
little and linearly, with weights linear along the segment, over contiguous floats (SIMD).

Precision: sub-images are at baseband about |x - c| - rho_c, rho_c = |c - o| (o the scene
centre), and every phase is formed from small differences (|x - a| - |x - b| =
(b - a).(2 (x - b) + (b - a)) / (|x - a| + |x - b|)), never from two ranges of hundreds of
kilometres each rounded to 6e-11 m. Each polar grid keeps :data:`MARGIN_ANGLE` and
:data:`MARGIN_RANGE` samples outside the image, enough for the next level's taps.

Accuracy knobs: ``oversample_angle`` and ``oversample_range`` (samples per Nyquist interval of
the polar grids), ``range_taps`` and ``leaf`` (pulses backprojected directly into each
first-level sub-image). Defaults (1.75, 2.0, 8, 16): -56.5 to -61 dB image error against the exact
matched filter on the test geometries (:mod:`salkit.simulate.testbeds`); :data:`ACCURATE`
(2.5, 2.5): -64 to -73 dB. docs/performance.md gives the accuracy-speed curve.
"""
from __future__ import annotations

import math

import numpy as np
from numba import get_num_threads, njit, prange

from ..choices import ACCURACY, check_choice
from ..constants import SPEED_OF_LIGHT
from ..errors import ScenarioError
from ..signals.windows import Window
from .backprojection import _sincos_cycles, range_profiles
from .formers import ImageGrid, ImageResult, register_former
from .phasehistory import PhaseHistory
from ..tolerances import BP_UPSAMPLE

#: Default accuracy settings (image error -56.5 to -61 dB against the exact matched filter).
LEAF_PULSES = 16
#: Sub-images merged into each parent (4: fewer levels than 2, the same accuracy; the last merge is by 2).
MERGE_FACTOR = 4
OVERSAMPLE_ANGLE = 1.75
OVERSAMPLE_RANGE = 2.0
#: Taps of the angular interpolation (the range one has 6).
ANGLE_TAPS = 8
#: Leaves use the series for R - |X - c| where it is exact enough (tests switch it off to compare).
SERIES = True
#: Taps of the merges' range interpolation.
RANGE_TAPS = 8
#: The accuracy setting (``processing.accuracy = "high"``): -64 to -73 dB against the exact
#: matched filter, about 1.3x the default's time.
ACCURATE = {"oversample_angle": 2.5, "oversample_range": 2.5}
#: Taps of the leaves' range interpolation of the pulses' profiles.
LEAF_TAPS = 8
#: Samples kept outside the image's extent on each side of a polar grid, in angle and in range:
#: enough that the next level's interpolation of its own margin finds every tap (4 were too few
#: for 8 taps: the image's edges lost 10 to 15 dB).
MARGIN_ANGLE = 5
MARGIN_RANGE = 6


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
    return np.ascontiguousarray(np.linalg.solve(A, rhs.T).T, dtype=np.float32)


@njit(cache=True, inline="always", fastmath=True, error_model="numpy")
def _rotate(vr, vi, cyc):
    """(vr + j vi) exp(j 2 pi cyc), the cycles reduced in float64 before the float32 sin/cos."""
    y = np.float32(cyc - np.floor(cyc + 0.5))
    s, c = _sincos_cycles(y)
    return vr * c - vi * s, vr * s + vi * c


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _polar_line(o, ea, er, cen, r0, dr, n, u, X0, X1, X2, rl):
    """The plane points of one polar line (direction cosine u along ea, ranges r0 + k dr from
    ``cen``, on the far side of ``cen`` along er) written into ``X0, X1, X2`` and their ranges into
    ``rl`` (the caller's buffers, at least ``n`` long: no allocation per line), and the first and
    last index that lie in the plane (top < lo: none; entries before lo are not set).

    A point at range r exists where r^2 (1 - u^2) >= h^2, h the distance from ``cen`` to the
    plane's line along ea through the foot of ``cen``: from a range found in closed form on, so
    the loop over the line has no branch and vectorises.
    """
    d0 = o[0] - cen[0]
    d1 = o[1] - cen[1]
    d2 = o[2] - cen[2]
    da = d0 * ea[0] + d1 * ea[1] + d2 * ea[2]
    dg = d0 * er[0] + d1 * er[1] + d2 * er[2]
    h2 = d0 * d0 + d1 * d1 + d2 * d2 - da * da - dg * dg
    w = 1.0 - u * u
    if w <= 0.0:
        return n, -1
    lo = 0
    if h2 > 0.0:
        lo = max(0, int(math.ceil((math.sqrt(h2 / w) - r0) / dr)))
        while lo < n and (r0 + lo * dr) ** 2 * w < h2:
            lo += 1
    if lo >= n:
        return n, -1
    x0 = X0[lo:]
    x1 = X1[lo:]
    x2 = X2[lo:]
    rr = rl[lo:]
    oa0 = o[0] - da * ea[0] - dg * er[0]
    oa1 = o[1] - da * ea[1] - dg * er[1]
    oa2 = o[2] - da * ea[2] - dg * er[2]
    for q in range(n - lo):
        r = r0 + (lo + q) * dr
        rr[q] = r
        sa = r * u
        t = math.sqrt(max(r * r * w - h2, 0.0))
        x0[q] = oa0 + sa * ea[0] + t * er[0]
        x1[q] = oa1 + sa * ea[1] + t * er[1]
        x2[q] = oa2 + sa * ea[2] + t * er[2]
    return lo, n - 1


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _leaf_line(prof, rp0, inv_drp, pos, ref, qrel, weight, first, count, cen, X0, X1, X2, r_line, cyc_per_m, tr,
               acc2, fr_b, sn_b, cs_b, t2, E0, E1, E2, h, series):
    """Backproject a leaf's pulses onto one polar line of points (baseband): per pulse, the
    profile bin position and phase of every point (SIMD), then the range pass (the profiles are
    sampled at the polar grids' range spacing, so the line moves one profile bin per point).

    The phase k ((R - |X - c|) - (R_ref - rho)) is formed from small differences only:
    R - |X - c| = (2 q.(X - c) + |q|^2) / (R + |X - c|), q = c - p (``qrel`` holds q, |q|^2 and
    R_ref - rho per pulse), so it stays exact at 560 km where R and |X - c| alone carry 6e-11 m
    of rounding (5e-4 rad at 1.55 um). With ``series`` (the caller's bound on the leaf's extent
    against its range keeps the truncation below 1e-5 rad) the quotient is the series
    x (1 - s + 2 s^2), x = num / 2r, s = x / 2r, and R = r + (R - r): no square root or division
    per point and pulse. ``E0, E1, E2, h`` are scratch of at least the line's length.
    """
    n = X0.shape[0]
    nb = prof.shape[1] // 2
    for k in range(n):
        E0[k] = X0[k] - cen[0]
        E1[k] = X1[k] - cen[1]
        E2[k] = X2[k] - cen[2]
        h[k] = 0.5 / r_line[k]
    for p in range(first, first + count):
        px = pos[p, 0]
        py = pos[p, 1]
        pz = pos[p, 2]
        rp = ref[p] + rp0
        q0 = 2.0 * qrel[p, 0]
        q1 = 2.0 * qrel[p, 1]
        q2 = 2.0 * qrel[p, 2]
        qq = qrel[p, 3]
        rf = qrel[p, 4]
        wp = weight[p]
        if series:
            for k in range(n):
                x = (q0 * E0[k] + q1 * E1[k] + q2 * E2[k] + qq) * h[k]
                sx = x * h[k]
                dif = x * (1.0 - sx * (1.0 - 2.0 * sx))
                fr_b[k] = (r_line[k] + dif - rp) * inv_drp
                cyc = (dif - rf) * cyc_per_m
                y = np.float32(cyc - np.floor(cyc + 0.5))
                sn, cs = _sincos_cycles(y)
                sn_b[k] = sn * wp
                cs_b[k] = cs * wp
        else:
            for k in range(n):
                e0 = X0[k] - px
                e1 = X1[k] - py
                e2 = X2[k] - pz
                R = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                fr_b[k] = (R - rp) * inv_drp
                dif = (q0 * E0[k] + q1 * E1[k] + q2 * E2[k] + qq) / (R + r_line[k])
                cyc = (dif - rf) * cyc_per_m
                y = np.float32(cyc - np.floor(cyc + 0.5))
                sn, cs = _sincos_cycles(y)
                sn_b[k] = sn * wp
                cs_b[k] = cs * wp
        _range_pass(fr_b, n, prof[p], 0, nb - 1, fr_b[n - 1] - fr_b[0], tr, sn_b, cs_b, acc2, t2)


def _chunks() -> int:
    """How many chunks the parallel kernels split their lines into: four a thread (each chunk
    allocates its line buffers once; read here, outside the kernels, so that they cache)."""
    return 4 * get_num_threads()


@njit(cache=True)
def _line_scratch(n, n_child_bins):
    """Buffers for the lines of one chunk, each at least ``n`` points long: the points X0, X1, X2
    and their ranges; E0, E1, E2; the bin fractions and angle indices (float64); sin and cos
    (float32); the interleaved accumulator and range-pass buffer (2 n float32); a child's cut
    (``n_child_bins`` float32); a zero ``extra`` (float64)."""
    return (np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n),
            np.empty(n), np.empty(n), np.empty(n, np.float32), np.empty(n, np.float32),
            np.empty(2 * n, np.float32), np.empty(2 * n, np.float32), np.empty(n_child_bins, np.float32),
            np.zeros(n))


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _leaf_kernel(prof, rp0, inv_drp, pos, ref, qrel, weight, first, count, cen, o, ea, er,
                 u0, du, nu, r0, dr, nr, cyc_per_m, tr, out, series, chunks):
    """Backproject each leaf's pulses onto its polar grid, at baseband (``LEAF_TAPS``-tap
    least-squares interpolation of range profiles sampled at the grid's range spacing)."""
    S, NU, NR = out.shape
    n_jobs = S * NU
    n_chunks = max(1, min(n_jobs, chunks))
    for ch in prange(n_chunks):
        # one set of line buffers a chunk of lines, not a line (an allocation per line is a page
        # fault per line where the allocator trims eagerly, as in a Dask worker's thread)
        X0, X1, X2, rl, E0, E1, E2, fr_b, v_b, sn_b, cs_b, acc2, t2, _h2, _z = _line_scratch(NR, 0)
        for job in range(ch * n_jobs // n_chunks, (ch + 1) * n_jobs // n_chunks):
            s = job // NU
            iu = job % NU
            orow = out[s, iu]
            for k in range(NR):  # every sample written (the grids are reused buffers, not zeroed)
                orow[k] = 0j
            if iu >= nu[s]:
                continue
            lo, top = _polar_line(o, ea, er, cen[s], r0[s], dr, nr[s], u0[s] + iu * du[s], X0, X1, X2, rl)
            if top <= lo:
                continue
            m = top + 1 - lo
            for k in range(2 * m):
                acc2[k] = np.float32(0.0)
            _leaf_line(prof, rp0, inv_drp, pos, ref, qrel, weight, first[s], count[s], cen[s], X0[lo:top + 1],
                       X1[lo:top + 1], X2[lo:top + 1], rl[lo:top + 1], cyc_per_m, tr, acc2[:2 * m], fr_b[:m],
                       sn_b[:m], cs_b[:m], t2[:2 * m], E0, E1, E2, v_b, series)
            seg = out[s, iu, lo:top + 1]
            for k in range(m):
                seg[k] = complex(acc2[2 * k], acc2[2 * k + 1])


#: Largest move of an interpolation fraction within one segment of constant weights' slope, samples.
SEG_FRACTION = 0.03125
#: Largest departure of the fraction from linear across a segment, samples (error below -70 dB).
SEG_CURVATURE = 2e-4
#: Longest segment, samples.
SEG_MAX = 512
#: Point index of each interleaved float along a segment (0, 0, 1, 1, ...), read instead of
#: computed: converting the int64 index to float32 has no packed instruction without AVX-512DQ,
#: which left the passes scalar on AVX2 (FFBP 3x slower there than with AVX-512).
RAMP2 = (np.arange(2 * SEG_MAX) >> 1).astype(np.float32)


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _angle_at(j, fr_b, v_b, n, inv_slope):
    """The child angle index at child range bin j, linear between the line's points (``inv_slope``:
    points per bin on average, for the first guess of the bracketing pair)."""
    k = int((j - fr_b[0]) * inv_slope)
    k = min(max(k, 0), n - 2)
    while k > 0 and fr_b[k] > j:
        k -= 1
    while k < n - 2 and fr_b[k + 1] <= j:
        k += 1
    return v_b[k] + (v_b[k + 1] - v_b[k]) * (j - fr_b[k]) / (fr_b[k + 1] - fr_b[k])


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _segment_end(f0, f_at_e, f_at_mid, chord, floor0, floor_e):
    """Whether a segment whose fraction goes f0 -> f_at_e (f_at_mid at a middle point where the
    chord between the ends is ``chord``) keeps one integer part and moves little and linearly
    enough for weights linear along it."""
    return (floor_e == floor0 and abs(f_at_e - f0) <= SEG_FRACTION
            and abs(f_at_mid - chord) <= SEG_CURVATURE)


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _range_pass(fr_b, n, h2, j_lo, j_hi, span, tr, sn_b, cs_b, acc2, t2):
    """Interpolate a line's source (float32 (re, im) interleaved, bins j_lo .. j_hi) in range at
    each point's bin position ``fr_b`` (increasing; ``span`` = fr_b[n-1] - fr_b[0]) with the table
    ``tr`` (an even number of taps, from ir - taps/2 + 1 to ir + taps/2 around bin ir), rotate by
    (cs, sn) and add to ``acc2``; points whose taps leave j_lo .. j_hi are skipped. Where the line
    moves one bin per point (a polar line against a source sampled as its range), in segments of
    weights linear along the segment over contiguous floats (SIMD); otherwise point by point.
    """
    T = tr.shape[0] - 1
    taps = tr.shape[1]
    hb = taps // 2 - 1
    k_lo = 0
    while k_lo < n and int(math.floor(fr_b[k_lo])) - hb < j_lo:
        k_lo += 1
    k_hi = n - 1
    while k_hi >= k_lo and int(math.floor(fr_b[k_hi])) + taps - hb - 1 > j_hi:
        k_hi -= 1
    if abs(span - (n - 1)) > 0.01 * (n - 1):  # not one bin per point (an image row): point by point
        for k in range(k_lo, k_hi + 1):
            fr = fr_b[k]
            ir = int(math.floor(fr))
            it = int((fr - ir) * T + 0.5)
            b0 = 2 * (ir - hb - j_lo)
            vr = np.float32(0.0)
            vi = np.float32(0.0)
            for b in range(taps):
                vr += tr[it, b] * h2[b0 + 2 * b]
                vi += tr[it, b] * h2[b0 + 2 * b + 1]
            acc2[2 * k] += vr * cs_b[k] - vi * sn_b[k]
            acc2[2 * k + 1] += vr * sn_b[k] + vi * cs_b[k]
        return
    # loops run over slices from 0 (an index that may be negative gets numba's wraparound, which
    # LLVM vectorises with scatters)
    tz = t2[2 * k_lo:2 * (k_hi + 1)]
    if taps != 8:  # the 8-tap segments assign every float
        for q in range(tz.shape[0]):
            tz[q] = np.float32(0.0)
    k = k_lo
    while k <= k_hi:
        f0 = fr_b[k]
        ir = int(math.floor(f0))
        off = ir - k
        e = min(k + SEG_MAX - 1, k_hi)
        if e > k:  # the fraction fr - (index) drifts slowly: first guess from its local drift
            d = abs(fr_b[k + 1] - f0 - 1.0)
            if d > 0.0:
                e = min(e, k + max(int(SEG_FRACTION / d), 1))
        while e > k:
            km = (k + e) // 2
            fe = fr_b[e] - (e + off)
            fm = fr_b[km] - (km + off)
            chord = (f0 - ir) + (fe - (f0 - ir)) * (km - k) / (e - k)
            if _segment_end(f0 - ir, fe, fm, chord, 0, int(math.floor(fe))):
                break
            e = k + (e - k) // 2
        m2 = 2 * (e + 1 - k)
        t0 = f0 - ir
        t1 = fr_b[e] - math.floor(fr_b[e])
        i0 = int(t0 * T + 0.5)
        i1 = int(t1 * T + 0.5)
        inv_m = np.float32(1.0 / (e - k)) if e > k else np.float32(0.0)
        tt = t2[2 * k:2 * k + m2]
        if taps == 8:  # the taps in registers, one store a float (LLVM will not interchange the loops)
            s0 = 2 * (k + off - hb - j_lo)
            src = h2[s0:s0 + m2 + 14]
            w0, w1, w2, w3 = tr[i0, 0], tr[i0, 1], tr[i0, 2], tr[i0, 3]
            w4, w5, w6, w7 = tr[i0, 4], tr[i0, 5], tr[i0, 6], tr[i0, 7]
            d0 = (tr[i1, 0] - w0) * inv_m
            d1 = (tr[i1, 1] - w1) * inv_m
            d2 = (tr[i1, 2] - w2) * inv_m
            d3 = (tr[i1, 3] - w3) * inv_m
            d4 = (tr[i1, 4] - w4) * inv_m
            d5 = (tr[i1, 5] - w5) * inv_m
            d6 = (tr[i1, 6] - w6) * inv_m
            d7 = (tr[i1, 7] - w7) * inv_m
            for q in range(m2):
                r = RAMP2[q]
                tt[q] = ((w0 + d0 * r) * src[q] + (w1 + d1 * r) * src[q + 2] + (w2 + d2 * r) * src[q + 4]
                         + (w3 + d3 * r) * src[q + 6] + (w4 + d4 * r) * src[q + 8] + (w5 + d5 * r) * src[q + 10]
                         + (w6 + d6 * r) * src[q + 12] + (w7 + d7 * r) * src[q + 14])
        else:
            for b in range(taps):
                src = h2[2 * (k + off - hb + b - j_lo):2 * (k + off - hb + b - j_lo) + m2]
                wb = tr[i0, b]
                dwb = (tr[i1, b] - wb) * inv_m
                for q in range(m2):
                    tt[q] += (wb + dwb * RAMP2[q]) * src[q]
        k = e + 1
    sv = sn_b[k_lo:k_hi + 1]
    cv = cs_b[k_lo:k_hi + 1]
    a2 = acc2[2 * k_lo:2 * (k_hi + 1)]
    for q in range(sv.shape[0]):  # phase restored
        vr = tz[2 * q]
        vi = tz[2 * q + 1]
        a2[2 * q] += vr * cv[q] - vi * sv[q]
        a2[2 * q + 1] += vr * sv[q] + vi * cv[q]


@njit(cache=True, fastmath=True, boundscheck=False, error_model="numpy")
def _accumulate_child(Gf, c, u0c, duc, nuc, r0c, nrc, cx, cy, cz, dr_child, ea0, ea1, ea2, X0, X1, X2, E0, E1, E2,
                      r_line, extra, q0, q1, q2, qq, drho, cyc_per_m, tu, tr, acc2, fr_b, v_b, sn_b, cs_b, h2, t2):
    """Add child ``c`` (baseband, interpolated, phase restored) along one parent line of points.

    ``Gf`` holds the children's grids as float32, (re, im) interleaved along range; ``acc2`` the
    line's accumulator, interleaved too. The parent line crosses the child's range bins in order,
    so the 2-D interpolation separates (14 taps instead of 48). Pass 1 (SIMD): every point's child
    range bin (fraction) and angle index, and the phase k (r_c - r) as float32 sin/cos after a
    float64 reduction. Pass 2: the child cut along the line in angle at each of its own range bins
    the line crosses; pass 3: that cut interpolated in range at every point. Both run in segments
    where the fraction keeps its integer part, moves by at most ``SEG_FRACTION`` and departs from
    linear by at most ``SEG_CURVATURE``: there the weights are linear along the segment and the
    inner loops run over contiguous floats (SIMD). Points are assumed valid (the caller trims the
    line to its points in the plane).
    """
    n = X0.shape[0]
    inv_dr = 1.0 / dr_child
    inv_du = 1.0 / duc
    T = tr.shape[0] - 1
    for k in range(n):
        e0 = X0[k] - cx
        e1 = X1[k] - cy
        e2 = X2[k] - cz
        rc = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        fr_b[k] = (rc - r0c) * inv_dr
        v_b[k] = ((e0 * ea0 + e1 * ea1 + e2 * ea2) / rc - u0c) * inv_du
        # k ((|X - c_child| - rho_child) - (|X - c_line| - rho_line) + extra), from small differences
        dif = (q0 * E0[k] + q1 * E1[k] + q2 * E2[k] + qq) / (rc + r_line[k])
        cyc = (dif - drho + extra[k]) * cyc_per_m
        y = np.float32(cyc - np.floor(cyc + 0.5))
        sn, cs = _sincos_cycles(y)
        sn_b[k] = sn
        cs_b[k] = cs
    if n < 2:
        return
    # pass 2: the child cut along the line, on the child's range bins j_lo .. j_hi, into h2
    hb = tr.shape[1] // 2 - 1
    j_lo = max(int(math.floor(fr_b[0])) - hb, 0)
    j_hi = min(int(math.floor(fr_b[n - 1])) + tr.shape[1] - hb - 1, nrc - 1)
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
                b0 = iu - ha
                x0 = Gf[c, b0, g:g + m2]
                x1 = Gf[c, b0 + 1, g:g + m2]
                x2 = Gf[c, b0 + 2, g:g + m2]
                x3 = Gf[c, b0 + 3, g:g + m2]
                x4 = Gf[c, b0 + 4, g:g + m2]
                x5 = Gf[c, b0 + 5, g:g + m2]
                x6 = Gf[c, b0 + 6, g:g + m2]
                x7 = Gf[c, b0 + 7, g:g + m2]
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
def _line_from_children(Gf, c0, c1, cu0, cdu, cnu, cr0, cnr, ccen, crho, lcen, lrho, dr_child, ea, X0, X1, X2,
                        r_line, extra, cyc_per_m, tu, tr, orow, E0, E1, E2, acc2, fr_b, v_b, sn_b, cs_b, h2, t2):
    """Children c0 .. c1 - 1 summed along one line of points (a parent's polar line or an image
    row) into ``orow``, each interpolated and moved from its baseband to the line's:
    exp(j k ((|X - c_child| - rho_child) - (|X - c_line| - rho_line) + extra)), ``r_line`` =
    |X - c_line|, ``extra`` 0 for a parent and |X - o| for the image (baseband about the origin
    with rho 0, then undone). The range differences are formed from small ones:
    |X - a|^2 - |X - b|^2 = (b - a).(2 (X - b) + (b - a)). The rest are the caller's scratch
    (:func:`_line_scratch`), sliced here to the line: no allocation per line."""
    m = X0.shape[0]
    E0 = E0[:m]
    E1 = E1[:m]
    E2 = E2[:m]
    acc2 = acc2[:2 * m]
    fr_b = fr_b[:m]
    v_b = v_b[:m]
    sn_b = sn_b[:m]
    cs_b = cs_b[:m]
    t2 = t2[:2 * m]
    for k in range(m):
        E0[k] = X0[k] - lcen[0]
        E1[k] = X1[k] - lcen[1]
        E2[k] = X2[k] - lcen[2]
    for k in range(2 * m):
        acc2[k] = np.float32(0.0)
    for c in range(c0, c1):
        q0 = lcen[0] - ccen[c, 0]
        q1 = lcen[1] - ccen[c, 1]
        q2 = lcen[2] - ccen[c, 2]
        _accumulate_child(Gf, c, cu0[c], cdu[c], cnu[c], cr0[c], cnr[c], ccen[c, 0], ccen[c, 1], ccen[c, 2], dr_child,
                          ea[0], ea[1], ea[2], X0, X1, X2, E0, E1, E2, r_line, extra, 2.0 * q0, 2.0 * q1, 2.0 * q2,
                          q0 * q0 + q1 * q1 + q2 * q2, crho[c] - lrho, cyc_per_m, tu, tr, acc2, fr_b, v_b, sn_b,
                          cs_b, h2, t2)
    for k in range(m):
        orow[k] = complex(acc2[2 * k], acc2[2 * k + 1])


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _merge_kernel(Gf, cu0, cdu, cnu, cr0, cnr, ccen, crho, dr_child, factor, o, ea, er, cen, rho, u0, du, nu, r0, dr,
                  nr, cyc_per_m, tu, tr, out, chunks):
    """Merge ``factor`` consecutive child sub-images into each parent's polar grid."""
    S, NU, NR = out.shape
    n_child = Gf.shape[0]
    n_jobs = S * NU
    n_chunks = max(1, min(n_jobs, chunks))
    for ch in prange(n_chunks):
        X0, X1, X2, rl, E0, E1, E2, fr_b, v_b, sn_b, cs_b, acc2, t2, h2, zero = _line_scratch(NR, Gf.shape[2])
        for job in range(ch * n_jobs // n_chunks, (ch + 1) * n_jobs // n_chunks):
            s = job // NU
            iu = job % NU
            orow = out[s, iu]
            for k in range(NR):  # every sample written (the grids are reused buffers, not zeroed)
                orow[k] = 0j
            if iu >= nu[s]:
                continue
            lo, top = _polar_line(o, ea, er, cen[s], r0[s], dr, nr[s], u0[s] + iu * du[s], X0, X1, X2, rl)
            if top < lo:
                continue
            _line_from_children(Gf, s * factor, min(s * factor + factor, n_child), cu0, cdu, cnu, cr0, cnr, ccen,
                                crho, cen[s], rho[s], dr_child, ea, X0[lo:top + 1], X1[lo:top + 1], X2[lo:top + 1],
                                rl[lo:top + 1], zero[:top + 1 - lo], cyc_per_m, tu, tr, out[s, iu, lo:top + 1], E0,
                                E1, E2, acc2, fr_b, v_b, sn_b, cs_b, h2, t2)


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _final_kernel(G, cu0, cdu, cnu, cr0, cnr, ccen, crho, dr_child, o, ea, er, az, rg, cyc_per_m, tu, tr, out):
    """Every remaining sub-image interpolated onto the output grid (table weights), its phase
    k (|x - c| - rho_c) restored (from small differences, as the merges)."""
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
                g0 = x0 - o[0]
                g1 = x1 - o[1]
                g2 = x2 - o[2]
                a0 = o[0] - ccen[c, 0]
                a1 = o[1] - ccen[c, 1]
                a2 = o[2] - ccen[c, 2]
                ra = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
                num = g0 * (g0 + 2.0 * a0) + g1 * (g1 + 2.0 * a1) + g2 * (g2 + 2.0 * a2)
                vr, vi = _rotate(vr, vi, (num / (rc + ra) + (ra - crho[c])) * cyc_per_m)
                acc_r += vr
                acc_i += vi
            out[i, j] = complex(acc_r, acc_i)


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _final_rows(Gf, cu0, cdu, cnu, cr0, cnr, ccen, crho, dr_child, o, ea, er, az, rg, cyc_per_m, tu, tr, out, chunks):
    """Every remaining sub-image interpolated onto the output grid row by row, separably (as a
    merge: a row along the range axis crosses each child's range bins in order when every child
    centre lies on the near side of the image, which the caller checks), its phase k |x - c|
    restored (the line's baseband about the origin o with rho 0, undone by ``extra`` = |x - o|)."""
    nx, ny = out.shape
    n_chunks = max(1, min(nx, chunks))
    for ch in prange(n_chunks):
        X0, X1, X2, d, E0, E1, E2, fr_b, v_b, sn_b, cs_b, acc2, t2, h2, _z = _line_scratch(ny, Gf.shape[2])
        for i in range(ch * nx // n_chunks, (ch + 1) * nx // n_chunks):
            for k in range(ny):
                X0[k] = o[0] + az[i] * ea[0] + rg[k] * er[0]
                X1[k] = o[1] + az[i] * ea[1] + rg[k] * er[1]
                X2[k] = o[2] + az[i] * ea[2] + rg[k] * er[2]
                d[k] = math.sqrt(az[i] * az[i] + rg[k] * rg[k])
            _line_from_children(Gf, 0, Gf.shape[0], cu0, cdu, cnu, cr0, cnr, ccen, crho, o, 0.0, dr_child, ea, X0, X1,
                                X2, d, d, cyc_per_m, tu, tr, out[i], E0, E1, E2, acc2, fr_b, v_b, sn_b, cs_b, h2, t2)


def _rows_in_order(o: np.ndarray, er: np.ndarray, centres: np.ndarray, rg: np.ndarray) -> bool:
    """Whether every image row (a line along ``er``) crosses each sub-aperture's range bins in
    order: the range from a centre c grows along the row wherever (x - c).er > 0, so it is
    enough that the row's first point lies beyond every centre along er."""
    return rg.size > 1 and float(np.min((o - centres) @ er)) + float(rg[0]) > 0.0


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
        n_u = int(math.ceil((hi - lo) / du[s])) + 1 + 2 * MARGIN_ANGLE
        u0[s] = lo - MARGIN_ANGLE * du[s]
        nu[s] = n_u
        r0[s] = rmin - MARGIN_RANGE * dr
        nr[s] = int(math.ceil((float(R.max()) - rmin) / dr)) + 1 + 2 * MARGIN_RANGE
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
         azimuth_window: np.ndarray, range_window: np.ndarray, leaf: int = LEAF_PULSES, factor: int = MERGE_FACTOR,
         oversample_angle: float = OVERSAMPLE_ANGLE, oversample_range: float = OVERSAMPLE_RANGE,
         range_taps: int = RANGE_TAPS, progress=None) -> tuple[np.ndarray, dict]:
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
    leaf : int
        Pulses per first-level sub-image.
    factor : int
        Sub-images merged into each parent.
    oversample_angle, oversample_range : float
        Polar-grid samples per Nyquist interval (the range profiles are sampled at the grids'
        range spacing, ``oversample_range`` or a little more: an FFT length).
    range_taps : int
        Taps of the merges' range interpolation (even).
    progress : callable, optional
        ``progress(done, total)`` in levels.

    Returns
    -------
    (complex64 (nx, ny), dict)
        The image and the sizes of the factorisation (levels, polar samples).
    """
    P, M = ph.shape
    c = SPEED_OF_LIGHT
    lam_min = c / float(freq[-1])
    f_c = float(freq[M // 2])
    cyc_per_m = 2.0 * f_c / c
    # range profiles sampled at the polar grids' range spacing (at least oversample_range per
    # resolution cell): a polar line then moves one profile bin per point
    prof, rp0, dr, _ = range_profiles(ph, freq, oversample_range, np.asarray(range_window, np.float64))
    plane = grid.plane
    o = np.ascontiguousarray(plane.origin, np.float64)
    ea = np.ascontiguousarray(plane.azimuth, np.float64)
    er = np.ascontiguousarray(plane.range, np.float64)
    step = float(np.median(np.linalg.norm(np.diff(positions, axis=0), axis=1))) if P > 1 else 0.0
    tu = interpolation_table(ANGLE_TAPS, oversample_angle)
    tr = interpolation_table(range_taps, prof.shape[1] / M)
    tl = interpolation_table(LEAF_TAPS, prof.shape[1] / M)
    w = np.asarray(azimuth_window, np.float32)
    # level 0: leaves of `leaf` pulses
    groups = [(a, min(a + leaf, P)) for a in range(0, P, leaf)]
    weights = np.array([max(float(w[a:b].sum()), 1e-30) for a, b in groups])
    centres = np.array([positions[a:b].mean(axis=0) for a, b in groups])
    lengths = _lengths(positions, groups, centres, ea, step)
    n_levels, S = 2, len(groups)  # leaves, merges, final
    while S > 2:
        S = -(-S // (factor if S > factor else 2))
        n_levels += 1
    done = 0
    u0, du, nu, r0, nr = _polar_grids(centres, lengths, grid, lam_min, dr, oversample_angle)
    # two buffers used in turn by the levels (one read, one written): their pages are faulted in
    # once, not at every level (page faults inside the parallel kernels cost up to half a merge)
    pool = [np.empty(0, np.complex64), np.empty(0, np.complex64)]

    def grid_buffer(level, shape):
        size = int(np.prod(shape))
        if pool[level % 2].size < size:
            pool[level % 2] = np.empty(size, np.complex64)
        return pool[level % 2][:size].reshape(shape)

    G = grid_buffer(0, (len(groups), int(nu.max()), int(nr.max())))
    first = np.array([a for a, _ in groups], np.int64)
    count = np.array([b - a for a, b in groups], np.int64)
    rho = np.linalg.norm(centres - o, axis=1)
    leaf_of = np.repeat(np.arange(len(groups)), count)
    q = centres[leaf_of] - positions
    qrel = np.ascontiguousarray(np.column_stack([q, np.einsum("ij,ij->i", q, q), ref_range - rho[leaf_of]]))
    # the leaves' series for R - |X - c| (no sqrt or division) where its truncation, about
    # 5 x^4 / (2 r)^3 with x the leaf's extent and r the nearest polar range, stays below 1e-5 rad
    x_max = float(np.max(np.linalg.norm(q, axis=1))) if q.size else 0.0
    r_min = float(np.min(r0))
    series = SERIES and r_min > 0 and 5.0 * x_max ** 4 / (2.0 * r_min) ** 3 * 4.0 * math.pi / lam_min < 1e-5
    _leaf_kernel(prof.view(np.float32), rp0, 1.0 / dr, positions, ref_range, qrel, w, first, count, centres, o, ea,
                 er, u0, du, nu, r0, dr, nr, cyc_per_m, tl, G, series, _chunks())
    samples = [int((nu * nr).sum())]
    done += 1
    if progress:
        progress(done, n_levels)
    # merge `factor` at a time, the last merge by two, until two sub-images remain for the final step
    spans = list(groups)
    while G.shape[0] > 2:
        S = G.shape[0]
        f_level = factor if S > factor else 2
        parents = [(i, min(i + f_level, S)) for i in range(0, S, f_level)]
        spans = [(spans[a][0], spans[b - 1][1]) for a, b in parents]
        pw = np.array([weights[a:b].sum() for a, b in parents])
        pcen = np.array([(centres[a:b] * weights[a:b, None]).sum(axis=0) / pw[k] for k, (a, b) in enumerate(parents)])
        plen = _lengths(positions, spans, pcen, ea, step)
        pu0, pdu, pnu, pr0, pnr = _polar_grids(pcen, plen, grid, lam_min, dr, oversample_angle)
        out = grid_buffer(done, (len(parents), int(pnu.max()), int(pnr.max())))
        prho = np.linalg.norm(pcen - o, axis=1)
        _merge_kernel(G.view(np.float32), u0, du, nu, r0, nr, centres, rho, dr, f_level, o, ea, er, pcen, prho, pu0,
                      pdu, pnu, pr0, dr, pnr, cyc_per_m, tu, tr, out, _chunks())
        G, centres, weights, rho = out, pcen, pw, prho
        u0, du, nu, r0, nr = pu0, pdu, pnu, pr0, pnr
        samples.append(int((nu * nr).sum()))
        done += 1
        if progress:
            progress(done, n_levels)
    img = np.zeros((grid.azimuth.size, grid.range.size), np.complex64)
    az, rg = np.asarray(grid.azimuth, np.float64), np.asarray(grid.range, np.float64)
    if _rows_in_order(o, er, centres, rg):
        _final_rows(G.view(np.float32), u0, du, nu, r0, nr, centres, rho, dr, o, ea, er, az, rg, cyc_per_m, tu, tr,
                    img, _chunks())
    else:
        _final_kernel(G, u0, du, nu, r0, nr, centres, rho, dr, o, ea, er, az, rg, cyc_per_m, tu, tr, img)
    done += 1
    if progress:
        progress(done, done)
    return img, {"ffbp_levels": done, "ffbp_leaf_pulses": leaf, "ffbp_polar_samples": int(np.mean(samples))}


@register_former("ffbp")
def form_ffbp(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
              accuracy: str = "standard", progress=None) -> ImageResult:
    """Fast factorised backprojection (the registered ``ffbp`` former), normalised as ``bp``.

    Parameters
    ----------
    ph : PhaseHistory
        Spotlight collection, any trajectory.
    grid : ImageGrid
    window : Window
        Over the pulses and in range.
    upsample : int
        Not used (the shared calling convention of the formers): the leaves read range profiles
        sampled at the polar grids' range spacing through an 8-tap least-squares kernel.
    accuracy : {"standard", "high"}
        "standard" (the module defaults) or "high" (:data:`ACCURATE`).
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
    check_choice("processing.accuracy", accuracy, ACCURACY)
    knobs = ACCURATE if accuracy == "high" else {}
    img, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, grid, wa, wr, progress=progress, **knobs)
    norm = max(float(wa.sum()), 1e-30) * float(wr.sum())
    info.update({"support_azimuth": P, "support_range": M})
    return ImageResult((img / norm).astype(np.complex64), info)
