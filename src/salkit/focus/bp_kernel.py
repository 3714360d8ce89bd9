"""The backprojection kernel (numba, parallel), for any trajectory: the ``bp`` former
(:mod:`salkit.focus.bp`) and its variants call it.

For each pulse the phase history P(f) is turned into an upsampled range profile; each pixel at
differential range dR = |x - p| - R_ref adds profile(dR) * exp(+j 4 pi f_c dR / c), the profile
read between its bins by the interpolation named (:data:`INTERPOLATIONS`: linear, nearest, Keys
cubic, four taps fitted to the band), whose mean response is divided out of the spectrum first.
The reading of the profiles is eight pixels at a time in vector registers (:mod:`salkit.focus.simd`),
sixteen for the four-tap kernels on AVX-512 code (:data:`SIXTEEN`).

Precision: |x - p| is computed in float64 from the plane geometry (|x - p|^2 = A + g (B + g) for
pixels x = o + g r along a range line), differenced against the float64 reference range, and
only the phase reduced to [-pi, pi) (in cycles, float64) is handed to a float32 sin/cos
polynomial. The result is exact at 200 km and 560 km range at 1.55 um, where float32 ranges
(~1.5 cm precision at 200 km) would destroy the image.

Fast path: on a uniform line, the float64 work is done once a segment of :data:`SEGMENT` pixels
(:data:`SHORT_SEGMENT` on lines shorter than :data:`LONG_LINE_SEGMENTS` segments and where the
longer step's rounding would exceed the budget), at its centre (range, profile offset, phase in
cycles, and the phase's Taylor coefficients along the line); each pixel's offset and phase is a
float32 cubic step from there, a vector of lanes at a time, with the step's whole cycles a pixel
taken out in float64 so that its float32 sum stays a few cycles. Its truncation and rounding are
bounded line by line (:func:`segment_fits`); a line whose bound exceeds :data:`SEGMENT_TOLERANCE`
(1.9e-5 rad) takes the exact path. On the wide-angle X-band benchmark the image is unchanged to
0.1 dB of error against the exact former and the kernel about 1.3x faster.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft
from numba import njit, prange

from ..geometry.ranges import range_offsets
from ..signals.phase import sincos_cycles, sincos_cycles_scaled
from ..constants import FFT_WORKERS, SPEED_OF_LIGHT
from ..tolerances import BP_UPSAMPLE
from .profiles import (FOUR_TAP_PADDING, interpolation_of, pack_profiles, pad_profiles, profile_length,
                       profile_sampling, range_profiles, range_profiles_into, symmetric_coefficients)
from .simd import WIDTH, linear8, taps4x8, taps4x16, wide_vectors

WORKERS = FFT_WORKERS

#: The four-tap second pass sixteen pixels a call (:data:`salkit.focus.simd.taps4x16`) where numba's
#: code is AVX-512, eight (:data:`salkit.focus.simd.taps4x8`) where it is AVX2: read once, at import
#: (numba's cache is keyed by the target).
SIXTEEN = wide_vectors()



@njit(cache=True, inline="always", fastmath=True, error_model="numpy", boundscheck=False)
def _pixel(j, x, dR, w, cyc_per_m, idx, frs, ss, cs):
    """Pass 1's outputs for pixel j: the profile offset and fraction of position ``x`` (bins), and
    the weighted sin/cos of its phase, the cycles dR * cyc_per_m reduced to [-0.5, 0.5] in float64
    (so that it vectorises) before the float32 polynomial."""
    i0 = np.int32(x)
    idx[j] = np.uint32(i0) << np.uint32(1)  # (re, im) floats: 2 a bin
    frs[j] = np.float32(x - i0)
    cyc = dR * cyc_per_m
    ss[j], cs[j] = sincos_cycles_scaled(np.float32(cyc - np.rint(cyc)), w)


@njit(cache=True, inline="always", fastmath=True, error_model="numpy", boundscheck=False)
def _differential_range(g, A, B, C, refp, h):
    """|x - p| and |x - p| - R_ref in float64 at ``g`` along the line |x - p|^2 = A + g (B + g),
    the difference corrected by the exact R^2 - R_ref^2 = C + g (B + g) times ``h`` (0.5 / R_ref
    where a range's rounding reaches the phase, else 0: the correction then multiplied away)."""
    q = g * (B + g)
    R = math.sqrt(A + q)
    dR = R - refp
    return R, dR + (C + q - dR * (R + refp)) * h


#: Pixels a segment of the first pass's fast path on lines of at least :data:`LONG_LINE_SEGMENTS`
#: segments: each pixel's range is its segment's float64 anchor plus a float32 Taylor step. 32
#: since 0.30.0 (16 before): half the float64 anchors, whose square root and division take four
#: lanes a vector on AVX2 code (the kernel 3-5 % faster there on 1024-pixel lines; the same on
#: AVX-512 code), for a Taylor step twice as long (its error bounds, :func:`segment_fits`).
SEGMENT = 32

#: Pixels a segment on shorter lines, and on lines that the long segment does not fit
#: (:func:`segment_fits`: at short range with fine pixels, e.g. 1.55 um at 5 km with 2.5 cm ground
#: pixels, its float32 rounding exceeds the budget): the fast path as it was before 0.30.0; the
#: exact path where this does not fit either.
SHORT_SEGMENT = 16

#: The segment's pixels' offsets from its centre, pixels.
LANES = np.arange(SEGMENT, dtype=np.float32) - np.float32((SEGMENT - 1) / 2)

#: Segments of :data:`SEGMENT` pixels a line must hold for them to be used (else
#: :data:`SHORT_SEGMENT`), and the anchors computed at least (a line of fewer segments gets them
#: for centres past its end too, unused): the float64 anchors' loop takes its vector path only from
#: 20 iterations on with AVX2 code and 24 with AVX-512 code (LLVM's run-time check), and fewer
#: would be computed one at a time (lines of 256 pixels: the kernel 10-15 % slower).
LONG_LINE_SEGMENTS = 24

#: :data:`LANES` for :data:`SHORT_SEGMENT`.
SHORT_LANES = np.arange(SHORT_SEGMENT, dtype=np.float32) - np.float32((SHORT_SEGMENT - 1) / 2)

#: The fast path's phase error budget, cycles (1.9e-5 rad: an error floor near -94 dB, beside the
#: float32 sin/cos polynomial's 4.3e-6): the bound on the Taylor step's truncation and float32 rounding
#: (:func:`segment_fits`) must stay under it, or the line takes the exact float64 path.
SEGMENT_TOLERANCE = 3.0e-6



def step_rounding(segment: int) -> float:
    """The float32 rounding of a ``segment``-pixel Taylor step's phase beyond its quadratic part,
    cycles: the anchor's phase and the linear part, each reduced to half a cycle (the latter a
    pixel), reach 0.5 + (segment - 1) / 4 cycles, and their sum and the coefficients' roundings stay
    under 2^-22 of that (32 pixels: 8.25 cycles, 2.0e-6; 7.5e-7 from the operations and 4.6e-7 from
    the linear coefficient's float32 rounding at worst).

    Parameters
    ----------
    segment : int
        Pixels a segment.

    Returns
    -------
    float
        Cycles.

    Examples
    --------
    >>> round(step_rounding(16) * 1e6, 3)
    1.013
    """
    return 2.0 ** -22 * (0.5 + 0.25 * (segment - 1))


#: :func:`step_rounding` of :data:`SEGMENT` (2.0e-6 cycles).
STEP_ROUNDING = step_rounding(SEGMENT)

#: :func:`step_rounding` of :data:`SHORT_SEGMENT` (1.0e-6 cycles).
SHORT_STEP_ROUNDING = step_rounding(SHORT_SEGMENT)


@njit(cache=True, fastmath=True, error_model="numpy", boundscheck=False)
def _anchors(r0, inv_dr, A, B, C, refp, gcs, dg, cyc_per_m, corr, anc, anci):
    """The fast path's anchors: each segment's centre g (``gcs``, one a segment) in float64 as the
    exact path computes a pixel (range, the long-range correction when ``corr``, profile offset,
    phase in cycles), and there the phase's Taylor coefficients in cycles a pixel, E1, E2, E3 (from R', R''/2, R'''/6).

    ``anci[k]`` gets the whole bins of the offset; ``anc[:, k]`` its fraction, the phase reduced
    to [-0.5, 0.5] cycles with n/2 added (n = rint(E1): the step's integer part n t, t a
    half-integer, is n/2 cycles), E1, E1 - n, E2 and E3.
    """
    h = 0.5 / refp if corr else 0.0  # the correction multiplied by 0 where it is not needed
    hb = 0.5 * B
    hc2 = 0.5 * max(A - hb * hb, 0.0)  # half the perpendicular distance squared: 1 - R'^2 = c^2 / R^2
    for k in range(gcs.shape[0]):
        g = gcs[k]  # read, not computed from k: an int64 to float64 conversion has no packed instruction on AVX2
        R, dR = _differential_range(g, A, B, C, refp, h)
        x = (dR - r0) * inv_dr
        xi = np.floor(x)  # a float (math.floor's int64 would leave the loop scalar on AVX2)
        iR = 1.0 / R
        r1 = (g + hb) * iR
        r2 = hc2 * iR * iR * iR
        e1 = r1 * dg * cyc_per_m
        n1 = np.rint(e1)
        cyc = dR * cyc_per_m + 0.5 * n1
        anci[k] = np.int32(xi)
        anc[0, k] = np.float32(x - xi)
        anc[1, k] = np.float32(cyc - np.rint(cyc))
        anc[2, k] = np.float32(e1)
        anc[3, k] = np.float32(e1 - n1)
        anc[4, k] = np.float32(r2 * dg * dg * cyc_per_m)
        anc[5, k] = np.float32(-r1 * r2 * iR * dg * dg * dg * cyc_per_m)


@njit(cache=True, inline="always", fastmath=True, error_model="numpy", boundscheck=False)
def _segment_steps(anc, anci, k, lanes, fq, idx, frs, ss):
    """Segment k's pixels (``lanes``: their offsets from its centre, a module constant, so that the
    loop has a constant count), :func:`_steps`' first loop."""
    xf = anc[0, k]
    ca = anc[1, k]
    e1 = anc[2, k]
    e1r = anc[3, k]
    e2 = anc[4, k]
    e3 = anc[5, k]
    xb = anci[k]
    n = lanes.shape[0]
    for m in range(n):
        j = k * n + m
        t = lanes[m]
        hi = t * (e2 + t * e3)
        xl = xf + t * (e1 + hi) * fq
        fl = np.floor(xl)
        idx[j] = np.uint32(xb + np.int32(fl)) << np.uint32(1)
        frs[j] = xl - fl
        cy = ca + t * (e1r + hi)
        ss[j] = cy - np.rint(cy)  # the phase in cycles, for the sin and cos


@njit(cache=True, fastmath=True, error_model="numpy", boundscheck=False)
def _steps(anc, anci, nseg, fq, w, idx, frs, ss, cs, short):
    """Pass 1 of the fast path's ``nseg`` segments of :data:`SEGMENT` pixels (``short``:
    :data:`SHORT_SEGMENT`), a vector of lanes at a time: each pixel t pixels from its segment's
    centre (:data:`LANES`, :data:`SHORT_LANES`) steps t (E1 + t (E2 + t E3)) cycles from the anchor
    (:func:`_anchors`), its profile offset that times ``fq`` bins a cycle, its phase the same
    step with E1 - n, so that the float32 sum stays a few cycles and its rounding ~1e-7 cycles."""
    if short:
        for k in range(nseg):
            _segment_steps(anc, anci, k, SHORT_LANES, fq, idx, frs, ss)
        n = nseg * SHORT_SEGMENT
    else:
        for k in range(nseg):
            _segment_steps(anc, anci, k, LANES, fq, idx, frs, ss)
        n = nseg * SEGMENT
    # the sin and cos in a loop of their own: with the steps' constants too, sixteen AVX2 registers
    # spill (10 % of the kernel's time there)
    for j in range(n):
        ss[j], cs[j] = sincos_cycles_scaled(ss[j], w)


@njit(cache=True, inline="always", fastmath=True, error_model="numpy", boundscheck=False)
def _pass2(pk, idx, frs, ss, cs, out_re, out_im, mode, cf, j_lo, j_hi):
    """Pass 2 for pixels ``j_lo`` .. ``j_hi - 1``: read the profile ``pk`` at each pixel's offset,
    interpolate (``mode``: :data:`INTERPOLATIONS`' codes; 0 linear between bins b and b + 1 of
    the interleaved profile, 1 nearest, 2 and 3 four taps on the padded interleaved profile with
    the weights' coefficients ``cf``: :func:`kernel_profiles`), rotate and accumulate; eight pixels at a time
    (:mod:`salkit.focus.simd`; four taps sixteen at a time on AVX-512 code, :data:`SIXTEEN`), the last
    few scalar."""
    n8 = j_lo + (j_hi - j_lo) // WIDTH * WIDTH
    if mode == 0:  # linear: bins b and b + 1
        for j in range(j_lo, n8, WIDTH):
            linear8(pk, idx, frs, ss, cs, out_re, out_im, j)
        for j in range(n8, j_hi):
            k = idx[j]
            f = frs[j]
            vr = pk[k] + f * (pk[k + np.uint32(2)] - pk[k])
            vi = pk[k + np.uint32(1)] + f * (pk[k + np.uint32(3)] - pk[k + np.uint32(1)])
            s = ss[j]
            c = cs[j]
            out_re[j] += vr * c - vi * s
            out_im[j] += vr * s + vi * c
    elif mode == 1:  # nearest bin
        for j in range(j_lo, j_hi):
            k = idx[j] + np.uint32(2) * np.uint32(frs[j] >= 0.5)
            vr = pk[k]
            vi = pk[k + np.uint32(1)]
            s = ss[j]
            c = cs[j]
            out_re[j] += vr * c - vi * s
            out_im[j] += vr * s + vi * c
    else:  # four taps, bins -1 .. 2 (Keys cubic, or fitted to the band)
        sym = cf[16:]  # the kernel's even and odd parts (taps4x8)
        j8 = j_lo
        if SIXTEEN:
            j8 = j_lo + (j_hi - j_lo) // (2 * WIDTH) * (2 * WIDTH)
            for j in range(j_lo, j8, 2 * WIDTH):
                taps4x16(pk, idx, frs, ss, cs, out_re, out_im, j, sym)
        for j in range(j8, n8, WIDTH):
            taps4x8(pk, idx, frs, ss, cs, out_re, out_im, j, sym)
        for j in range(n8, j_hi):
            k = idx[j]
            t = frs[j]
            vr = np.float32(0.0)
            vi = np.float32(0.0)
            for q in range(4):
                wq = cf[4 * q] + t * (cf[4 * q + 1] + t * (cf[4 * q + 2] + t * cf[4 * q + 3]))
                vr += wq * pk[k + np.uint32(2 * q)]
                vi += wq * pk[k + np.uint32(2 * q + 1)]
            s = ss[j]
            c = cs[j]
            out_re[j] += vr * c - vi * s
            out_im[j] += vr * s + vi * c


@njit(cache=True, fastmath=True, error_model="numpy", boundscheck=False)
def _bp_row(pk, r0, inv_dr, hi, A, B, C, refp, rg, cyc_per_m, w, out_re, out_im, idx, frs, ss, cs, mode, cf, inside,
            fast, short, gcs, dg, anc, anci):
    """One pulse into one range line, in two passes so that both vectorise.

    Pass 1 (SIMD): the pixel's profile offset and fraction, and the sin and cos of its phase
    (:func:`_pixel`). Exact path: float64 range |x - p| from the line's quadratic, difference
    against the float64 reference, at long range corrected by the exact R^2 - R_ref^2 = C +
    g (B + g) (a range's rounding, 6e-11 m at 560 km, would otherwise reach the phase), phase
    reduced to [-0.5, 0.5) cycles in float64 and handed to the float32 sin/cos polynomial. Fast
    path (``fast``: the line inside the profile, uniform, its Taylor steps within
    :data:`SEGMENT_TOLERANCE`): segments of :data:`SEGMENT` pixels (``short``:
    :data:`SHORT_SEGMENT`), centres ``gcs``, each anchored at its centre by the exact computation
    (:func:`_anchors`), its pixels a float32 Taylor step from it (:func:`_steps`). Pass 2:
    :func:`_pass2`.
    """
    ny = rg.shape[0]
    h = 0.5 / refp
    # corrected where a range's rounding (half an ulp) reaches 1e-4 rad of phase, an error floor of
    # -83 dB (beyond ~55 km at 1.55 um; never at X band)
    corr = refp * cyc_per_m * 2.2e-16 * 6.3 > 1e-4
    j0 = 0
    if fast:
        _anchors(r0, inv_dr, A, B, C, refp, gcs, dg, cyc_per_m, corr, anc, anci)
        segment = SHORT_SEGMENT if short else SEGMENT
        nseg = ny // segment  # ``gcs`` may hold more (:func:`_centres`)
        _steps(anc, anci, nseg, np.float32(inv_dr / cyc_per_m), w, idx, frs, ss, cs, short)
        j0 = nseg * segment
    if corr:
        for j in range(j0, ny):
            _, dR = _differential_range(rg[j], A, B, C, refp, h)
            x = (dR - r0) * inv_dr
            valid = np.float32((x >= 0.0) & (x <= hi))
            _pixel(j, min(max(x, 0.0), hi), dR, valid * w, cyc_per_m, idx, frs, ss, cs)
    elif inside:  # the whole line inside the profile: no clamp, no mask
        r0i = r0 * inv_dr
        for j in range(j0, ny):
            g = rg[j]
            dR = math.sqrt(A + g * (B + g)) - refp
            _pixel(j, dR * inv_dr - r0i, dR, w, cyc_per_m, idx, frs, ss, cs)
    else:
        for j in range(j0, ny):
            g = rg[j]
            dR = math.sqrt(A + g * (B + g)) - refp
            x = (dR - r0) * inv_dr
            valid = np.float32((x >= 0.0) & (x <= hi))
            _pixel(j, min(max(x, 0.0), hi), dR, valid * w, cyc_per_m, idx, frs, ss, cs)
    _pass2(pk, idx, frs, ss, cs, out_re, out_im, mode, cf, 0, ny)


@njit(cache=True)
def segment_plan(rg, cyc_per_m, segment=SEGMENT):
    """Whether a line's pixels can take the first pass's fast path, and its error bounds' factors.

    The line must be uniform (g_j = g_0 + j dg to 1e-7 cycles of phase) and at least one
    ``segment`` long. Every pixel is then within u_max = (segment - 1) dg / 2 of its segment's
    centre; :func:`segment_fits` bounds the phase's Taylor step from there with these factors.

    Parameters
    ----------
    rg : float64 (ny,)
        Range coordinates of the pixels, m.
    cyc_per_m : float
        Cycles of phase a metre of differential range.
    segment : int
        Pixels a segment (:data:`SEGMENT` or :data:`SHORT_SEGMENT`).

    Returns
    -------
    segmented : bool
    dg : float
        Pixel spacing, m.
    trunc : float
        cyc_per_m u_max^4 / 24, cycles m^4.
    quad : float
        2^-23 cyc_per_m u_max^2, cycles m^2.

    Examples
    --------
    >>> segment_plan(np.arange(64) * 0.2, 64.0)[:2]
    (True, 0.2)
    >>> segment_plan(np.arange(64) ** 1.01 * 0.2, 64.0)[0]
    False
    """
    ny = rg.shape[0]
    dg = (rg[-1] - rg[0]) / max(ny - 1, 1)
    uniform = ny >= segment and dg != 0.0
    for j in range(ny):
        uniform &= abs(rg[j] - (rg[0] + j * dg)) * cyc_per_m < 1e-7
    u_max = 0.5 * (segment - 1) * abs(dg)
    return uniform, dg, cyc_per_m * u_max ** 4 / 24.0, 2.0 ** -23 * cyc_per_m * u_max * u_max


@njit(cache=True, inline="always")
def segment_fits(A, B, R_min, trunc, quad, rounding=STEP_ROUNDING):
    """Whether the line |x - p|^2 = A + g (B + g) keeps the fast path's phase error within
    :data:`SEGMENT_TOLERANCE`.

    Along the line |x - p| = sqrt(c^2 + s^2) (c^2 = A - B^2 / 4 the perpendicular distance
    squared, s from its foot), whose fourth derivative is at most min(3 / c^3, 15 c^2 / R^5) at
    distance R from the antenna, and R'' = c^2 / R^3. On the pixels' part of the line (R >=
    ``R_min``) the Taylor step then errs by at most ``trunc`` min(3 / c^3, 15 c^2 / R_min^5)
    cycles (its remainder), and its float32 sum by 2^-22 times its size: ``quad`` c^2 / R_min^3
    for the quadratic part and ``rounding`` for the rest (the anchor's phase and the linear part,
    reduced to half a cycle a pixel: :data:`STEP_ROUNDING` for :data:`SEGMENT`,
    :data:`SHORT_STEP_ROUNDING` for :data:`SHORT_SEGMENT`).

    Parameters
    ----------
    A, B : float
        The line's quadratic, m^2 and m.
    R_min : float
        Least distance from the antenna to the pixels' part of the line, m.
    trunc, quad : float
        From :func:`segment_plan`.
    rounding : float
        The rest's float32 rounding, cycles.

    Returns
    -------
    bool
    """
    if R_min <= 0.0:
        return False
    c2 = max(A - 0.25 * B * B, 0.0)
    r3 = R_min * R_min * R_min
    k4 = 15.0 * c2 / (r3 * R_min * R_min)
    if c2 > 0.0:
        k4 = min(k4, 3.0 / (c2 * math.sqrt(c2)))
    return trunc * k4 + quad * c2 / r3 + rounding < SEGMENT_TOLERANCE


@njit(cache=True)
def _centres(g0, dg, nseg, segment):
    """The centres of ``nseg`` segments of ``segment`` pixels from ``g0``, spacing ``dg``, m, and of
    more past the line's end up to :data:`LONG_LINE_SEGMENTS` (the anchors' loop vectorised)."""
    gcs = np.empty(max(nseg, LONG_LINE_SEGMENTS))
    for k in range(gcs.shape[0]):
        gcs[k] = g0 + (k * segment + 0.5 * (segment - 1)) * dg
    return gcs


#: Image rows a thread takes together: each pulse's profile is read for all of them in turn, so it
#: stays in the core's cache (16x profiles of a block of pulses do not fit in L2; one pulse's does).
ROW_TILE = 8


@njit(parallel=True, nogil=True, cache=True, fastmath=True)
def bp_kernel(profiles, n_bins, r0, inv_dr, pos, ref, D, row_origin, rdir, rg, cyc_per_m, weight, img_re, img_im,
              mode, cf, segments=True):
    """Accumulate a block of pulses into the image, tiles of :data:`ROW_TILE` rows in parallel.

    Parameters
    ----------
    profiles : float32 (P, L)
        Range profiles as the interpolation reads them (:func:`kernel_profiles`): interleaved
        (re, im), with one bin of padding before and two after for the four-tap kernels; bin b
        (of the unpadded profile) is at differential range r0 + b/inv_dr.
    n_bins : int
        Bins a profile.
    pos : float64 (P, 3)
    ref : float64 (P,)
    D : float64 (P,)
        |p|^2 - ref^2, exact (:func:`salkit.geometry.ranges.range_offsets`).
    row_origin : float64 (nx, 3)
        3-D point of range coordinate 0 of each azimuth row, relative to the scene centre.
    rdir : float64 (3,)
        Unit range axis.
    rg : float64 (ny,)
        Range coordinates of the pixels along a row.
    cyc_per_m : float
        2 f_c / c, cycles of phase per metre of dR.
    weight : float32 (nx, P)
        Per-row, per-pulse weight (azimuth window, beam equalisation); 0 skips.
    img_re, img_im : float32 (nx, ny), accumulated in place.
    mode : int
        Interpolation of the profiles (:data:`INTERPOLATIONS`' codes).
    cf : float32 (24,)
        The four-tap kernels' coefficients (:func:`kernel_profiles`), unused by the others.
    segments : bool
        Let lines take the first pass's fast path where they fit it (:func:`segment_plan`,
        :func:`segment_fits`: segments of :data:`SEGMENT` pixels, else of :data:`SHORT_SEGMENT`);
        False computes every pixel by the exact float64 path.
    """
    nx = row_origin.shape[0]
    ny = rg.shape[0]
    P = pos.shape[0]
    hi = n_bins - 2.0
    g_lo = rg.min()
    g_hi = rg.max()
    n_tiles = (nx + ROW_TILE - 1) // ROW_TILE
    segmented, dg, trunc, quad = segment_plan(rg, cyc_per_m)
    segmented &= segments and ny // SEGMENT >= LONG_LINE_SEGMENTS
    short_ok, _, trunc_s, quad_s = segment_plan(rg, cyc_per_m, SHORT_SEGMENT)
    short_ok &= segments
    gcs = _centres(rg[0], dg, ny // SEGMENT, SEGMENT)  # the segments' centres
    gcs_s = _centres(rg[0], dg, ny // SHORT_SEGMENT, SHORT_SEGMENT)
    for t in prange(n_tiles):
        anc = np.empty((6, gcs_s.shape[0]), np.float32)
        anci = np.empty(gcs_s.shape[0], np.int32)
        idx = np.empty(ny, np.uint32)
        frs = np.empty(ny, np.float32)
        ss = np.empty(ny, np.float32)
        cs = np.empty(ny, np.float32)
        i_end = min(nx, (t + 1) * ROW_TILE)
        for p in range(P):
            for i in range(t * ROW_TILE, i_end):
                w = weight[i, p]
                if w == 0.0:
                    continue
                ox = row_origin[i, 0] - pos[p, 0]
                oy = row_origin[i, 1] - pos[p, 1]
                oz = row_origin[i, 2] - pos[p, 2]
                A = ox * ox + oy * oy + oz * oz
                B = 2.0 * (ox * rdir[0] + oy * rdir[1] + oz * rdir[2])
                o0 = row_origin[i, 0]
                o1 = row_origin[i, 1]
                o2 = row_origin[i, 2]
                C = D[p] + o0 * (o0 - 2.0 * pos[p, 0]) + o1 * (o1 - 2.0 * pos[p, 1]) + o2 * (o2 - 2.0 * pos[p, 2])
                # |x - p| along the line is convex in g: least at the foot of the perpendicular
                # (clipped to the line), greatest at an end; a bin of margin for the roundings
                gc = min(max(-0.5 * B, g_lo), g_hi)
                R_min = math.sqrt(A + gc * (B + gc))
                x_lo = (R_min - ref[p] - r0) * inv_dr
                x_hi = (math.sqrt(max(A + g_lo * (B + g_lo), A + g_hi * (B + g_hi))) - ref[p] - r0) * inv_dr
                inside = (x_lo >= 1.0) & (x_hi <= hi - 1.0)
                fast = segmented and inside and segment_fits(A, B, R_min, trunc, quad)
                short = (not fast) and short_ok and inside and segment_fits(A, B, R_min, trunc_s, quad_s,
                                                                            SHORT_STEP_ROUNDING)
                _bp_row(profiles[p], r0, inv_dr, hi, A, B, C, ref[p], rg, cyc_per_m, np.float32(w),
                        img_re[i], img_im[i], idx, frs, ss, cs, mode, cf, inside, fast or short, short,
                        gcs_s if short else gcs, dg, anc, anci)


def kernel_profiles(prof: np.ndarray, interpolation: str, n_samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Range profiles laid out for :func:`bp_kernel`, and the interpolation's coefficients.

    Parameters
    ----------
    prof : complex64 (P, Nb)
        Upsampled range profiles (:func:`salkit.focus.profiles.range_profiles`).
    interpolation : {"linear", "nearest", "cubic", "fitted"}
    n_samples : int
        Frequencies a pulse (the band a profile occupies: ``n_samples`` of its ``Nb`` bins'
        frequencies; the fitted kernel is fitted to it).

    Returns
    -------
    profiles : float32 (P, L)
        Interleaved (re, im): the profiles themselves viewed as float32 (linear and nearest read
        bins b and b + 1), or padded with one bin before and two after (four taps:
        :func:`salkit.focus.profiles.pad_profiles`).
    cf : float32 (24,)
        The four-tap kernel's coefficients (zeros for the others): 16 tap-major, tap k's weight
        sum_d cf[4 k + d] t^d (the pixels one at a time), then its 8 even and odd parts about t =
        1/2 (:func:`salkit.focus.profiles.symmetric_coefficients`; eight pixels at a time,
        :data:`salkit.focus.simd.taps4x8`).

    Examples
    --------
    >>> p, cf = kernel_profiles(np.ones((2, 5), np.complex64), "cubic", 2)
    >>> p.shape, cf[:4].tolist()
    ((2, 16), [0.0, -0.5, 1.0, -0.5])
    >>> kernel_profiles(np.ones((2, 5), np.complex64), "linear", 2)[0].shape
    (2, 10)
    """
    cf = kernel_coefficients(interpolation, n_samples, prof.shape[1])
    if interpolation_of(interpolation).coefficients is None:
        return np.ascontiguousarray(prof, np.complex64).view(np.float32), cf
    return pad_profiles(prof), cf


def kernel_coefficients(interpolation: str, n_samples: int, n_bins: int) -> np.ndarray:
    """The interpolation's coefficients as :func:`bp_kernel` reads them (:func:`kernel_profiles`).

    Parameters
    ----------
    interpolation : {"linear", "nearest", "cubic", "fitted"}
    n_samples : int
        Frequencies a pulse.
    n_bins : int
        Bins a profile (the FFT length).

    Returns
    -------
    float32 (24,)
        16 tap-major polynomial coefficients, then the 8 of their even and odd parts about t = 1/2;
        zeros for linear and nearest.

    Examples
    --------
    >>> kernel_coefficients("cubic", 2, 5)[:4].tolist()
    [0.0, -0.5, 1.0, -0.5]
    """
    spec = interpolation_of(interpolation)
    if spec.coefficients is None:
        return np.zeros(24, np.float32)
    c = spec.coefficients(int(n_samples), int(n_bins))
    return np.concatenate([np.ravel(c), symmetric_coefficients(c, 0.5)]).astype(np.float32)


#: Bytes of one kernel call's range profiles, counted at 16 a bin (the buffer the blocks share is
#: 8; :func:`salkit.focus.bp.bp_memory`): long pulses (many samples, high upsampling) go through in
#: fewer pulses a call.
PROFILE_BYTES = 128 * 2 ** 20

#: Pulses a kernel call of :func:`backproject` at most (:func:`profile_block`): 128 since 0.30.4 (32
#: before) where the call's profiles fit :data:`PROFILE_CACHE_BYTES`. Each call sets up its tiles'
#: lines and its threads once: at 256^2 (469 pulses) the former took 0.029 s against 0.032 s with 32,
#: at 1024^2 about 1 % less; the image is the same bits (every pixel sums its pulses in order,
#: whatever the calls).
PULSE_BLOCK = 128

#: Pulses a call keeps at least where the profiles are long (the block before 0.30.4).
BASE_BLOCK = 32

#: Bytes of one call's profiles (complex64) above which a call takes fewer pulses, down to
#: :data:`BASE_BLOCK`: every tile of rows reads all of them in turn, and past the cache they come
#: from memory at every tile (at 2048^2, 9 MB of profiles a call of 128 pulses took 6.12 s against
#: 5.71 s for 32; 64 pulses, 4.5 MB, 5.50 s against 5.54 s).
PROFILE_CACHE_BYTES = 4.5 * 2 ** 20


def profile_block(n_samples: int, upsample: int, block: int = PULSE_BLOCK) -> int:
    """Pulses a kernel call of :func:`backproject`: ``block``, halved (a power of two dividing it)
    while the call's profiles exceed :data:`PROFILE_CACHE_BYTES` (down to :data:`BASE_BLOCK`), then
    until they fit :data:`PROFILE_BYTES`.

    Parameters
    ----------
    n_samples : int
        Frequencies a pulse.
    upsample : int
    block : int

    Returns
    -------
    int

    Examples
    --------
    >>> profile_block(737, 6), profile_block(1475, 6), profile_block(2950, 6)
    (128, 64, 32)
    >>> profile_block(2000, 16), profile_block(655360, 16)
    (32, 1)
    """
    length = profile_length(n_samples, upsample)
    while block > BASE_BLOCK and block * 8.0 * length > PROFILE_CACHE_BYTES:
        block //= 2
    per_pulse = 2 * 8.0 * length
    while block > 1 and block * per_pulse > PROFILE_BYTES:
        block //= 2
    return block


def backproject(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray,
                row_origin: np.ndarray, rdir: np.ndarray, rg: np.ndarray, weight: np.ndarray,
                range_window: np.ndarray, upsample: int = BP_UPSAMPLE, block: int = PULSE_BLOCK,
                progress=None, linear_compensation: bool = True, out=None,
                interpolation: str = "linear", segments: bool = True) -> np.ndarray:
    """Backproject a phase history onto a plane grid.

    The pulses go through :func:`bp_kernel` in blocks, each block's range profiles transformed in
    place into one buffer kept for the call, in the layout the kernel reads
    (:func:`salkit.focus.profiles.range_profiles_into`).

    Parameters
    ----------
    ph : complex (P, M)
        Phase history, P(f) = exp(-j 4 pi f (R - R_ref)/c) per unit scatterer.
    freq : float64 (M,)
        Uniform frequency samples, Hz.
    positions : float64 (P, 3)
        Antenna positions, m.
    ref_range : float64 (P,)
        Reference ranges, m.
    row_origin : float64 (nx, 3)
        Point of range coordinate 0 on each azimuth row, m.
    rdir : float64 (3,)
        Unit range axis.
    rg : float64 (ny,)
        Range coordinates, m.
    weight : float32 (nx, P)
        Per-row, per-pulse weights.
    range_window : float (M,)
    upsample : int
        Range-profile upsampling (linear interpolation in between).
    block : int
        Pulses per kernel call, at most (:func:`profile_block` lowers it for long pulses).
    linear_compensation : bool
        Pre-compensate the interpolation's mean attenuation (:attr:`Interpolation.gain`).
    out : (float32 (nx, ny), float32 (nx, ny)), optional
        Accumulators (real, imaginary) to add into: pulse blocks backprojected one after another
        into the same accumulators give the whole collection's image, the same bits (each pixel sums
        its pulses in order).
    interpolation : {"linear", "nearest", "cubic", "fitted"}
        How the profiles are read between bins (:data:`salkit.focus.profiles.INTERPOLATIONS`).
    segments : bool
        Let uniform lines take the first pass's fast path where its error bounds allow
        (:func:`segment_plan`); False: every pixel by the exact float64 path (for tests and
        comparisons; the images agree to the float32 sin/cos polynomial's error).

    Returns
    -------
    complex64 (nx, ny) or None
        The image, not normalised; None when ``out`` is given (the accumulators hold it).
    """
    nx, ny = row_origin.shape[0], rg.size
    mode = interpolation_of(interpolation).code
    block = profile_block(ph.shape[1], upsample, block)
    if out is None:
        img_re = np.zeros((nx, ny), np.float32)
        img_im = np.zeros((nx, ny), np.float32)
    else:
        img_re, img_im = out
    P = ph.shape[0]
    rdir = np.ascontiguousarray(rdir, dtype=np.float64)
    rg = np.ascontiguousarray(rg, dtype=np.float64)
    row_origin = np.ascontiguousarray(row_origin, dtype=np.float64)
    D = range_offsets(positions, ref_range)
    # one buffer for every block's profiles, in the layout the kernel reads (the four-tap kernels:
    # one zero bin before, two after; :func:`kernel_profiles`), each block transformed in place
    four_taps = interpolation_of(interpolation).coefficients is not None
    lead, trail = FOUR_TAP_PADDING if four_taps else (0, 0)
    nfft, _ = profile_sampling(freq, upsample)
    work = np.zeros((min(block, P), lead + nfft + trail), np.complex64)
    cf = kernel_coefficients(interpolation, ph.shape[1], nfft)
    for a in range(0, P, block):
        b = min(P, a + block)
        r0, dr, f_c = range_profiles_into(work, ph[a:b], freq, upsample, range_window, linear_compensation,
                                          interpolation, lead)
        cyc = 2.0 * f_c / SPEED_OF_LIGHT
        bp_kernel(work[:b - a].view(np.float32), nfft, r0, 1.0 / dr,
                  np.ascontiguousarray(positions[a:b], dtype=np.float64),
                  np.ascontiguousarray(ref_range[a:b], dtype=np.float64), D[a:b], row_origin, rdir, rg, cyc,
                  np.ascontiguousarray(weight[:, a:b], dtype=np.float32), img_re, img_im, mode, cf, segments)
        if progress is not None:
            progress(b, P)
    if out is not None:
        return None
    img = np.empty((nx, ny), np.complex64)
    img.real = img_re
    img.imag = img_im
    return img


@njit(parallel=True, nogil=True, cache=True, fastmath=True)
def _contrib_kernel(packed, r0, inv_dr, pos, ref, pts, cyc_per_m, out):
    """out[p, k] = profile_p(dR) exp(+j 2 pi cyc_per_m dR), dR = |x_k - p_p| - R_ref,p (float64)."""
    P = pos.shape[0]
    K = pts.shape[0]
    hi = packed.shape[1] - 2.0
    for p in prange(P):
        pk = packed[p]
        for k in range(K):
            d0 = pts[k, 0] - pos[p, 0]
            d1 = pts[k, 1] - pos[p, 1]
            d2 = pts[k, 2] - pos[p, 2]
            dR = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) - ref[p]
            x = (dR - r0) * inv_dr
            if x < 0.0 or x > hi:
                out[p, k] = 0.0
                continue
            i0 = int(x)
            f = np.float32(x - i0)
            vr = pk[i0, 0] + f * pk[i0, 2]
            vi = pk[i0, 1] + f * pk[i0, 3]
            cyc = dR * cyc_per_m
            y = np.float32(cyc - np.rint(cyc))
            s, c = sincos_cycles(y)
            out[p, k] = complex(vr * c - vi * s, vr * s + vi * c)


def pulse_contributions(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray,
                        points: np.ndarray, range_window: np.ndarray | None = None,
                        upsample: int = BP_UPSAMPLE, block: int = 64) -> np.ndarray:
    """What each pulse backprojects onto each of a set of points, unsummed.

    Backprojection is the sum over pulses of these terms, so an image with per-pulse complex
    weights a_n is ``a @ contributions`` (backprojection autofocus, Ash 2012).

    Parameters
    ----------
    ph : complex (P, M)
        Phase history (as :func:`backproject`).
    freq : float64 (M,)
        Uniform frequency samples, Hz.
    positions : float64 (P, 3)
        Antenna positions, m.
    ref_range : float64 (P,)
        Reference ranges, m.
    points : float64 (K, 3)
        Points in the scene frame, m.
    range_window : float (M,), optional
        Range window (default none).
    upsample : int
        Range-profile upsampling.
    block : int
        Pulses per profile computation.

    Returns
    -------
    complex64 (P, K)
        Unnormalised contributions (the sum over pulses equals :func:`backproject` on those points).
    """
    P, M = ph.shape
    pts = np.ascontiguousarray(points, dtype=np.float64)
    out = np.empty((P, pts.shape[0]), np.complex64)
    wr = np.ones(M) if range_window is None else np.asarray(range_window)
    for a in range(0, P, block):
        b = min(P, a + block)
        prof, r0, dr, f_c = range_profiles(ph[a:b], freq, upsample, wr, True)
        _contrib_kernel(pack_profiles(prof), r0, 1.0 / dr, np.ascontiguousarray(positions[a:b], np.float64),
                        np.ascontiguousarray(ref_range[a:b], np.float64), pts, 2.0 * f_c / SPEED_OF_LIGHT,
                        out[a:b])
    return out
