"""The eight-pixel intrinsics of the backprojection kernel's second pass and of FFBP's range pass onto
image rows: on random profiles, offsets and phases, each gives what the same interpolation, rotation and accumulation give written out in
numpy (float64), to float32 rounding, lanes and all (a wrong shuffle would swap pixels)."""
import numpy as np
from numba import njit

from salkit.focus.profiles import KEYS_COEFFICIENTS, fitted_coefficients, symmetric_coefficients
from salkit.focus.simd import WIDTH, linear8, taps4x8, taps4x16, taps8_sym7


@njit
def _linear(pk, idx, frs, ss, cs, ore, oim):
    for j in range(0, idx.size, WIDTH):
        linear8(pk, idx, frs, ss, cs, ore, oim, j)


@njit
def _taps(pc, idx, frs, ss, cs, ore, oim, cf):
    for j in range(0, idx.size, WIDTH):
        taps4x8(pc, idx, frs, ss, cs, ore, oim, j, cf)


@njit
def _taps16(pc, idx, frs, ss, cs, ore, oim, cf):
    for j in range(0, idx.size, 2 * WIDTH):
        taps4x16(pc, idx, frs, ss, cs, ore, oim, j, cf)


@njit
def _taps8(pc, idx, sv, ss, cs, ore, oim, cf):
    for j in range(0, idx.size, WIDTH):
        taps8_sym7(pc, idx, sv, ss, cs, ore, oim, j, cf)


def _inputs(rng, n, nb):
    bins = rng.integers(0, nb - 2, n)
    frs = rng.random(n).astype(np.float32)
    ph = rng.uniform(-np.pi, np.pi, n)
    ss, cs = np.sin(ph).astype(np.float32), np.cos(ph).astype(np.float32)
    ore = rng.standard_normal(n).astype(np.float32)
    oim = rng.standard_normal(n).astype(np.float32)
    return bins, frs, ss, cs, ore, oim


def test_linear8_is_linear_interpolation_rotated_and_added():
    rng = np.random.default_rng(5)
    n, nb = 64, 300
    prof = (rng.standard_normal(nb) + 1j * rng.standard_normal(nb)).astype(np.complex64)
    bins, frs, ss, cs, ore, oim = _inputs(rng, n, nb)
    v = prof[bins] + frs * (prof[bins + 1] - prof[bins])
    want = (ore + 1j * oim) + v.astype(np.complex128) * (cs + 1j * ss)
    _linear(prof.view(np.float32), (2 * bins).astype(np.uint32), frs, ss, cs, ore, oim)
    np.testing.assert_allclose(ore + 1j * oim, want, rtol=0, atol=2e-5 * np.abs(want).max())


def test_taps4x8_is_the_four_tap_kernel_rotated_and_added():
    """Keys' cubic and a fitted kernel given as their even and odd parts about t = 1/2: the weights
    the taps' own cubics in t give (a wrong sign or pairing would swap taps 0 and 3)."""
    rng = np.random.default_rng(6)
    n, nb = 64, 300
    prof = (rng.standard_normal(nb) + 1j * rng.standard_normal(nb)).astype(np.complex64)
    padded = np.concatenate([[0], prof, [0, 0]]).astype(np.complex64)
    for coefficients in (KEYS_COEFFICIENTS, fitted_coefficients(50, 400)):
        bins, frs, ss, cs, ore, oim = _inputs(rng, n, nb)
        w = np.vander(frs.astype(np.float64), 4, increasing=True) @ np.asarray(coefficients).T  # (n, 4)
        v = sum(w[:, q] * padded[bins + q] for q in range(4))  # padded bin b + q is bin b + q - 1
        want = (ore + 1j * oim) + v * (cs + 1j * ss)
        cf = symmetric_coefficients(coefficients, 0.5).astype(np.float32)
        _taps(padded.view(np.float32), (2 * bins).astype(np.uint32), frs, ss, cs, ore, oim, cf)
        np.testing.assert_allclose(ore + 1j * oim, want, rtol=0, atol=2e-5 * np.abs(want).max())


