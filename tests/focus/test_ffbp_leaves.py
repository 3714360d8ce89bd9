"""FFBP's leaf kernels: the least-squares interpolation tables against Lagrange on band-limited
signals, their polynomial form against the float64 weights, and the leaves' series for
R - |X - c| against the exact quotient."""
import numpy as np
import pytest

from salkit.focus.ffbp_leaves import interpolation_table, least_squares_weights, polynomial_weights


def _bandlimited(os, n=2048, seed=0):
    """Samples of a random signal flat in |f| < 1/(2 os) cycles/sample, and an exact evaluator."""
    rng = np.random.default_rng(seed)
    f = (np.arange(n) / n - 0.5) / os
    a = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    at = lambda x: np.exp(2j * np.pi * np.outer(x, f)) @ a  # noqa: E731
    return at(np.arange(64, dtype=float)), at


@pytest.mark.parametrize("taps, os, limit_db, gain_db", [(6, 1.75, -47.0, 12.0), (8, 1.75, -60.0, 12.0),
                                                         (4, 4.0, -60.0, 6.0)])
def test_interpolation_table_error_on_band_limited_signals(taps, os, limit_db, gain_db):
    """The least-squares kernel interpolates a band-limited signal to its design accuracy (flat
    spectrum: -50, -64 and -70 dB expected), far better than Lagrange at the same taps."""
    s, at = _bandlimited(os)
    W = interpolation_table(taps, os)
    x = np.random.default_rng(1).uniform(taps, 64 - taps, 400)
    i0 = np.floor(x).astype(int)
    t = x - i0
    offs = np.arange(-(taps // 2 - 1), taps // 2 + 1)
    est = np.sum(W[np.rint(t * (W.shape[0] - 1)).astype(int)] * s[i0[:, None] + offs], axis=1)
    truth = at(x)
    err = 10 * np.log10(np.sum(np.abs(est - truth) ** 2) / np.sum(np.abs(truth) ** 2))
    assert err < limit_db
    lag = np.ones((t.size, taps))
    for i, oi in enumerate(offs):
        for j, oj in enumerate(offs):
            if i != j:
                lag[:, i] *= (t - oj) / (oi - oj)
    err_lag = 10 * np.log10(np.sum(np.abs(np.sum(lag * s[i0[:, None] + offs], axis=1) - truth) ** 2)
                            / np.sum(np.abs(truth) ** 2))
    assert err < err_lag - gain_db


def test_leaf_series_equals_the_exact_quotient(monkeypatch):
    """The leaves' series for R - |X - c| (no square root or division) against the exact
    quotient, on the wide-angle arc where it is used: the same image to -100 dB."""
    import salkit.focus.ffbp as F
    from salkit.focus import phase_history
    from salkit.focus.formers import ImageGrid
    from salkit.simulate.testbeds import wide_angle
    tb = wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.point_targets(64, count=3)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(64))
    P, M = ph.data.shape
    a, _ = F.ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M))
    monkeypatch.setattr(F, "SERIES", False)
    b, _ = F.ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M))
    assert np.sum(np.abs(a - b) ** 2) <= 1e-10 * np.sum(np.abs(b) ** 2)  # -100 dB (often identical in float32)


@pytest.mark.parametrize("os", [1.25, 1.5, 1.75, 2.0, 3.0, 4.0])
def test_polynomial_weights_equal_the_least_squares_weights(os):
    """The weights' polynomials (evaluated in float32, as the kernels do) stay within 2e-5 of
    the float64 least-squares weights at every fraction, closer than the table's nearest entry."""
    t = np.random.default_rng(2).uniform(0.0, 1.0, 5000)
    c = polynomial_weights(8, os)
    s = (2.0 * t - 1.0).astype(np.float32)
    w = np.zeros((t.size, 8), np.float32)
    for d in range(c.shape[1] - 1, -1, -1):  # Horner in float32
        w = w * s[:, None] + c[:, d][None, :]
    exact = least_squares_weights(8, os, t)
    assert np.abs(w - exact).max() < 2e-5
    table = interpolation_table(8, os)
    nearest = table[np.rint(t * (table.shape[0] - 1)).astype(int)]
    assert np.abs(w - exact).max() < np.abs(nearest - exact).max()


