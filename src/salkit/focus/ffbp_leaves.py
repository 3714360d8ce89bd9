"""Fast factorised backprojection's kernels, part one (numba): the least-squares interpolation
tables, the polar lines of a sub-image, the leaves (pulses backprojected into the first level's
sub-images) and the segmented range pass every step shares. The driver is :mod:`salkit.focus.ffbp`;
the merges are in :mod:`salkit.focus.ffbp_merges`.
"""
from __future__ import annotations

import functools
import math

import numpy as np
from numba import get_num_threads, njit, prange

from .._blas import serial_blas
from ..signals.phase import sincos_cycles as _sincos_cycles
from .ffbp_axes import _own_line_start, _own_point, _own_weights

#: Fractional positions tabulated per interpolation kernel (nearest entry: a position error of
#: 1/4096 sample, a phase error below 5e-4 rad at the band edge).
TABLE_STEPS = 2048


#: Degree of the polynomials in the fraction that give the weights where they change at every
#: sample (:func:`polynomial_weights`; 6: 7e-6 of the largest weight at 1.75x oversampling).
POLY_DEGREE = 6


def least_squares_weights(taps: int, oversample: float, t: np.ndarray) -> np.ndarray:
    """Least-squares optimal interpolation weights at the fractions ``t``, float64.

    For each fraction t the ``taps`` weights minimise the error of interpolating exp(j 2 pi f t)
    over the band |f| <= 1 / (2 oversample) cycles per sample, flat weighting: the normal
    equations of that fit are a Toeplitz system of sinc functions.

    Parameters
    ----------
    taps : int
        Even number of samples, at offsets -(taps/2 - 1) .. taps/2 from the sample below t.
    oversample : float
        Sampling rate over the signal's bandwidth, > 1.
    t : float64 (K,)
        Fractions in [0, 1], samples.

    Returns
    -------
    float64 (K, taps)

    Examples
    --------
    >>> w = least_squares_weights(8, 1.75, np.array([0.0, 0.5]))
    >>> bool(abs(w[0, 3] - 1.0) < 1e-12), bool(np.allclose(w[1], w[1, ::-1]))
    (True, True)
    """
    offs = np.arange(-(taps // 2 - 1), taps // 2 + 1, dtype=np.float64)
    band = 1.0 / oversample  # two-sided bandwidth, cycles per sample
    A = band * np.sinc(band * (offs[:, None] - offs[None, :]))
    rhs = band * np.sinc(band * (np.asarray(t, np.float64)[:, None] - offs[None, :]))
    return np.linalg.solve(A, rhs.T).T


def interpolation_table(taps: int, oversample: float, steps: int = TABLE_STEPS) -> np.ndarray:
    """Least-squares optimal interpolation weights for a signal band-limited to 1/oversample of
    the sampling rate, tabulated (:func:`least_squares_weights` at ``steps + 1`` fractions).

    At the same oversampling this kernel is 10 to 20 dB better than Lagrange interpolation
    (6 taps at 1.75x: -50 dB against -33 dB, for a flat spectrum).

    Parameters
    ----------
    taps, oversample
        As :func:`least_squares_weights`.
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
    return _table(int(taps), float(oversample), int(steps)).copy()


@functools.lru_cache(maxsize=64)
def _table(taps: int, oversample: float, steps: int) -> np.ndarray:
    """:func:`interpolation_table`, computed once for each set of arguments (read-only; the callers
    get copies): FFBP asks for the same few kernels at every call on a geometry."""
    t = np.arange(steps + 1) / steps
    with serial_blas():  # no BLAS threads left spinning beside the kernels that follow (:mod:`salkit._blas`)
        w = least_squares_weights(taps, oversample, t)
    table = np.ascontiguousarray(w, dtype=np.float32)
    table.setflags(write=False)
    return table


def polynomial_weights(taps: int, oversample: float, degree: int = POLY_DEGREE) -> np.ndarray:
    """The least-squares interpolation weights as polynomials in s = 2 t - 1 (t the fraction):
    weight b at t is sum_d c[b, d] s^d. Fitted by Chebyshev least squares to the float64 weights
    at 4097 fractions; where the fraction changes at every output sample this costs a few
    multiply-adds, vectorised, instead of a table row per sample, and it has no table step
    (the nearest of 2048 entries moves a sample by up to 1/4096).

    Parameters
    ----------
    taps : int
        Even number of samples.
    oversample : float
        Sampling rate over the signal's bandwidth, > 1.
    degree : int
        Polynomial degree.

    Returns
    -------
    float32 (taps, degree + 1)
        Coefficients of s^0 .. s^degree for each tap.

    Examples
    --------
    >>> c = polynomial_weights(8, 1.75)
    >>> t = np.array([0.0, 0.3, 1.0])
    >>> w = np.polynomial.polynomial.polyval(2 * t - 1, c.astype(float).T).T
    >>> bool(np.abs(w - least_squares_weights(8, 1.75, t)).max() < 2e-5)
    True
    """
    return _polynomials(int(taps), float(oversample), int(degree)).copy()


@functools.lru_cache(maxsize=64)
def _polynomials(taps: int, oversample: float, degree: int) -> np.ndarray:
    """:func:`polynomial_weights`, computed once for each set of arguments (read-only; the callers
    get copies)."""
    t = np.linspace(0.0, 1.0, 4097)
    with serial_blas():  # the fit on one BLAS thread: none left spinning beside FFBP's kernels
        w = least_squares_weights(taps, oversample, t)
        cheb = np.polynomial.chebyshev.chebfit(2.0 * t - 1.0, w, degree)  # (degree + 1, taps)
    power = np.stack([np.polynomial.chebyshev.cheb2poly(cheb[:, b]) for b in range(taps)])
    power = np.ascontiguousarray(power, dtype=np.float32)
    power.setflags(write=False)
    return power


@njit(cache=True, inline="always", fastmath=True, error_model="numpy")
def _reduced(cyc):
    """The phase ``cyc`` (cycles, float64) reduced to [-0.5, 0.5] in float64, as float32: what
    a first pass stores for :func:`_sincos_pass`."""
    return np.float32(cyc - np.rint(cyc))


@njit(cache=True, inline="always", fastmath=True, error_model="numpy")
def _sincos_reduced(cyc):
    """sin and cos (float32) of 2 pi ``cyc``, the cycles reduced to [-0.5, 0.5] in float64 before
    the float32 polynomial (phases of any size stay exact): the point-by-point last step's phase."""
    return _sincos_cycles(_reduced(cyc))


@njit(cache=True, inline="always", fastmath=True, error_model="numpy")
def _sincos_pass(sn_b, cs_b, n, w):
    """sin and cos (times ``w``) of the reduced phases ``sn_b[:n]`` (:func:`_reduced`), in place
    into ``sn_b`` and ``cs_b``: a loop of its own, float32 throughout, so that it runs at the
    float32 vector width (twice the float64 one of the first passes that store the phases) and
    without their float64 constants in registers (AVX2 has 16)."""
    for k in range(n):
        s, c = _sincos_cycles(sn_b[k])
        sn_b[k] = s * w
        cs_b[k] = c * w


@njit(cache=True, inline="always", fastmath=True, error_model="numpy")
def _rotate(vr, vi, cyc):
    """(vr + j vi) exp(j 2 pi cyc) (:func:`_sincos_reduced`)."""
    s, c = _sincos_reduced(cyc)
    return vr * c - vi * s, vr * s + vi * c


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _line_start(o, ea, er, cen, r0, dr, n, u):
    """Where the polar line of direction cosine ``u`` from ``cen`` (ranges r0 + k dr, k < n) enters
    the plane: its first index lo (n: never), h^2 (the squared distance from ``cen`` to the plane's
    line along ea through the foot of ``cen``), w = 1 - u^2, the foot's point oa (the line's
    point at range r is oa + r u ea + sqrt(r^2 w - h^2) er) and the foot less ``cen``, f, formed
    from o - cen (:func:`_polar_line_terms`)."""
    d0 = o[0] - cen[0]
    d1 = o[1] - cen[1]
    d2 = o[2] - cen[2]
    da = d0 * ea[0] + d1 * ea[1] + d2 * ea[2]
    dg = d0 * er[0] + d1 * er[1] + d2 * er[2]
    h2 = d0 * d0 + d1 * d1 + d2 * d2 - da * da - dg * dg
    w = 1.0 - u * u
    oa0 = o[0] - da * ea[0] - dg * er[0]
    oa1 = o[1] - da * ea[1] - dg * er[1]
    oa2 = o[2] - da * ea[2] - dg * er[2]
    f0 = d0 - da * ea[0] - dg * er[0]
    f1 = d1 - da * ea[1] - dg * er[1]
    f2 = d2 - da * ea[2] - dg * er[2]
    if w <= 0.0:
        return n, h2, w, oa0, oa1, oa2, f0, f1, f2
    lo = 0
    if h2 > 0.0:
        lo = max(0, int(math.ceil((math.sqrt(h2 / w) - r0) / dr)))
        while lo < n and (r0 + lo * dr) ** 2 * w < h2:
            lo += 1
    return min(lo, n), h2, w, oa0, oa1, oa2, f0, f1, f2


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
    lo, h2, w, oa0, oa1, oa2, _, _, _ = _line_start(o, ea, er, cen, r0, dr, n, u)
    if lo >= n:
        return n, -1
    x0 = X0[lo:]
    x1 = X1[lo:]
    x2 = X2[lo:]
    rr = rl[lo:]
    for q in range(n - lo):
        r = r0 + (lo + q) * dr
        rr[q] = r
        sa = r * u
        t = math.sqrt(max(r * r * w - h2, 0.0))
        x0[q] = oa0 + sa * ea[0] + t * er[0]
        x1[q] = oa1 + sa * ea[1] + t * er[1]
        x2[q] = oa2 + sa * ea[2] + t * er[2]
    return lo, n - 1


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _polar_line_terms(o, ea, er, cen, r0, dr, n, u, rl, tl):
    """One polar line (:func:`_polar_line`) as what a merge reads of it: its points are
    X - ``cen`` = f + r u e_a + t(r) e_r, f the foot of ``cen`` on the plane less ``cen`` (from
    o - cen, never from X: the points' coordinates are not formed), t(r) = sqrt(r^2 (1 - u^2) - h^2).
    Writes each point's range r into ``rl`` and t(r) into ``tl`` from index 0 (the line's point lo
    at 0: two numbers a point, where the points and their offsets took seven), and returns lo, top
    (as :func:`_polar_line`) and f."""
    lo, h2, w, _, _, _, f0, f1, f2 = _line_start(o, ea, er, cen, r0, dr, n, u)
    if lo >= n:
        return n, -1, f0, f1, f2
    for q in range(n - lo):
        r = r0 + (lo + q) * dr
        rl[q] = r
        tl[q] = math.sqrt(max(r * r * w - h2, 0.0))
    return lo, n - 1, f0, f1, f2


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
            rps = rp * inv_drp
            rfc = rf * cyc_per_m
            for k in range(n):
                x = (q0 * E0[k] + q1 * E1[k] + q2 * E2[k] + qq) * h[k]
                sx = x * h[k]
                dif = x * (1.0 - sx * (1.0 - 2.0 * sx))
                fr_b[k] = (r_line[k] + dif) * inv_drp - rps
                sn_b[k] = _reduced(dif * cyc_per_m - rfc)
        else:
            for k in range(n):
                e0 = X0[k] - px
                e1 = X1[k] - py
                e2 = X2[k] - pz
                R = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                fr_b[k] = (R - rp) * inv_drp
                dif = (q0 * E0[k] + q1 * E1[k] + q2 * E2[k] + qq) / (R + r_line[k])
                sn_b[k] = _reduced((dif - rf) * cyc_per_m)
        _sincos_pass(sn_b, cs_b, n, wp)
        _range_pass(fr_b, n, prof[p], 0, nb - 1, fr_b[n - 1] - fr_b[0], tr, sn_b, cs_b, acc2, t2)


def _chunks() -> int:
    """How many chunks the parallel kernels split their lines into: four a thread (each chunk
    allocates its line buffers once; read here, outside the kernels, so that they cache)."""
    return 4 * get_num_threads()


@njit(cache=True)
def _line_scratch(n):
    """Buffers for the leaves' lines of one chunk, each at least ``n`` points long: the points X0,
    X1, X2 and their ranges; E0, E1, E2; the bin fractions and a float64 scratch; sin and cos
    (float32); the interleaved accumulator and range-pass buffer (2 n float32). (A merge's are
    :func:`salkit.focus.ffbp_merges._merge_scratch`.)"""
    return (np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n),
            np.empty(n), np.empty(n), np.empty(n, np.float32), np.empty(n, np.float32),
            np.empty(2 * n, np.float32), np.empty(2 * n, np.float32))


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
        X0, X1, X2, rl, E0, E1, E2, fr_b, v_b, sn_b, cs_b, acc2, t2 = _line_scratch(NR)
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


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _tap_range(fr_b, n, taps, j_lo, j_hi):
    """The first and last of the points at bin positions ``fr_b[:n]`` (increasing) whose ``taps``
    taps (bins ir - taps/2 + 1 .. ir + taps/2 around ir) all lie within j_lo .. j_hi (k_hi < k_lo:
    none)."""
    hb = taps // 2 - 1
    k_lo = 0
    while k_lo < n and int(math.floor(fr_b[k_lo])) - hb < j_lo:
        k_lo += 1
    k_hi = n - 1
    while k_hi >= k_lo and int(math.floor(fr_b[k_hi])) + taps - hb - 1 > j_hi:
        k_hi -= 1
    return k_lo, k_hi


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
    k_lo, k_hi = _tap_range(fr_b, n, taps, j_lo, j_hi)
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
            if i0 == i1:  # one table row for the whole segment: constant weights
                for q in range(m2):
                    tt[q] = (w0 * src[q] + w1 * src[q + 2] + w2 * src[q + 4] + w3 * src[q + 6] + w4 * src[q + 8]
                             + w5 * src[q + 10] + w6 * src[q + 12] + w7 * src[q + 14])
            else:
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


#: Frequencies a block of the FFT leaves' phase ramps (:func:`_leaf_spectra`): the ramp is a table of
#: this many phasors times one a block, so that a frequency costs one complex product, not a sin/cos.
#: Each block's loop pays a set-up (numba's slices, LLVM's checks that the arrays do not overlap) of
#: about a hundred cycles: 256 where 64 took the sums from 1.9 to 1.3 cycles a frequency and pulse
#: (Zen 4, 4096 frequencies; 512: 1.4, the table's sin/cos outgrowing the saving).
RAMP_BLOCK = 256


@njit(parallel=True, nogil=True, cache=True, error_model="numpy")
def _windowed_spectra(ph, wr, are, aim):
    """The FFT leaves' inputs (:func:`salkit.focus.ffbp._leaf_inputs`), a pulse a job on every core:
    ``are[p, :M]``, ``aim[p, :M]`` the real and imaginary parts of ``ph[p]`` (complex, (P, M)) times
    ``wr`` (float32 (M,)), as float32, and zero past M (the padding)."""
    P, M = ph.shape
    for p in prange(P):
        ar = are[p]
        ai = aim[p]
        row = ph[p]
        for m in range(M):
            ar[m] = np.float32(row[m].real * wr[m])
            ai[m] = np.float32(row[m].imag * wr[m])
        for m in range(M, ar.shape[0]):
            ar[m] = np.float32(0.0)
            ai[m] = np.float32(0.0)


@njit(cache=True, fastmath=True, error_model="numpy")
def _ramp_tables(start, step, cyc0, wp, n_hi, t_hi_re, t_hi_im, t_lo_re, t_lo_im):
    """The phasors exp(j 2 pi (cyc0 + (start + m) step)) of m = RAMP_BLOCK h + l as the products of
    two tables: ``t_hi`` (times ``wp``) for h < ``n_hi``, ``t_lo`` for l < RAMP_BLOCK, each phase
    formed and reduced to [-0.5, 0.5] cycles in float64 (one loop), then its sin and cos in float32
    (another: both vectorise)."""
    for hh in range(n_hi):
        t_hi_im[hh] = _reduced(cyc0 + (start + RAMP_BLOCK * hh) * step)
    for ll in range(RAMP_BLOCK):
        t_lo_im[ll] = _reduced(ll * step)
    for hh in range(n_hi):
        s, c = _sincos_cycles(t_hi_im[hh])
        t_hi_re[hh] = c * wp
        t_hi_im[hh] = s * wp
    for ll in range(RAMP_BLOCK):
        s, c = _sincos_cycles(t_lo_im[ll])
        t_lo_re[ll] = c
        t_lo_im[ll] = s


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _ramp_block(are, aim, p, hh, t_hi_re, t_hi_im, g_re, g_im):
    """Block ``hh`` of a ramp sum: its phasor from the high table, pulse p's spectrum and the sums'
    slices (slices from 0: no index that numba must check for wraparound, one vector loop)."""
    b = hh * RAMP_BLOCK
    return (t_hi_re[hh], t_hi_im[hh], are[p, b:b + RAMP_BLOCK], aim[p, b:b + RAMP_BLOCK], g_re[b:b + RAMP_BLOCK],
            g_im[b:b + RAMP_BLOCK])


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _ramp_sum(are, aim, p, n_hi, t_hi_re, t_hi_im, t_lo_re, t_lo_im, g_re, g_im):
    """g += pulse p's spectrum times its phase ramp (:func:`_ramp_tables`), block by block."""
    for hh in range(n_hi):
        tr, ti, ar, ai, gr, gi = _ramp_block(are, aim, p, hh, t_hi_re, t_hi_im, g_re, g_im)
        for m in range(RAMP_BLOCK):
            wr = tr * t_lo_re[m] - ti * t_lo_im[m]
            wi = tr * t_lo_im[m] + ti * t_lo_re[m]
            gr[m] += ar[m] * wr - ai[m] * wi
            gi[m] += ar[m] * wi + ai[m] * wr


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _ramp_sum2(are, aim, p, ap, n_hi, t_hi_re, t_hi_im, t_lo_re, t_lo_im, g_re, g_im, g1_re, g1_im):
    """:func:`_ramp_sum` into g, and its term weighted by ``ap`` into g1 too (the own-axis leaves'
    first-order sum)."""
    a32 = np.float32(ap)
    for hh in range(n_hi):
        tr, ti, ar, ai, gr, gi = _ramp_block(are, aim, p, hh, t_hi_re, t_hi_im, g_re, g_im)
        hr = g1_re[hh * RAMP_BLOCK:hh * RAMP_BLOCK + RAMP_BLOCK]
        hi = g1_im[hh * RAMP_BLOCK:hh * RAMP_BLOCK + RAMP_BLOCK]
        for m in range(RAMP_BLOCK):
            wr = tr * t_lo_re[m] - ti * t_lo_im[m]
            wi = tr * t_lo_im[m] + ti * t_lo_re[m]
            xr = ar[m] * wr - ai[m] * wi
            xi = ar[m] * wi + ai[m] * wr
            gr[m] += xr
            gi[m] += xi
            hr[m] += a32 * xr
            hi[m] += a32 * xi


@njit(cache=True, inline="always", error_model="numpy")
def _line_job(jj, j0, NU, u0, du, nr, lims):
    """Row ``jj`` of a batch starting at job ``j0``: its leaf s, line iu, direction cosine and
    range count, its ``lims`` set to none until the line is formed."""
    job = j0 + jj
    s = job // NU
    iu = job % NU
    lims[jj, 0] = 0
    lims[jj, 1] = -1
    return s, iu, u0[s] + iu * du[s], nr[s]


@njit(cache=True, inline="always", error_model="numpy")
def _ramp_scratch(n_hi):
    """A chunk's tables of phasors (:func:`_ramp_tables`): high (``n_hi``) and low (RAMP_BLOCK), re and im."""
    return (np.empty(n_hi, np.float32), np.empty(n_hi, np.float32), np.empty(RAMP_BLOCK, np.float32),
            np.empty(RAMP_BLOCK, np.float32))


@njit(cache=True, inline="always", error_model="numpy")
def _spectra_sizes(spec, M, dr, are, chunks):
    """The FFT leaves' kernels' sizes: lines, FFT length, the middle frequency's index, the range
    frequency step (cycles a metre), ramp blocks and chunks."""
    L = spec.shape[0]
    nfft = spec.shape[1] // 2
    return L, nfft, M // 2, 1.0 / (nfft * dr), are.shape[1] // RAMP_BLOCK, max(1, min(L, chunks))


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _pulse_ramp(p, dlt, r0s, ref, qrel, weight, dr, nfft, h, step, cyc_per_m, n_hi, t_hi_re, t_hi_im, t_lo_re,
                t_lo_im):
    """Pulse p's phase ramp over the frequencies into the tables (:func:`_ramp_tables`), its range
    against the leaf's centre ``dlt`` taken along the line; returns the profile bin its line's first
    sample reads (rho = r0 + dlt - R_ref,p)."""
    D = r0s + dlt - ref[p]  # rho of the line's first sample
    _ramp_tables(-h, step * D, cyc_per_m * (dlt - qrel[p, 4]), weight[p], n_hi, t_hi_re, t_hi_im, t_lo_re, t_lo_im)
    return D / dr + nfft // 2


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _spectrum_row(row, g_re, g_im, M, h, nfft):
    """The sums of M frequencies into a row of the transform (float32, interleaved, nfft complex
    values): frequency m at bin (m - h) mod nfft, zeros between."""
    for m in range(h, M):
        row[2 * (m - h)] = g_re[m]
        row[2 * (m - h) + 1] = g_im[m]
    for k in range(2 * (M - h), 2 * (nfft - h)):
        row[k] = np.float32(0.0)
    for m in range(h):
        row[2 * (nfft - h + m)] = g_re[m]
        row[2 * (nfft - h + m) + 1] = g_im[m]


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _line_limits(lims, jj, lo, n, off_lo, off_hi, nfft):
    """The points of a leaf's line whose every pulse reads its profile where the interpolating
    leaves would (eight taps inside the profile): the first and last index into ``lims[jj]``."""
    lims[jj, 0] = max(lo, int(math.ceil(3.0 - off_lo)))
    lims[jj, 1] = min(n - 1, int(math.ceil(nfft - 4.0 - off_hi)) - 1)


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _pulse_delta(qrel, p, e0, e1, e2, rc):
    """|x - p| - |x - c| from small differences: x - c = e (|e| = ``rc``), qrel[p] = (c - p, |c - p|^2, ..)."""
    q0 = qrel[p, 0]
    q1 = qrel[p, 1]
    q2 = qrel[p, 2]
    num = 2.0 * (q0 * e0 + q1 * e1 + q2 * e2) + qrel[p, 3]  # |x - p|^2 - |x - c|^2
    f0 = e0 + q0
    f1 = e1 + q1
    f2 = e2 + q2
    return num / (math.sqrt(f0 * f0 + f1 * f1 + f2 * f2) + rc)


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _leaf_spectra(are, aim, M, ref, qrel, weight, first, count, cen, o, ea, er, u0, du, nu, r0, dr, nr, cyc_per_m,
                  j0, NU, spec, lims, chunks):
    """The FFT leaves' first step (``are``, ``aim``: the pulses' windowed spectra, M frequencies
    padded with zeros to a multiple of :data:`RAMP_BLOCK`): for each polar line of jobs ``j0`` ..
    ``j0 + len(spec) - 1`` (job s NU + iu: leaf s, line iu), into its row of ``spec`` (float32,
    interleaved, nfft complex values) the range spectrum whose inverse FFT (``norm="forward"``) is
    the leaf's baseband sum along the line at ranges r0[s] + i dr (a row of zeros where there is no
    line).

    Each pulse p's range profile is read at rho = r + delta_p - R_ref,p, delta_p = |x - p| - |x - c|
    (the pulse's range against the leaf centre's, taken at the line's middle point: along a line
    it changes by less than the caller's bound, :func:`salkit.focus.ffbp.leaf_shift_spread`), so
    its contribution is its windowed spectrum A_p(m) times exp(j 2 pi (beta_m (r0 + delta_p -
    R_ref,p) + k (delta_p - (R_ref,p - rho_c)))), beta_m = (m - M//2) / (nfft dr) and k the
    cycles a metre at f_c: a sum over the pulses for each frequency, then one transform a line,
    with no interpolation of profiles. ``lims[j]`` gets the first and last index of the line
    inside the plane and inside every pulse's profile (none: last < first).
    """
    L, nfft, h, step, n_hi, n_chunks = _spectra_sizes(spec, M, dr, are, chunks)
    for ch in prange(n_chunks):
        g_re = np.empty(n_hi * RAMP_BLOCK, np.float32)
        g_im = np.empty(n_hi * RAMP_BLOCK, np.float32)
        t_hi_re, t_hi_im, t_lo_re, t_lo_im = _ramp_scratch(n_hi)
        for jj in range(ch * L // n_chunks, (ch + 1) * L // n_chunks):
            s, iu, u, n = _line_job(jj, j0, NU, u0, du, nr, lims)
            row = spec[jj]
            lo, h2, w, oa0, oa1, oa2, _, _, _ = _line_start(o, ea, er, cen[s], r0[s], dr, n, u)
            if iu >= nu[s] or lo >= n:  # no line: its row is transformed all the same
                row[:] = np.float32(0.0)
                continue
            rm = r0[s] + 0.5 * (lo + n - 1) * dr  # the line's middle point
            t = math.sqrt(max(rm * rm * w - h2, 0.0))
            e0 = oa0 + rm * u * ea[0] + t * er[0] - cen[s, 0]
            e1 = oa1 + rm * u * ea[1] + t * er[1] - cen[s, 1]
            e2 = oa2 + rm * u * ea[2] + t * er[2] - cen[s, 2]
            rc = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            for m in range(g_re.shape[0]):
                g_re[m] = np.float32(0.0)
                g_im[m] = np.float32(0.0)
            off_lo = np.inf
            off_hi = -np.inf
            for p in range(first[s], first[s] + count[s]):
                off = _pulse_ramp(p, _pulse_delta(qrel, p, e0, e1, e2, rc), r0[s], ref, qrel, weight, dr, nfft, h,
                                  step, cyc_per_m, n_hi, t_hi_re, t_hi_im, t_lo_re, t_lo_im)
                off_lo = min(off_lo, off)
                off_hi = max(off_hi, off)
                _ramp_sum(are, aim, p, n_hi, t_hi_re, t_hi_im, t_lo_re, t_lo_im, g_re, g_im)
            _spectrum_row(row, g_re, g_im, M, h, nfft)
            _line_limits(lims, jj, lo, n, off_lo, off_hi, nfft)


@njit(parallel=True, nogil=True, cache=True, fastmath=True, error_model="numpy")
def _leaf_spectra_own(are, aim, M, ref, qrel, weight, first, count, frame, u0, du, nu, r0, dr, nr, cyc_per_m, j0, NU,
                      spec, spec1, lims, bq, chunks):
    """:func:`_leaf_spectra` on the leaves' own axes (:mod:`salkit.focus.ffbp_axes`, ``frame`` a row a
    leaf), with the first-order correction: each pulse's eps at the line's first and last point
    (eps = delta_p - delta_p at the middle), their rank-one model eps_p(r) ~ a_p b(r)
    (:func:`~salkit.focus.ffbp_axes._own_weights`), and beside each line's spectrum in ``spec`` the
    sum weighted by a_p and j 2 pi (2 f / c) into ``spec1``, whose transform times b along the line
    is the correction (:func:`_leaf_store_own`); ``bq[j]`` = (middle index, b's slope and curvature
    a point)."""
    L, nfft, h, step, n_hi, n_chunks = _spectra_sizes(spec, M, dr, are, chunks)
    width = 1
    for s in range(count.shape[0]):
        width = max(width, count[s])
    for ch in prange(n_chunks):
        g_re = np.empty(n_hi * RAMP_BLOCK, np.float32)
        g_im = np.empty(n_hi * RAMP_BLOCK, np.float32)
        g1_re = np.empty(n_hi * RAMP_BLOCK, np.float32)
        g1_im = np.empty(n_hi * RAMP_BLOCK, np.float32)
        t_hi_re, t_hi_im, t_lo_re, t_lo_im = _ramp_scratch(n_hi)
        d_mid = np.empty(width)
        e_lo = np.empty(width)
        e_hi = np.empty(width)
        for jj in range(ch * L // n_chunks, (ch + 1) * L // n_chunks):
            s, iu, u, n = _line_job(jj, j0, NU, u0, du, nr, lims)
            bq[jj, 0] = 0.0
            bq[jj, 1] = 0.0
            bq[jj, 2] = 0.0
            row = spec[jj]
            row1 = spec1[jj]
            fr = frame[s]
            lo, sa, sb, h2 = _own_line_start(fr, r0[s], dr, n, u)
            if iu >= nu[s] or lo >= n:  # no line: its rows are transformed all the same
                row[:] = np.float32(0.0)
                row1[:] = np.float32(0.0)
                continue
            rm = r0[s] + 0.5 * (lo + n - 1) * dr  # the line's middle point, and its ends
            e0, e1, e2 = _own_point(fr, sa, sb, h2, rm)
            a0, a1, a2 = _own_point(fr, sa, sb, h2, r0[s] + lo * dr)
            b0, b1, b2 = _own_point(fr, sa, sb, h2, r0[s] + (n - 1) * dr)
            rc = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            rca = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
            rcb = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
            saa = 0.0
            sab = 0.0
            sbb = 0.0
            for i in range(count[s]):
                p = first[s] + i
                dlt = _pulse_delta(qrel, p, e0, e1, e2, rc)
                ea = _pulse_delta(qrel, p, a0, a1, a2, rca) - dlt
                eb = _pulse_delta(qrel, p, b0, b1, b2, rcb) - dlt
                d_mid[i] = dlt
                e_lo[i] = ea
                e_hi[i] = eb
                saa += ea * ea
                sab += ea * eb
                sbb += eb * eb
            va, vb = _own_weights(saa, sab, sbb)
            for m in range(g_re.shape[0]):
                g_re[m] = np.float32(0.0)
                g_im[m] = np.float32(0.0)
                g1_re[m] = np.float32(0.0)
                g1_im[m] = np.float32(0.0)
            off_lo = np.inf
            off_hi = -np.inf
            for i in range(count[s]):
                p = first[s] + i
                off = _pulse_ramp(p, d_mid[i], r0[s], ref, qrel, weight, dr, nfft, h, step, cyc_per_m, n_hi, t_hi_re,
                                  t_hi_im, t_lo_re, t_lo_im)
                off_lo = min(off_lo, off)
                off_hi = max(off_hi, off)
                _ramp_sum2(are, aim, p, va * e_lo[i] + vb * e_hi[i], n_hi, t_hi_re, t_hi_im, t_lo_re, t_lo_im, g_re,
                           g_im, g1_re, g1_im)
            _spectrum_row(row, g_re, g_im, M, h, nfft)
            for m in range(M):  # times j 2 pi (2 f_m / c): the phase's rate in eps
                wm = np.float32(2.0 * math.pi * ((m - h) * step + cyc_per_m))
                xr = g1_re[m]
                g1_re[m] = -wm * g1_im[m]
                g1_im[m] = wm * xr
            _spectrum_row(row1, g1_re, g1_im, M, h, nfft)
            _line_limits(lims, jj, lo, n, off_lo, off_hi, nfft)
            half = 0.5 * (n - 1 - lo)
            if half > 0.0:
                bq[jj, 0] = 0.5 * (lo + n - 1)
                bq[jj, 1] = (vb - va) / (2.0 * half)
                bq[jj, 2] = (va + vb) / (2.0 * half * half)


@njit(parallel=True, nogil=True, cache=True, error_model="numpy")
def _leaf_store_own(lines, lines1, lims, bq, out):
    """:func:`_leaf_store` of the own-axis leaves: each point the transformed line plus b times the
    transformed correction (b = slope x + curvature x^2, x the index from the middle, ``bq``)."""
    L = lines.shape[0]
    n = out.shape[1]
    for jj in prange(L):
        src = lines[jj]
        src1 = lines1[jj]
        row = out[jj]
        a, b = _kept_span(row, lims, jj, n)
        mid = bq[jj, 0]
        b1 = bq[jj, 1]
        b2 = bq[jj, 2]
        for k in range(a, b):
            x = k - mid
            row[k] = src[k] + np.float32(b1 * x + b2 * x * x) * src1[k]


@njit(cache=True, inline="always", error_model="numpy")
def _kept_span(row, lims, jj, n):
    """The span a to b - 1 of a leaf's row that its ``lims[jj]`` keep (clipped to the row's ``n``
    points; none where last < first), the row zeroed outside it."""
    a = min(max(lims[jj, 0], 0), n)
    b = min(lims[jj, 1], n - 1)
    if b < a:
        a = b = n
    else:
        b += 1
    for k in range(a):
        row[k] = 0j
    for k in range(b, n):
        row[k] = 0j
    return a, b


@njit(parallel=True, nogil=True, cache=True, error_model="numpy")
def _leaf_store(lines, lims, out):
    """The FFT leaves' last step: the first ``out.shape[1]`` points of each transformed line of
    ``lines`` (complex64 (L, nfft)) into its row of ``out`` (complex64 (L, NR), NR <= nfft), zero
    outside its ``lims`` (first and last index kept; none where last < first)."""
    L = lines.shape[0]
    n = out.shape[1]
    for jj in prange(L):
        src = lines[jj]
        row = out[jj]
        a, b = _kept_span(row, lims, jj, n)
        for k in range(a, b):
            row[k] = src[k]
