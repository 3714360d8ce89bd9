"""The eight-pixel intrinsics of the backprojection kernel's second pass: on random profiles, offsets
and phases, each gives what the same interpolation, rotation and accumulation give written out in
numpy (float64), to float32 rounding, lanes and all (a wrong shuffle would swap pixels)."""
import numpy as np
from numba import njit

from salkit.focus.profiles import KEYS_COEFFICIENTS, fitted_coefficients
from salkit.focus.simd import WIDTH, linear8, taps4x8


@njit
def _linear(pk, idx, frs, ss, cs, ore, oim):
    for j in range(0, idx.size, WIDTH):
        linear8(pk, idx, frs, ss, cs, ore, oim, j)


@njit
def _taps(pc, idx, frs, ss, cs, ore, oim, cf):
    for j in range(0, idx.size, WIDTH):
        taps4x8(pc, idx, frs, ss, cs, ore, oim, j, cf)


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
    rng = np.random.default_rng(6)
    n, nb = 64, 300
    prof = (rng.standard_normal(nb) + 1j * rng.standard_normal(nb)).astype(np.complex64)
    padded = np.concatenate([[0], prof, [0, 0]]).astype(np.complex64)
    for coefficients in (KEYS_COEFFICIENTS, fitted_coefficients(50, 400)):
        bins, frs, ss, cs, ore, oim = _inputs(rng, n, nb)
        w = np.vander(frs.astype(np.float64), 4, increasing=True) @ np.asarray(coefficients).T  # (n, 4)
        v = sum(w[:, q] * padded[bins + q] for q in range(4))  # padded bin b + q is bin b + q - 1
        want = (ore + 1j * oim) + v * (cs + 1j * ss)
        cf = np.ascontiguousarray(coefficients, np.float32).ravel()
        _taps(padded.view(np.float32), (2 * bins).astype(np.uint32), frs, ss, cs, ore, oim, cf)
        np.testing.assert_allclose(ore + 1j * oim, want, rtol=0, atol=2e-5 * np.abs(want).max())