def _seed_case(which="5km", n=128, plane="slant"):
    """A seed geometry's phase history of a few points (straight track), its grid and the exact
    former's image on every 8th row."""
    from salkit.focus import phase_history
    from salkit.focus.exact import exact_image
    from salkit.focus.formers import ImageGrid
    from salkit.simulate.testbeds import seed
    tb = seed(which, n, plane)
    pts, amp = tb.point_targets(n, count=5)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(n))
    sel = np.arange(4, n, 8)
    rows = ig.plane.points(ig.azimuth[sel], np.zeros(sel.size))
    truth = exact_image(ph.data, ph.freq, ph.positions, ph.reference_range, rows, ig.plane.range, ig.range)
    return ph, ig, sel, truth


def _form(ph, ig, **kw):
    """FFBP's image normalised as the ``ffbp`` former's (no window: by pulses x frequencies), and its info."""
    import salkit.focus.ffbp as F
    P, M = ph.data.shape
    img, info = F.ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M), **kw)
    return img / np.float32(P * M), info


def _db(a, b):
    return 10 * np.log10(np.sum(np.abs(a - b) ** 2) / np.sum(np.abs(b) ** 2))


@pytest.mark.parametrize("which, plane", [("5km", "slant"), ("200km", "ground")])
def test_fft_leaves_are_the_interpolating_leaves_without_their_error(monkeypatch, which, plane):
    """On a seed paper's straight track the leaves are formed by FFT (the pulses' spectra with their
    range ramps, no profile interpolation): the image differs from the interpolating leaves' (the
    same 16-pulse leaves) by their interpolation error only, and is at least as close to the
    exact matched filter."""
    import salkit.focus.ffbp as F
    ph, ig, sel, truth = _seed_case(which, 128, plane)
    lay = F.ffbp_layout(ph.positions, ph.freq, ig)
    assert lay.fft_leaves and max(b - a for a, b in lay.levels[0][0]) == F.FFT_LEAF_PULSES
    fft, info = _form(ph, ig, leaf=16)
    assert info["ffbp_leaf_pulses"] == 16
    monkeypatch.setattr(F, "FFT_LEAVES", False)
    interp, _ = _form(ph, ig, leaf=16)
    assert _db(fft, interp) < -60.0
    e_fft, e_interp = _db(fft[sel], truth), _db(interp[sel], truth)
    assert e_fft < -50.0 and e_fft <= e_interp + 0.2  # 200 km at 128^2: -53.3 dB either way (-55.3 with 32-pulse leaves)


def test_default_leaves_by_fft_are_longer_and_as_exact():
    """Where the leaves fit the FFT, the default takes leaves of FFT_LEAF_PULSES (at 4096 pulses one
    merge fewer) and stays within the default's accuracy against the exact matched filter."""
    import salkit.focus.ffbp as F
    for plane in ("slant", "ground"):
        ph, ig, sel, truth = _seed_case("5km", 256, plane)
        img, info = _form(ph, ig)
        assert info["ffbp_leaf_pulses"] == F.FFT_LEAF_PULSES
        assert _db(img[sel], truth) < -55.0, plane


