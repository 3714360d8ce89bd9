"""Eight pixels at a time: the second pass of the backprojection kernel (:mod:`salkit.focus.bp_kernel`)
written as LLVM vector code, for numba functions.

The second pass reads each pixel's range-profile bins at an index computed by the first pass: a
gather, which LLVM leaves scalar on AMD Zen (its gather instructions are microcoded and slower than
scalar loads) and cannot vectorise anyway while it cannot prove the profile and the image apart.
These intrinsics load each of eight pixels' bins as one short vector (the bins a pixel needs are
adjacent in memory), transpose the eight vectors in registers into one vector a quantity
(eight pixels' real parts, imaginary parts, ...), and do the interpolation, the rotation by the
pixel's phase and the accumulation eight pixels wide. The IR is target-independent: LLVM lowers it
to AVX-512, AVX2 or SSE shuffles as the machine has.

Every pointer argument is a numba array (1-D, C-contiguous); ``j`` is the first of the eight pixels,
and the caller keeps ``j + 8 <= len(idx)`` and every offset plus the bins read inside the profile.
:data:`taps4x16` takes sixteen (``j + 16 <= len(idx)``): two eight-pixel transposes side by side in
512-bit rows, the arithmetic on sixteen lanes (AVX-512 code; the kernel reads :func:`wide_vectors`).
"""
from __future__ import annotations

import llvmlite.binding as llvm
import llvmlite.ir as ir
from numba import types
from numba.core.registry import cpu_target
from numba.extending import intrinsic

from ..signals.vectors import array_data as _data
from ..signals.vectors import load_vector as _load
from ..signals.vectors import splat
from ..signals.vectors import store_vector as _store

_F32 = ir.FloatType()
_I32 = ir.IntType(32)
_I64 = ir.IntType(64)
_V8F = ir.VectorType(_F32, 8)
_V4F = ir.VectorType(_F32, 4)
_V8I = ir.VectorType(_I32, 8)

#: Pixels an intrinsic handles.
WIDTH = 8


def wide_vectors() -> bool:
    """Whether numba's code on this machine is AVX-512 (32 vector registers of 16 floats) rather
    than AVX2 (16 of 8): the target's features as numba's code generator holds them, the host's
    or ``NUMBA_CPU_FEATURES``. Kernels whose best loop structure differs between the two read it
    once, at import, as a constant (numba's cache is keyed by the target too).

    Returns
    -------
    bool
    """
    features = getattr(cpu_target.target_context.codegen(), "_tm_features", None)  # what numba compiles for
    if features is None:  # pragma: no cover - a numba without that attribute: the host's features
        return bool(llvm.get_host_cpu_features().get("avx512f", False))
    return "+avx512f" in features.split(",")


def _gather_rows(builder, base, offsets, vty):
    """One short vector load a pixel: ``vty`` at ``base + offsets[lane]`` for the eight lanes of the
    <8 x i32> ``offsets`` (each pixel's bins are adjacent, so a gather is eight plain loads)."""
    rows = []
    for lane in range(8):
        off = builder.zext(builder.extract_element(offsets, ir.Constant(_I32, lane)), _I64)
        rows.append(_load(builder, base, off, vty))
    return rows


def _mask(*ix):
    return ir.Constant(ir.VectorType(_I32, len(ix)), list(ix))


def _halves_mask(mask8, halves):
    """A two-input shuffle mask of eight lanes applied to each of ``halves`` eight-lane halves of
    two ``<8 halves x float>`` vectors (lane l of half h from half h of either input)."""
    if halves == 1:
        return _mask(*mask8)
    n = 8 * halves
    return _mask(*[x + 8 * h if x < 8 else x - 8 + n + 8 * h for h in range(halves) for x in mask8])


