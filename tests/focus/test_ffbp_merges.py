"""FFBP's merge kernels: merging by two or by four gives the image direct backprojection gives,
the last step's angle cut along a row and its range pass along the row equal the float64
least-squares interpolation at the row's exact angles and ranges, and its point-by-point path
equals its separable row pass."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.focus import phase_history
from salkit.focus.ffbp import ffbp
from salkit.focus.ffbp_leaves import least_squares_weights, polynomial_weights
from salkit.focus.ffbp_merges import _angle_cut_row, _row_range_pass
from salkit.focus.formers import ImageGrid
from salkit.focus.profiles import symmetric_coefficients
from salkit.simulate.testbeds import wide_angle

from .test_ffbp import CASES, _error_db, _images


def test_merging_by_two_and_by_four_agree_with_the_direct_sum():
    tb = wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.point_targets(64, count=3)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(64))
    P, M = ph.data.shape
    direct = focus(tb.dataset(pts, amp), grid=tb.grid(64), algorithm="exact", window_name="none")["image"].values
    for factor in (2, 4):
        img, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M), factor=factor)
        img = img / (P * M)
        err = 10 * np.log10(np.sum(np.abs(img - direct) ** 2) / np.sum(np.abs(direct) ** 2))
        assert err < -50, (factor, err)


def test_final_step_point_by_point_agrees(monkeypatch):
    """Where image rows do not cross the sub-apertures' range bins in order, the last step
    interpolates point by point (48 taps): the same image as the separable row pass."""
    import salkit.focus.ffbp as ffbp_module
    sc, a, b = _images(CASES["5km"])
    monkeypatch.setattr(ffbp_module, "_rows_in_order", lambda *args: False)
    c = focus(simulate(sc), sc.processing, algorithm="ffbp")
    assert _error_db(a, c) < -40
    assert _error_db(b, c) < -40




@pytest.mark.parametrize("os_", [1.75, 3.0])
def test_row_angle_cut_equals_float64_interpolation_at_the_exact_angles(os_):
    """On a row along the range axis u = along / r exactly: the cut at each child range bin is
    the 8-tap least-squares interpolation across the child's angle rows at that u, here against
    a float64 evaluation, on rows crossing many angle samples (both signs of ``along``), with
    the bins whose taps leave the grid set to zero. The kernel enters as its mirrored pairs' even
    and odd parts (the default's and ``accuracy: high``'s oversampling)."""
    rng = np.random.default_rng(3)
    nu, nb = 300, 2000
    G = (rng.standard_normal((2, nu, nb)) + 1j * rng.standard_normal((2, nu, nb))).astype(np.complex64)
    Gf = G.view(np.float32)
    r0, dr, u0, du = 9000.0, 0.5, -0.052, 3.5e-4
    cps = symmetric_coefficients(polynomial_weights(8, os_), 0.0).astype(np.float32)
    fb = np.empty(nb)
    s2 = np.empty(2 * nb, np.float32)
    h2 = np.empty(2 * nb, np.float32)
    for along in (-445.0, 2.0, 467.0):
        j_lo, j_hi = 50, 1900
        _angle_cut_row(Gf, 1, nu, along, r0, dr, u0, 1.0 / du, j_lo, j_hi, cps, h2, fb, s2)
        got = h2[:2 * (j_hi + 1 - j_lo)].view(np.complex64)
        j = np.arange(j_lo, j_hi + 1)
        f = (along / (r0 + j * dr) - u0) / du
        iu = np.floor(f).astype(int)
        inside = (iu >= 3) & (iu + 5 <= nu)
        assert inside.any() and (~inside).any() if along == 467.0 else inside.all()
        want = np.zeros(j.size, np.complex128)
        w = least_squares_weights(8, os_, f[inside] - iu[inside])
        rows = iu[inside, None] + np.arange(-3, 5)[None, :]
        want[inside] = np.sum(w * G[1][rows, j[inside, None]], axis=1)
        assert np.all(got[~inside] == 0)
        err = np.abs(got - want).max() / np.abs(want[inside]).max()
        assert err < 1e-4, (along, err)


def test_row_range_pass_equals_float64_interpolation_at_each_pixel():
    """Pixels stepping 0.84 bins each along a row, with a little curvature (so every fraction
    differs): each pixel's value is the 8-tap least-squares interpolation of the cut at its bin
    position, rotated by its phase and added to what the accumulators held, against float64;
    pixels whose taps leave the cut's bins are left alone; line lengths that leave 1 to 7
    pixels after the groups of eight take the one-by-one path."""
    rng = np.random.default_rng(4)
    nb, os_ = 1200, 2.0
    cr = polynomial_weights(8, os_)
    crs = symmetric_coefficients(cr, 0.0).astype(np.float32)  # the eight-pixel path's form of them
    j_lo, j_hi = 40, 1150
    cut = (rng.standard_normal(j_hi + 1 - j_lo) + 1j * rng.standard_normal(j_hi + 1 - j_lo)).astype(np.complex64)
    h2 = np.zeros(2 * nb, np.float32)
    h2[:2 * cut.size] = cut.view(np.float32)
    for n in (1300, 1301, 1307):
        k = np.arange(n)
        fr = 20.0 + 0.84 * k + 1.5e-5 * k ** 2
        ph = rng.uniform(-np.pi, np.pi, n)
        sn, cs = np.sin(ph).astype(np.float32), np.cos(ph).astype(np.float32)
        are = rng.standard_normal(n).astype(np.float32)
        aim = rng.standard_normal(n).astype(np.float32)
        want = (are + 1j * aim).astype(np.complex128)
        ir = np.floor(fr).astype(int)
        inside = (ir - 3 >= j_lo) & (ir + 4 <= j_hi)
        assert inside.sum() > 1000 and (~inside).any()
        w = least_squares_weights(8, os_, (fr - ir)[inside])
        rows = ir[inside, None] - j_lo + np.arange(-3, 5)[None, :]
        want[inside] += np.sum(w * cut[rows], axis=1) * (cs[inside] + 1j * sn[inside])
        _row_range_pass(fr, n, h2, j_lo, j_hi, cr, crs, sn, cs, are, aim, np.empty(n, np.uint32),
                        np.empty(n, np.float32))
        err = np.abs(are + 1j * aim - want).max() / np.abs(cut).max()
        assert err < 2e-5, (n, err)
