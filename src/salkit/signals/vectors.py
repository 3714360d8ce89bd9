"""Vector code for numba kernels: LLVM IR helpers for intrinsics, and a sixteen-lane complex
accumulation.

LLVM leaves a loop scalar when it cannot prove the arrays it reads and writes apart (numba's
arrays carry no ``noalias``): an accumulator ``acc[n + j] += c w[j]`` whose table ``w`` might be
the accumulator itself. These intrinsics load, compute and store whole vectors, so the question
does not arise. The IR is target-independent: LLVM lowers a ``<16 x float>`` to one AVX-512 or two
AVX2 registers as the machine has. Without fast-math flags the arithmetic is IEEE float32, operation
for operation what the scalar loop computes (no fused multiply-add): the results are bit for bit the
same.

The backprojection kernel's second pass (:mod:`salkit.focus.simd`) and the simulator's chirp
accumulation (:mod:`salkit.simulate.kernels`) use them.
"""
from __future__ import annotations

import llvmlite.ir as ir
from numba import types
from numba.extending import intrinsic

F32 = ir.FloatType()
I32 = ir.IntType(32)
I64 = ir.IntType(64)

#: Lanes of :func:`caxpy16`.
LANES = 16

_V16F = ir.VectorType(F32, LANES)
_V16I = ir.VectorType(I32, LANES)


def array_data(context, builder, aty, aval):
    """The data pointer of a numba array value (in an intrinsic's code generator).

    Parameters
    ----------
    context, builder
        The intrinsic's code-generation context and IR builder.
    aty : numba.types.Array
    aval : llvmlite value
        The array (a numba array structure).

    Returns
    -------
    llvmlite value
        Pointer to its first element.
    """
    return context.make_array(aty)(context, builder, aval).data


def load_vector(builder, base, j, vty):
    """A vector of type ``vty`` loaded from ``base + j`` (elements), alignment 4.

    Parameters
    ----------
    builder : llvmlite.ir.IRBuilder
    base : llvmlite value
        Element pointer.
    j : llvmlite value
        Offset in elements (i64).
    vty : llvmlite.ir.VectorType

    Returns
    -------
    llvmlite value
    """
    p = builder.bitcast(builder.gep(base, [j]), vty.as_pointer())
    return builder.load(p, align=4)


def store_vector(builder, v, base, j):
    """Store the vector ``v`` at ``base + j`` (elements), alignment 4.

    Parameters
    ----------
    builder : llvmlite.ir.IRBuilder
    v : llvmlite value
        A vector.
    base : llvmlite value
        Element pointer.
    j : llvmlite value
        Offset in elements (i64).
    """
    p = builder.bitcast(builder.gep(base, [j]), v.type.as_pointer())
    builder.store(v, p, align=4)


def splat(builder, x, vty):
    """A vector of type ``vty`` whose every lane is the scalar ``x``.

    Parameters
    ----------
    builder : llvmlite.ir.IRBuilder
    x : llvmlite value
        Scalar of ``vty``'s element type.
    vty : llvmlite.ir.VectorType

    Returns
    -------
    llvmlite value
    """
    v = builder.insert_element(ir.Constant(vty, ir.Undefined), x, ir.Constant(I32, 0))
    return builder.shuffle_vector(v, v, ir.Constant(ir.VectorType(I32, vty.count), [0] * vty.count))


@intrinsic
def caxpy16(typingctx, acc_re, acc_im, w_re, w_im, n, c_re, c_im, m):
    """``acc[n + j] += c w[j]`` for the sixteen lanes j < 16 (complex, as real and imaginary float32
    planes), the lanes j >= ``m`` left as they are.

    Called from numba code (the arguments are numba values; ``typingctx`` is numba's). The sixteen
    accumulator elements from ``n`` are read and written whatever ``m``: the caller keeps
    ``n + 16 <= len(acc)`` (pads the accumulator by 16). A masked lane adds -0.0, which gives back
    the value it read bit for bit (a signed zero or an infinity too, whatever the table holds there).

    Parameters
    ----------
    acc_re, acc_im : float32[::1]
        Accumulators, real and imaginary parts.
    w_re, w_im : float32[::1]
        Table, at least 16 long (a masked lane's entry is read, not used).
    n : int64
        First accumulator element.
    c_re, c_im : float32
        The complex factor.
    m : int64
        Lanes taken, 0 to 16.

    Returns
    -------
    none
        ``acc_re[n + j] += c_re w_re[j] - c_im w_im[j]``, ``acc_im[n + j] += c_re w_im[j] +
        c_im w_re[j]`` (j < m), float32 operation by operation.
    """
    sig = types.void(acc_re, acc_im, w_re, w_im, n, c_re, c_im, m)

    def codegen(context, builder, signature, args):
        ar, ai, wr_p, wi_p = (array_data(context, builder, signature.args[k], args[k]) for k in range(4))
        nn = args[4]
        zero = ir.Constant(I64, 0)
        keep = builder.icmp_signed("<", ir.Constant(_V16I, list(range(LANES))),
                                   splat(builder, builder.trunc(args[7], I32), _V16I))
        wr = load_vector(builder, wr_p, zero, _V16F)
        wi = load_vector(builder, wi_p, zero, _V16F)
        cr = splat(builder, args[5], _V16F)
        ci = splat(builder, args[6], _V16F)
        xr = load_vector(builder, ar, nn, _V16F)
        xi = load_vector(builder, ai, nn, _V16F)
        # a masked lane adds -0.0, which leaves every value as it is (x + -0 = x, -0 and +0 included):
        # the stores stay whole vectors (a select of the sums would become a masked store, slow on AMD)
        none = ir.Constant(_V16F, [-0.0] * LANES)
        dr = builder.select(keep, builder.fsub(builder.fmul(cr, wr), builder.fmul(ci, wi)), none)
        di = builder.select(keep, builder.fadd(builder.fmul(cr, wi), builder.fmul(ci, wr)), none)
        store_vector(builder, builder.fadd(xr, dr), ar, nn)
        store_vector(builder, builder.fadd(xi, di), ai, nn)
        return context.get_dummy_value()

    return sig, codegen