def transpose8(builder, rows, halves=1):
    """The transpose of eight ``<8 x float>`` values (three stages of two-input shuffles), or of
    each eight-lane half of eight ``<8 halves x float>`` values.

    Parameters
    ----------
    builder : llvmlite.ir.IRBuilder
    rows : list of 8 llvmlite values, <8 halves x float>
    halves : int
        Eight-lane halves a value (1: <8 x float>; 2: <16 x float>).

    Returns
    -------
    list of 8 llvmlite values, <8 halves x float>
        ``out[k][8 h + l] = rows[l][8 h + k]``.
    """
    def shuffle(a, b, *mask8):
        return builder.shuffle_vector(a, b, _halves_mask(mask8, halves))

    t = []
    for q in range(4):
        a, b = rows[2 * q], rows[2 * q + 1]
        t.append(shuffle(a, b, 0, 8, 2, 10, 4, 12, 6, 14))
        t.append(shuffle(a, b, 1, 9, 3, 11, 5, 13, 7, 15))
    u = [None] * 8
    for q in range(2):
        for h in range(2):
            a, b = t[4 * q + h], t[4 * q + 2 + h]
            u[4 * q + h] = shuffle(a, b, 0, 1, 8, 9, 4, 5, 12, 13)
            u[4 * q + 2 + h] = shuffle(a, b, 2, 3, 10, 11, 6, 7, 14, 15)
    out = [None] * 8
    for k in range(4):
        out[k] = shuffle(u[k], u[4 + k], 0, 1, 2, 3, 8, 9, 10, 11)
        out[k + 4] = shuffle(u[k], u[4 + k], 4, 5, 6, 7, 12, 13, 14, 15)
    return out


def _rotate_accumulate(builder, vr, vi, sp, cp, rp, mp, j, vty=_V8F):
    """out_re[j:j+n] += vr c - vi s; out_im[j:j+n] += vr s + vi c (n the lanes of ``vty``)."""
    s = _load(builder, sp, j, vty)
    c = _load(builder, cp, j, vty)
    o_r = _load(builder, rp, j, vty)
    o_i = _load(builder, mp, j, vty)
    o_r = builder.fadd(o_r, builder.fsub(builder.fmul(vr, c), builder.fmul(vi, s)))
    o_i = builder.fadd(o_i, builder.fadd(builder.fmul(vr, s), builder.fmul(vi, c)))
    _store(builder, o_r, rp, j)
    _store(builder, o_i, mp, j)


@intrinsic
def linear8(typingctx, pc, idx, frs, ss, cs, out_re, out_im, j):
    """Pass 2 of linear interpolation for the eight pixels ``j`` to ``j + 7``.

    Called from numba code (the arguments are numba values; ``typingctx`` is numba's).

    Parameters
    ----------
    pc : float32[::1]
        Profile as interleaved (re, im) floats (a complex64 profile viewed as float32).
    idx : uint32[::1]
        Offset in ``pc`` of each pixel's bin (2 x bin); the next bin is read too.
    frs, ss, cs : float32[::1]
        Fraction between bins, weighted sine and cosine of the pixel's phase.
    out_re, out_im : float32[::1]
        Accumulators.
    j : int64

    Returns
    -------
    none
        ``out[j + l] += (z_b + f (z_b+1 - z_b)) (c + 1j s)``, l = 0..7.
    """
    sig = types.void(pc, idx, frs, ss, cs, out_re, out_im, j)

    def codegen(context, builder, signature, args):
        pcp, ip, fp, sp, cp, rp, mp = (_data(context, builder, signature.args[k], args[k]) for k in range(7))
        jj = args[7]
        recs = _gather_rows(builder, pcp, _load(builder, ip, jj, _V8I), _V4F)  # re0 im0 re1 im1
        # two pixels a vector, then (re0 x4, im0 x4) and (re1 x4, im1 x4) of four pixels
        pairs = [builder.shuffle_vector(recs[2 * q], recs[2 * q + 1], _mask(*range(8))) for q in range(4)]
        lo = [builder.shuffle_vector(pairs[2 * h], pairs[2 * h + 1], _mask(0, 4, 8, 12, 1, 5, 9, 13)) for h in range(2)]
        hi = [builder.shuffle_vector(pairs[2 * h], pairs[2 * h + 1], _mask(2, 6, 10, 14, 3, 7, 11, 15)) for h in range(2)]
        first, second = _mask(0, 1, 2, 3, 8, 9, 10, 11), _mask(4, 5, 6, 7, 12, 13, 14, 15)
        re0 = builder.shuffle_vector(lo[0], lo[1], first)
        im0 = builder.shuffle_vector(lo[0], lo[1], second)
        re1 = builder.shuffle_vector(hi[0], hi[1], first)
        im1 = builder.shuffle_vector(hi[0], hi[1], second)
        f = _load(builder, fp, jj, _V8F)
        vr = builder.fadd(re0, builder.fmul(f, builder.fsub(re1, re0)))
        vi = builder.fadd(im0, builder.fmul(f, builder.fsub(im1, im0)))
        _rotate_accumulate(builder, vr, vi, sp, cp, rp, mp, jj)
        return context.get_dummy_value()

    return sig, codegen