def test_curved_tracks_do_not_fit_fft_leaves_on_the_planes_axis(monkeypatch):
    """A pulse's range against its leaf's centre moves along a polar line of the plane's axis where
    the track bends or climbs (the 4-degree X-band arc: by far more than the FFT leaves' tolerance),
    so without the leaves' own axes (salkit.focus.ffbp_axes, the default there) those leaves are
    interpolated, 16 pulses long; a straight track's spread is the closed form's
    |q|^2 (1 - u^2) / 2 (1/r_near - 1/r_far), metres below a picometre."""
    import salkit.focus.ffbp as F
    from salkit.focus import phase_history
    from salkit.focus.formers import ImageGrid
    from salkit.simulate.testbeds import wide_angle
    tb = wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.point_targets(64, count=3)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(64))
    assert F.ffbp_layout(ph.positions, ph.freq, ig).frame is not None  # by default: on their own axes
    monkeypatch.setattr(F, "OWN_AXIS_LEAVES", False)
    lay = F.ffbp_layout(ph.positions, ph.freq, ig)
    assert not lay.fft_leaves and max(b - a for a, b in lay.levels[0][0]) == F.LEAF_PULSES
    spans, centres = lay.levels[0][0], lay.levels[0][1]
    spread = F.leaf_shift_spread(spans, centres, lay.grids[0], ph.positions, ig, lay.dr)
    assert 4 * np.pi * ph.freq[-1] / 299792458.0 * spread > 10 * F.FFT_LEAF_TOLERANCE
    _, info = _form(ph, ig)
    assert info["ffbp_leaf_pulses"] == F.LEAF_PULSES
    # a straight track: the closed form bounds the sampled spread from above, and meets it within 10 %
    ph2, ig2, _, _ = _seed_case("5km", 64)
    lay2 = F.ffbp_layout(ph2.positions, ph2.freq, ig2, "standard")
    spans2, centres2 = lay2.levels[0][0], lay2.levels[0][1]
    u0, du, nu, r0, nr = lay2.grids[0]
    spread2 = F.leaf_shift_spread(spans2, centres2, lay2.grids[0], ph2.positions, ig2, lay2.dr)
    a = np.array([np.abs((ph2.positions[[s0, s1 - 1]] - c) @ ig2.plane.azimuth).max() for (s0, s1), c in zip(spans2, centres2)])
    u_min = np.minimum(np.abs(u0), np.abs(u0 + (nu - 1) * du))
    bound = np.max(a ** 2 * (1 - u_min ** 2) / 2 * (1 / r0 - 1 / (r0 + (nr - 1) * lay2.dr)))
    assert 0.9 * bound <= spread2 <= 1.01 * bound


