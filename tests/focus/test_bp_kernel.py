"""Backprojection: the image is the sum over pulses of the per-pulse contributions, and a point
focuses at the peak value its normalisation promises, at 200 km where float32 ranges fail; the
first pass's fast path gives every pixel its exact float64 offset and phase (X band to 560 km at
1.55 um), refuses lines it cannot bound, and its images are the exact path's."""
import numpy as np
import pytest

from salkit import simulate
from salkit.focus import phase_history
from salkit.focus.bp_kernel import (LONG_LINE_SEGMENTS, SEGMENT, SHORT_SEGMENT, SHORT_STEP_ROUNDING, _anchors, _steps,
                                    backproject, bp_kernel, kernel_coefficients, kernel_profiles, pulse_contributions,
                                    segment_fits, segment_plan, step_rounding, SEGMENT_TOLERANCE)
from salkit.constants import SPEED_OF_LIGHT
from salkit.focus.profiles import interpolation_of, range_profiles
from salkit.geometry.ranges import range_offsets
from salkit.geometry.collection import grid_axes, plane_from
from salkit.params import parse_scenario

from ..conftest import GEO, SPOT, merge


def _setup(base, nx=16, ny=12):
    sc = parse_scenario(merge(base, scene={"points": [{"x": 0.0, "y": 0.0}]}))
    ph = phase_history(simulate(sc))
    g = sc.processing.grid.model_copy(update={"nx": nx, "ny": ny})
    plane = plane_from(ph.track, ph.center_position, g.plane)
    az, rg = grid_axes(g)
    return ph, plane, az, rg


def test_image_is_the_sum_of_pulse_contributions():
    ph, plane, az, rg = _setup(SPOT)
    P, M = ph.data.shape
    W = np.ones((az.size, P), np.float32)
    img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, plane.points(az, np.zeros_like(az)),
                      plane.range, rg, W, np.ones(M))
    pts = np.stack([plane.points(np.full(rg.size, a), rg) for a in az]).reshape(-1, 3)
    c = pulse_contributions(ph.data, ph.freq, ph.positions, ph.reference_range, pts, np.ones(M))
    np.testing.assert_allclose(c.sum(axis=0).reshape(img.shape), img, rtol=1e-4, atol=1e-3 * np.abs(img).max())


@pytest.mark.parametrize("interpolation", ["fitted", "linear"])
def test_profiles_in_one_kept_buffer_give_the_same_image(interpolation):
    """backproject writes every block's profiles into one buffer in the kernel's layout; the image
    is bit for bit the one from each block's own profiles laid out by kernel_profiles."""
    ph, plane, az, rg = _setup(SPOT, nx=16, ny=40)
    P, M = ph.data.shape
    W = np.ones((az.size, P), np.float32)
    origin = plane.points(az, np.zeros_like(az))
    img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, origin, plane.range, rg, W, np.ones(M),
                      upsample=6, block=8, interpolation=interpolation)
    re = np.zeros(img.shape, np.float32)
    im = np.zeros(img.shape, np.float32)
    D = range_offsets(ph.positions, ph.reference_range)
    code = interpolation_of(interpolation).code
    for a in range(0, P, 8):
        b = min(P, a + 8)
        prof, r0, dr, f_c = range_profiles(ph.data[a:b], ph.freq, 6, np.ones(M), True, interpolation)
        kp, cf = kernel_profiles(prof, interpolation, M)
        assert np.array_equal(cf, kernel_coefficients(interpolation, M, prof.shape[1]))
        bp_kernel(kp, prof.shape[1], r0, 1.0 / dr, ph.positions[a:b].copy(), ph.reference_range[a:b].copy(), D[a:b],
                  origin, np.asarray(plane.range, np.float64), rg, 2.0 * f_c / SPEED_OF_LIGHT, W[:, a:b].copy(), re, im,
                  code, cf)
    assert np.array_equal(img.real, re) and np.array_equal(img.imag, im)


def test_point_at_200_km_peaks_at_pulses_times_samples():
    ph, plane, az, rg = _setup(GEO)
    P, M = ph.data.shape
    img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, plane.points(az, np.zeros_like(az)),
                      plane.range, rg, np.ones((az.size, P), np.float32), np.ones(M))
    i, j = np.unravel_index(np.argmax(np.abs(img)), img.shape)
    assert (az[i], rg[j]) == (0.0, 0.0)
    assert abs(img[i, j]) / (P * M) > 0.95  # unit point, coherent sum: the phase is right everywhere