def _horner(builder, cfp, first, count, x):
    """sum_i cf[first + i] x^i over ``count`` coefficients (Horner), ``x`` a float vector."""
    c = [splat(builder, builder.load(builder.gep(cfp, [ir.Constant(_I64, first + i)])), x.type) for i in range(count)]
    w = c[count - 1]
    for i in range(count - 2, -1, -1):
        w = builder.fadd(c[i], builder.fmul(x, w))
    return w


def _gather_halves(builder, base, offsets, lanes):
    """Eight ``<lanes x float>`` rows for :func:`transpose8`: row q holds the eight floats at
    ``base + offsets[q]``, and for sixteen lanes those at ``base + offsets[q + 8]`` after them
    (pixels q and q + 8 in the two halves)."""
    if lanes == 8:
        return _gather_rows(builder, base, offsets, _V8F)
    rows = []
    for q in range(8):
        pair = [_load(builder, base, builder.zext(builder.extract_element(offsets, ir.Constant(_I32, q + 8 * h)), _I64),
                      _V8F) for h in range(2)]
        rows.append(builder.shuffle_vector(pair[0], pair[1], _mask(*range(16))))
    return rows


def _taps_symmetric(taps: int, n_coef: int, shift: float, lanes: int = WIDTH):
    """An intrinsic for pass 2 of a ``taps``-tap interpolation (a multiple of 4) whose kernel is
    symmetric (tap ``taps - 1 - b`` at u weighs as tap b at -u, u = s - ``shift``) and whose weights
    are polynomials of ``n_coef`` coefficients in u: ``taps_sym(pc, idx, s, ss, cs, out_re, out_im,
    j, cf)`` for the ``lanes`` (8 or 16) pixels from ``j``. Each pair of taps (b, taps - 1 - b) is
    weighed E_b(u) +- O_b(u), its even and odd parts
    (:func:`salkit.focus.profiles.symmetric_coefficients`: ``cf[n_coef b:n_coef (b + 1)]`` the even
    part's coefficients of u^0, u^2, ... then the odd part's of u^1, u^3, ...), both polynomials in
    u^2: half the multiply-adds and coefficient loads of the taps' own polynomials. Sixteen pixels
    are transposed as two eights side by side (pixels q and q + 8 in one row's halves) and the
    arithmetic done on sixteen lanes at once: on AVX-512 one register a quantity, half the
    instructions of two eight-pixel calls."""
    blocks = taps // 4
    n_even = (n_coef + 1) // 2
    n_odd = n_coef // 2
    vf = ir.VectorType(_F32, lanes)
    vi = ir.VectorType(_I32, lanes)

    @intrinsic
    def taps_sym(typingctx, pc, idx, ss_frac, ss, cs, out_re, out_im, j, cf):
        sig = types.void(pc, idx, ss_frac, ss, cs, out_re, out_im, j, cf)

        def codegen(context, builder, signature, args):
            pcp, ip, fp, sp, cp, rp, mp, cfp = (_data(context, builder, signature.args[k], args[k])
                                                for k in (0, 1, 2, 3, 4, 5, 6, 8))
            jj = args[7]
            offsets = _load(builder, ip, jj, vi)
            cols = []
            for h in range(blocks):  # eight floats (four bins) of each pixel a transpose
                base = builder.gep(pcp, [ir.Constant(_I64, 8 * h)])
                cols += transpose8(builder, _gather_halves(builder, base, offsets, lanes), lanes // 8)
            u = _load(builder, fp, jj, vf)
            if shift:
                u = builder.fsub(u, splat(builder, ir.Constant(_F32, shift), vf))
            u2 = builder.fmul(u, u)
            weights = [None] * taps
            for b in range(taps // 2):
                even = _horner(builder, cfp, n_coef * b, n_even, u2)
                odd = builder.fmul(u, _horner(builder, cfp, n_coef * b + n_even, n_odd, u2))
                weights[b] = builder.fadd(even, odd)
                weights[taps - 1 - b] = builder.fsub(even, odd)
            vr = vim = None
            for b in range(taps):
                r = builder.fmul(weights[b], cols[2 * b])
                m = builder.fmul(weights[b], cols[2 * b + 1])
                vr = r if vr is None else builder.fadd(vr, r)
                vim = m if vim is None else builder.fadd(vim, m)
            _rotate_accumulate(builder, vr, vim, sp, cp, rp, mp, jj, vf)
            return context.get_dummy_value()

        return sig, codegen

    return taps_sym


#: Pass 2 of a symmetric four-tap interpolation (weights cubic in the fraction) for the eight pixels
#: ``j`` to ``j + 7``: the backprojection kernel's Keys cubic and fitted taps
#: (:mod:`salkit.focus.bp_kernel`). The weights come from their even and odd parts about the
#: middle of the bins (u = t - 1/2): 7 multiply-adds and 8 coefficient loads for eight pixels where
#: the taps' own cubics take 12 and 16 (on AVX2 code, a seventh of the pass's time).
#:
#: Arguments ``(pc, idx, frs, ss, cs, out_re, out_im, j, cf)``: ``pc`` float32[::1] the profile as
#: interleaved (re, im) floats, one bin of padding before and two after; ``idx`` uint32[::1] each
#: pixel's first tap (2 x (bin - 1) + 2 = 2 x bin); ``frs, ss, cs`` float32[::1] the fraction t
#: between bins and the weighted sine and cosine of the pixel's phase; ``out_re, out_im``
#: float32[::1] accumulators; ``cf`` float32[::1] 8 coefficients
#: (:func:`salkit.focus.profiles.symmetric_coefficients` of the taps' cubics in t, centre 1/2): taps
#: 0 and 3 (bins -1 and 2) weigh (cf[0] + cf[1] u^2) +- u (cf[2] + cf[3] u^2), taps 1 and 2 (bins
#: 0 and 1) the same with cf[4:8].
taps4x8 = _taps_symmetric(4, 4, 0.5)

#: :data:`taps4x8` for the sixteen pixels ``j`` to ``j + 15`` (the same arguments): on AVX-512 code
#: (:func:`wide_vectors`) the second pass takes sixteen pixels a call, about 10 % of the
#: backprojection kernel's time (2-core Zen 4: 0.62-0.66 s against 0.69-0.74 s for 917 pulses onto
#: 1024^2); on AVX2 code its sixteen lanes are two registers and it gains nothing.
taps4x16 = _taps_symmetric(4, 4, 0.5, 16)


#: Pass 2 of eight symmetric taps with degree-6 polynomial weights in s = 2 t - 1 (FFBP's range
#: interpolation onto image rows: :func:`salkit.focus.ffbp_merges._row_range_pass`), eight pixels at
#: a time, the weights from the four pairs' even and odd parts (33 multiply-adds and 28 coefficient
#: loads for eight pixels where the taps' own polynomials take 48 and 56).
#:
#: Arguments ``(pc, idx, s, ss, cs, out_re, out_im, j, cf)``: ``pc`` float32[::1] the source as
#: interleaved (re, im) floats; ``idx`` uint32[::1] each pixel's first float (its first tap);
#: ``s`` float32[::1] the weights' argument; ``ss, cs`` the weighted sine and cosine of each
#: pixel's phase; ``out_re, out_im`` float32[::1] accumulators; ``j`` the first of eight pixels;
#: ``cf`` float32[::1] 4 x 7 coefficients (:func:`salkit.focus.profiles.symmetric_coefficients` of
#: the taps' polynomials, centre 0).
taps8_sym7 = _taps_symmetric(8, 7, 0.0)