def test_fft_leaves_layout_holds_each_line_once_and_one_batch_of_transforms(monkeypatch):
    """The FFT leaves' grid buffer holds each line's own points (as the interpolating leaves'), one
    parent's leaves at a time (all of them without that), the lines transformed a batch at a time in
    a scratch of the FFT length: the layout's bytes say so."""
    import salkit.focus.ffbp as F
    ph, ig, _, _ = _seed_case("5km", 64)
    monkeypatch.setattr(F, "OWN_AXIS_LEAVES", False)  # the plane's axis (own axes: test_ffbp_axes)
    lay = F.ffbp_layout(ph.positions, ph.freq, ig)
    S, nu, nr = len(lay.levels[0][0]), int(lay.grids[0][2].max()), int(lay.grids[0][4].max())
    assert lay.fft_leaves and len(lay.levels) > 1
    assert lay.grid_bytes[0] == 8.0 * lay.levels[1][3] * nu * nr  # a parent's leaves at a time
    monkeypatch.setattr(F, "FUSED_LEAVES", False)
    assert F.ffbp_layout(ph.positions, ph.freq, ig).grid_bytes[0] == 8.0 * S * nu * nr  # all the leaves
    P, M = ph.data.shape
    spectra = 8.0 * P * (-(-M // F.RAMP_BLOCK) * F.RAMP_BLOCK)
    assert lay.profile_bytes == spectra + 8.0 * min(S * nu, F.FFT_LEAF_BATCH) * lay.nfft
    assert lay.nfft >= nr


def test_fft_leaves_in_any_batch_are_the_same_image(monkeypatch):
    """Lines transformed a few at a time (batches ending inside a leaf, a last batch part full) give
    the image of the default batch: each line lands in its own row of the grid."""
    import salkit.focus.ffbp as F
    ph, ig, _, _ = _seed_case("5km", 64)
    img = _form(ph, ig)[0]
    monkeypatch.setattr(F, "FFT_LEAF_BATCH", 7)
    small = _form(ph, ig)[0]
    assert F.ffbp_layout(ph.positions, ph.freq, ig).fft_leaves
    assert np.max(np.abs(small - img)) <= 1e-6 * np.max(np.abs(img))


def test_fft_leaves_beyond_the_memory_left_are_refused_naming_the_spectra():
    """The FFT leaves' layout is what FFBP sizes before any work: beyond the memory this process may
    still use it refuses, naming the pulses' spectra it would hold (not range profiles it would not)."""
    from salkit.errors import ResourceError
    from salkit.resources import set_limit
    ph, ig, _, _ = _seed_case("5km", 64)
    P, M = ph.data.shape
    set_limit(2 ** 19)
    try:
        with pytest.raises(ResourceError, match=rf"FFBP's pulses' spectra \({P} x {M}\) and polar grids"):
            _form(ph, ig)
    finally:
        set_limit(None)
    assert np.isfinite(_form(ph, ig)[0]).all()


def test_fft_leaves_a_parent_at_a_time_are_all_the_leaves_then_merged(monkeypatch):
    """Leaves formed and merged a parent at a time (the default) give the image of all the leaves
    formed first and merged after, the same sums in the same order: bit for bit."""
    import salkit.focus.ffbp as F
    ph, ig, _, _ = _seed_case("200km", 64, "ground")
    img, info = _form(ph, ig)
    assert F.ffbp_layout(ph.positions, ph.freq, ig).fft_leaves and info["ffbp_levels"] > 2
    monkeypatch.setattr(F, "FUSED_LEAVES", False)
    assert np.array_equal(_form(ph, ig)[0], img)


def test_leaf_store_keeps_each_lines_span_and_zeros_the_rest():
    """A transformed line's first points into its shorter row, zero outside its kept span (first and
    last index kept; a span past the row clipped to it; none where last < first)."""
    from salkit.focus.ffbp_leaves import _leaf_store
    lines = (np.arange(4 * 10) + 1j).astype(np.complex64).reshape(4, 10)
    lims = np.array([[2, 4], [0, 12], [5, 3], [-3, 0]], np.int64)
    out = np.full((4, 6), 99.0 + 0j, np.complex64)
    _leaf_store(lines, lims, out)
    want = np.zeros((4, 6), np.complex64)
    want[0, 2:5] = lines[0, 2:5]
    want[1, :] = lines[1, :6]
    want[3, :1] = lines[3, :1]
    assert np.array_equal(out, want)


@pytest.mark.parametrize("plane", ["ground", "slant"])
def test_polar_line_terms_are_the_lines_points_less_the_centre(plane):
    """A merge's view of a polar line (f + r u e_a + t e_r = X - c, each point's r and t) is the
    line the leaves build (_polar_line) less its centre, from the same first point on; with the
    plane's origin moved 6400 km along e_a (the same plane) the line is the same to the float64
    rounding of that distance (1e-9 m)."""
    from salkit.focus.ffbp_leaves import _polar_line, _polar_line_terms

    from .test_ffbp import line_geometry
    o, ea, er, c, r0, dr, n = line_geometry(plane)
    for u in (-0.3, 0.0, 0.12, 0.4):
        X0, X1, X2, rl, tl, rl2 = (np.empty(n) for _ in range(6))
        lo, top = _polar_line(o, ea, er, c, r0, dr, n, u, X0, X1, X2, rl2)
        lo_t, top_t, f0, f1, f2 = _polar_line_terms(o, ea, er, c, r0, dr, n, u, rl, tl)
        assert (lo_t, top_t) == (lo, top) and top - lo > 10
        m = top + 1 - lo
        X = np.stack([X0, X1, X2], axis=1)[lo:top + 1]
        E = np.array([f0, f1, f2]) + rl[:m, None] * u * ea + tl[:m, None] * er
        assert np.array_equal(rl[:m], rl2[lo:top + 1])
        assert np.abs(E - (X - c)).max() < 1e-8
        assert np.allclose((E @ ea) / np.linalg.norm(E, axis=1), u, rtol=0, atol=1e-12)  # the line's u
        far = _polar_line_terms(o + 6.4e6 * ea, ea, er, c, r0, dr, n, u, rl2, X0)
        assert far[:2] == (lo, top) and np.abs(np.array(far[2:]) - [f0, f1, f2]).max() < 1e-8


@pytest.mark.parametrize("dtype", [np.complex64, np.complex128])
def test_windowed_spectra_are_the_windowed_parts_padded_with_zeros(dtype):
    """The FFT leaves' inputs: each pulse's real and imaginary parts times the range window, as
    float32, then zeros to the padded length, whatever the buffers held before (they come from
    np.empty), for complex64 and complex128 phase histories."""
    from salkit.focus.ffbp_leaves import _windowed_spectra
    rng = np.random.default_rng(7)
    P, M, padded = 5, 37, 64
    ph = (rng.normal(size=(P, M)) + 1j * rng.normal(size=(P, M))).astype(dtype)
    wr = np.hanning(M + 2)[1:-1].astype(np.float32)
    are = np.full((P, padded), np.nan, np.float32)
    aim = np.full((P, padded), np.nan, np.float32)
    _windowed_spectra(ph, wr, are, aim)
    assert np.array_equal(are[:, :M], (ph.real * wr).astype(np.float32))
    assert np.array_equal(aim[:, :M], (ph.imag * wr).astype(np.float32))
    assert not are[:, M:].any() and not aim[:, M:].any()


def test_fft_leaves_reusing_a_dirty_scratch_give_the_same_lines():
    """The FFT leaves with a scratch kept across calls (as the parents' leaves share one) and filled
    with NaN before each: bit for bit the lines a fresh scratch gives, on the plane's axes (the seed
    geometry) and on the leaves' own (the arc, with the correction's scratch): every float of the
    scratch a call reads it has written."""
    import salkit.focus.ffbp as F
    from salkit.constants import SPEED_OF_LIGHT

    from .test_ffbp_axes import _arc
    for ph, ig in (_seed_case("5km", 64)[:2], _arc(128)):
        pos, freq, ref = ph.positions, ph.freq, ph.reference_range
        P, M = ph.data.shape
        lay = F.ffbp_layout(pos, freq, ig)
        assert lay.fft_leaves
        spans, centres = lay.levels[0][0], lay.levels[0][1]
        u0, du, nu, r0, nr = lay.grids[0]
        pl = ig.plane
        o, ea, er = (np.ascontiguousarray(v, np.float64) for v in (pl.origin, pl.azimuth, pl.range))
        first, count, _, qrel = F.leaf_pulses(spans, centres, pos, ref, o)
        are, aim = F._leaf_inputs(ph.data, np.ones(M))
        args = (are, aim, M, lay.dr, ref, qrel, np.ones(P, np.float32))
        cyc = 2.0 * freq[M // 2] / SPEED_OF_LIGHT
        shape = (2, int(nu.max()), int(nr.max()))
        work = F._fft_work(shape[0] * shape[1], lay.nfft, lay.frame is not None)
        for a in (0, len(spans) // 2, len(spans) - 2):
            s = slice(a, a + 2)
            fr = None if lay.frame is None else lay.frame[s]
            geo = (first[s], count[s], centres[s], o, ea, er, u0[s], du[s], nu[s], r0[s], nr[s], cyc, lay.nfft)
            fresh = np.zeros(shape, np.complex64)
            F._fft_leaves(*args, *geo, fresh, fr)
            for buf in work:
                if buf is not None and buf.dtype.kind in "fc":
                    buf.fill(np.nan)
            kept = np.zeros(shape, np.complex64)
            F._fft_leaves(*args, *geo, kept, fr, work)
            assert np.array_equal(kept, fresh) and np.abs(fresh).max() > 0


def test_kernel_designs_are_computed_once_and_handed_out_as_copies():
    """FFBP asks for the same kernels at every call: each is designed once (cached) and every
    caller gets its own writable copy, so that one caller's writes reach no other."""
    from salkit.focus import ffbp_leaves
    for get, cached in ((polynomial_weights, ffbp_leaves._polynomials), (interpolation_table, ffbp_leaves._table)):
        first = get(8, 1.8125)
        hits = cached.cache_info().hits
        first[:] = 0.0
        again = get(8, 1.8125)
        assert cached.cache_info().hits == hits + 1
        assert again.flags.writeable and not np.shares_memory(first, again)
        assert np.abs(again).max() > 0.5  # the design, not the zeros written into the first copy