def test_taps4x16_is_two_taps4x8_calls_bit_for_bit():
    """Sixteen pixels a call (pixels q and q + 8 transposed side by side): every lane the value the
    eight-pixel intrinsic gives, bit for bit (the same operations a lane), so AVX-512 and AVX2 code
    make the same image; and the four-tap kernel itself to float32 rounding."""
    rng = np.random.default_rng(16)
    n, nb = 96, 300
    prof = (rng.standard_normal(nb) + 1j * rng.standard_normal(nb)).astype(np.complex64)
    padded = np.concatenate([[0], prof, [0, 0]]).astype(np.complex64)
    coefficients = fitted_coefficients(50, 400)
    cf = symmetric_coefficients(coefficients, 0.5).astype(np.float32)
    bins, frs, ss, cs, ore, oim = _inputs(rng, n, nb)
    idx = (2 * bins).astype(np.uint32)
    eight = (ore.copy(), oim.copy())
    sixteen = (ore.copy(), oim.copy())
    _taps(padded.view(np.float32), idx, frs, ss, cs, *eight, cf)
    _taps16(padded.view(np.float32), idx, frs, ss, cs, *sixteen, cf)
    np.testing.assert_array_equal(sixteen[0], eight[0])
    np.testing.assert_array_equal(sixteen[1], eight[1])
    w = np.vander(frs.astype(np.float64), 4, increasing=True) @ np.asarray(coefficients).T
    want = (ore + 1j * oim) + sum(w[:, q] * padded[bins + q] for q in range(4)) * (cs + 1j * ss)
    np.testing.assert_allclose(sixteen[0] + 1j * sixteen[1], want, rtol=0, atol=2e-5 * np.abs(want).max())


def test_transpose8_of_halves_transposes_each_half():
    """transpose8 on <16 x float> rows: each eight-lane half transposed on its own, no lane crossing
    between halves (the sixteen-pixel pass reads pixels 0-7 from the low halves, 8-15 from the high)."""
    import llvmlite.ir as ir
    from numba import types
    from numba.extending import intrinsic

    from salkit.focus.simd import transpose8
    from salkit.signals.vectors import array_data, load_vector, store_vector

    v16 = ir.VectorType(ir.FloatType(), 16)

    @intrinsic
    def _t(typingctx, a, out):
        def codegen(context, builder, signature, args):
            ap = array_data(context, builder, signature.args[0], args[0])
            op = array_data(context, builder, signature.args[1], args[1])
            rows = [load_vector(builder, ap, ir.Constant(ir.IntType(64), 16 * q), v16) for q in range(8)]
            for k, col in enumerate(transpose8(builder, rows, 2)):
                store_vector(builder, col, op, ir.Constant(ir.IntType(64), 16 * k))
            return context.get_dummy_value()
        return types.void(a, out), codegen

    @njit
    def run(a, out):
        _t(a, out)

    a = np.arange(128, dtype=np.float32)
    out = np.zeros(128, np.float32)
    run(a, out)
    rows = a.reshape(8, 2, 8)  # row q, half h, lane l
    np.testing.assert_array_equal(out.reshape(8, 2, 8), rows.transpose(2, 1, 0))


def test_taps8_sym7_is_eight_symmetric_taps_of_polynomial_weights_rotated_and_added():
    """Eight complex taps from each pixel's first bin, tap b weighted by sum_d c[b, d] s^d for a random
    symmetric kernel (tap 7 - b at s as tap b at -s; every pair and power distinct), given as its
    even and odd parts: the sum rotated and added."""
    rng = np.random.default_rng(7)
    n, nb = 64, 300
    src = (rng.standard_normal(nb) + 1j * rng.standard_normal(nb)).astype(np.complex64)
    half = rng.standard_normal((4, 7))
    cf = np.vstack([half, half[::-1] * (-1.0) ** np.arange(7)])  # symmetric about s = 0
    bins, frs, ss, cs, ore, oim = _inputs(rng, n, nb - 8)
    sv = (2 * frs - 1).astype(np.float32)
    w = np.vander(sv.astype(np.float64), 7, increasing=True) @ cf.T  # (n, 8)
    v = sum(w[:, b] * src[bins + b] for b in range(8))
    want = (ore + 1j * oim) + v * (cs + 1j * ss)
    _taps8(src.view(np.float32), (2 * bins).astype(np.uint32), sv, ss, cs, ore, oim,
           symmetric_coefficients(cf, 0.0).astype(np.float32))
    np.testing.assert_allclose(ore + 1j * oim, want, rtol=0, atol=2e-5 * np.abs(want).max())


def test_wide_vectors_follows_numbas_target():
    """The target's features as numba compiles for them: AVX-512 off in NUMBA_CPU_FEATURES (what
    benchmarks/avx2.py sets) reads as AVX2 code whatever the host."""
    import os
    import subprocess
    import sys
    code = "from salkit.focus.simd import wide_vectors; print(wide_vectors())"
    env = dict(os.environ, NUMBA_CPU_NAME="znver3", NUMBA_CPU_FEATURES="+avx,+avx2,+fma,+sse4.2,-avx512f")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
    from salkit.focus.simd import wide_vectors
    assert isinstance(wide_vectors(), bool)