def _line(cyc_per_m, height, ground, dg, ny=64, seed=0):
    """A range line of ``ny`` pixels ``dg`` apart, ``ground`` m out and the antenna ``height`` up,
    in the kernel's terms (A, B, C, reference range), and each pixel's exact float64 differential
    range (the exact path's formula, corrected at long range)."""
    rng = np.random.default_rng(seed)
    p = np.array([rng.uniform(-50, 50), -ground, height])
    o = np.array([rng.uniform(-5, 5), rng.uniform(-5, 5), 0.0])
    rdir = np.array([0.0, 1.0, 0.0])
    rg = (np.arange(ny) - ny / 2) * dg
    ref = np.linalg.norm(p) + rng.uniform(-3, 3)
    D = range_offsets(p[None], np.array([ref]))[0]
    A = float((o - p) @ (o - p))
    B = float(2 * (o - p) @ rdir)
    C = float(D + o @ (o - 2 * p))
    q = rg * (B + rg)
    R = np.sqrt(A + q)
    dR = R - ref
    dR += (C + q - dR * (R + ref)) * (0.5 / ref)
    return A, B, C, ref, rg, dR


@pytest.mark.parametrize("short", [False, True])
@pytest.mark.parametrize("wavelength, height, ground, dg", [
    (0.031, 7300.0, 3000.0, 0.2),     # X band, the wide-angle benchmark's geometry
    (1.55e-6, 5000.0, 2000.0, 0.01),  # airborne SAL
    (1.55e-6, 560e3, 100e3, 0.05),    # 560 km at 1.55 um: the long-range correction in the anchors
])
def test_fast_path_gives_each_pixel_its_exact_offset_and_phase(wavelength, height, ground, dg, short):
    cyc = 2.0 / wavelength
    A, B, C, ref, rg, dR = _line(cyc, height, ground, dg)
    r0, inv_dr = -50.0, 1.0 / 0.04
    segment = SHORT_SEGMENT if short else SEGMENT
    ok, step, trunc, quad = segment_plan(rg, cyc, segment)
    rounding = {"rounding": SHORT_STEP_ROUNDING} if short else {}
    assert ok and step == pytest.approx(dg)
    assert segment_fits(A, B, np.sqrt(A + rg * (B + rg)).min(), trunc, quad, **rounding)
    nseg = rg.size // segment
    anc, anci = np.empty((6, nseg), np.float32), np.empty(nseg, np.int32)
    idx, frs, ss, cs = (np.empty(rg.size, t) for t in (np.uint32, np.float32, np.float32, np.float32))
    corr = ref * cyc * 2.2e-16 * 6.3 > 1e-4
    gcs = rg[0] + (np.arange(nseg) * segment + 0.5 * (segment - 1)) * step
    _anchors(r0, inv_dr, A, B, C, ref, gcs, step, cyc, corr, anc, anci)
    _steps(anc, anci, nseg, np.float32(inv_dr / cyc), np.float32(1.0), idx, frs, ss, cs, short)
    x = (dR - r0) * inv_dr
    np.testing.assert_allclose(idx / 2 + frs, x, rtol=0, atol=1e-4)  # bins
    # the phase, against float64 reduced in cycles, within the float32 sin/cos polynomial's error
    want = np.exp(2j * np.pi * ((dR * cyc) % 1.0))
    err = np.abs(cs + 1j * ss - want)
    assert err.max() < 2e-5


def test_fast_path_refuses_what_it_cannot_bound():
    cyc = 2.0 / 1.55e-6
    rg = np.arange(64) * 0.01
    assert not segment_plan(rg * (1 + 1e-6 * np.arange(64)), cyc)[0]  # not uniform
    assert not segment_plan(rg[:SEGMENT - 1], cyc)[0]  # shorter than a segment
    ok, _, trunc, quad = segment_plan(np.arange(64) * 0.05, cyc)
    assert ok and segment_fits(1e6 ** 2, 0.0, 1e6, trunc, quad)  # 1000 km broadside: a tiny bound
    assert not segment_fits(20.0 ** 2, 0.0, 20.0, trunc, quad)  # 20 m: the Taylor step's truncation is not
    # a line pointing nearly at the antenna 5 km away (3.7 cm off it) is nearly straight: it fits
    assert segment_fits(5e3 ** 2 + 0.037 ** 2, -2 * 5e3, 5e3 - 2.0, trunc, quad)
    # 0.5 m pixels at 1.55 um, 1 km broadside: the step's quadratic part is too large for float32
    assert not segment_fits(1e3 ** 2, 0.0, 1e3, *segment_plan(np.arange(64) * 0.5, cyc)[2:])


def test_short_segments_take_lines_the_long_ones_cannot_bound():
    """1.55 um at 5 km with 2.5 cm pixels (the vehicle example's grid): the long segment's float32
    rounding exceeds the budget, the short one's does not."""
    cyc = 2.0 / 1.55e-6
    A, B, C, ref, rg, dR = _line(cyc, 3000.0, 4000.0, 0.025)
    R_min = np.sqrt(A + rg * (B + rg)).min()
    assert not segment_fits(A, B, R_min, *segment_plan(rg, cyc)[2:])
    assert segment_fits(A, B, R_min, *segment_plan(rg, cyc, SHORT_SEGMENT)[2:], SHORT_STEP_ROUNDING)


COARSE = merge(SPOT, waveform__bandwidth=3e9, processing__grid__dy=0.025, processing__grid__plane="ground")
# 2.5 cm ground pixels at 5 km (the vehicle example): the long segments' rounding exceeds the budget


def _segments_taken(ph, plane, az, rg):
    """The segment length the kernel takes for the first line and the middle pulse where the line lies
    inside the profile (0: the exact path)."""
    P, M = ph.data.shape
    o = plane.points(az, np.zeros_like(az))[0] - ph.positions[P // 2]
    A, B = o @ o, 2 * o @ np.asarray(plane.range)
    R_min = np.sqrt(A + rg * (B + rg)).min()
    cyc = 2 * ph.freq[M // 2] / SPEED_OF_LIGHT
    long_ok, _, trunc, quad = segment_plan(rg, cyc)
    if long_ok and rg.size // SEGMENT >= LONG_LINE_SEGMENTS and segment_fits(A, B, R_min, trunc, quad):
        return SEGMENT
    short_ok, _, trunc, quad = segment_plan(rg, cyc, SHORT_SEGMENT)
    return SHORT_SEGMENT if short_ok and segment_fits(A, B, R_min, trunc, quad, SHORT_STEP_ROUNDING) else 0


@pytest.mark.parametrize("base, ny, segment", [
    (SPOT, 48, SHORT_SEGMENT),     # a short line: sixteen-pixel segments
    (merge(SPOT, processing__grid__ny=800, receiver__adc_rate=80e6), 800, SEGMENT),  # a long line: thirty-two
    (GEO, 48, SHORT_SEGMENT),
    (merge(COARSE, processing__grid__ny=800, receiver__adc_rate=80e6), 800, SHORT_SEGMENT),  # 32 pixels round too much
])
def test_fast_path_image_is_the_exact_paths(base, ny, segment):
    ph, plane, az, rg = _setup(base, nx=4, ny=ny)
    P, M = ph.data.shape
    assert _segments_taken(ph, plane, az, rg) == segment
    args = (ph.data, ph.freq, ph.positions, ph.reference_range, plane.points(az, np.zeros_like(az)), plane.range, rg,
            np.ones((az.size, P), np.float32), np.ones(M))
    for interpolation in ("linear", "fitted"):
        fast = backproject(*args, interpolation=interpolation)
        exact = backproject(*args, interpolation=interpolation, segments=False)
        assert np.abs(fast - exact).max() < 3e-5 * np.abs(exact).max()
        assert not np.array_equal(fast, exact)  # the fast path was taken


def test_step_rounding_grows_with_the_segment():
    """The rounding bound is 2^-22 of the step's largest phase, 0.5 + (segment - 1) / 4 cycles."""
    assert step_rounding(16) == pytest.approx(2.0 ** -22 * 4.25)
    assert step_rounding(32) == pytest.approx(2.0 ** -22 * 8.25)
    assert step_rounding(32) < SEGMENT_TOLERANCE  # room left for the truncation and the quadratic part
