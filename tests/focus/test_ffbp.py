"""Fast factorised backprojection against direct backprojection on the same data: point-target
figures (IRW within 2 %, PSLR within 0.5 dB, peak phase within 0.05 rad) at 5 km, 200 km and
560 km at 1.55 um, a curved trajectory, and a speckled scene's error energy below -40 dB."""
import numpy as np
import pytest

from salkit import focus, measure, simulate
from salkit.errors import ScenarioError
from salkit.focus.ffbp import (_tree, angle_lengths, aperture_parts, ffbp_layout, plan_parts, polar_tangent,
                               range_widening)
from salkit.focus.ffbp_leaves import _polar_line
from salkit.focus.formers import ImageGrid
from salkit.geometry.collection import grid_axes
from salkit.params import parse_scenario
from salkit.simulate.testbeds import seed, wide_angle

from ..conftest import GEO, SPOT, STRIP, merge

GEO560 = merge(GEO, platform__standoff=560000.0, platform__aperture_length=8.68, waveform__prf=300.0,
               platform__real_aperture=0.19)
CASES = {
    "5km": merge(SPOT, scene={"points": [{"x": 0.0, "y": 0.0, "phase": 0.7}, {"x": 0.12, "y": -0.2, "amplitude": 0.5}]}),
    "200km": GEO,
    "560km": GEO560,
}


def _images(d, **over):
    sc = parse_scenario(d)
    raw = simulate(sc)
    return sc, focus(raw, sc.processing, algorithm="bp", **over), focus(raw, sc.processing, algorithm="ffbp", **over)


def _error_db(a, b):
    A, B = a["image"].values, b["image"].values
    return 10 * np.log10(np.sum(np.abs(A - B) ** 2) / np.sum(np.abs(A) ** 2))


@pytest.mark.parametrize("case", list(CASES))
def test_point_targets_match_direct_backprojection(case):
    sc, a, b = _images(CASES[case])
    ph = sc.scene.points[0].phase
    ma, mb = measure(a, reflectivity_phase=ph), measure(b, reflectivity_phase=ph)
    for ax in ("range", "azimuth"):
        assert mb[f"irw_{ax}_m"] == pytest.approx(ma[f"irw_{ax}_m"], rel=0.02), ax
        assert abs(mb[f"pslr_{ax}_db"] - ma[f"pslr_{ax}_db"]) <= 0.5, ax
    assert abs(mb["peak_phase_error_rad"] - ma["peak_phase_error_rad"]) <= 0.05
    assert _error_db(a, b) < -40
    assert b.attrs["ffbp_levels"] >= 3


def test_speckled_scene_error_below_minus_40_db():
    d = merge(SPOT, scene={"points": [], "extended": {"kind": "pattern", "pattern": "uniform", "extent": [1.2, 1.2],
                                                      "spacing": 0.006, "speckle": True}})
    _, a, b = _images(d)
    assert _error_db(a, b) < -40


def test_any_trajectory():
    """A curved track (the antenna bows 3 cm, about 20000 wavelengths, off the straight line and
    wobbles vertically): still the direct image."""
    from salkit.geometry import build_collection
    pos = build_collection(parse_scenario(SPOT)).positions.copy()
    s = np.linspace(-1, 1, pos.shape[0])
    pos[:, 1] += 0.03 * (1 - s ** 2)
    pos[:, 2] += 0.005 * np.sin(3 * np.pi * s)
    d = merge(CASES["5km"], platform__positions=[tuple(map(float, p)) for p in pos])
    _, a, b = _images(d)
    assert _error_db(a, b) < -40


def test_stripmap_refused():
    sc = parse_scenario(STRIP)
    with pytest.raises(ScenarioError, match="ffbp"):
        focus(simulate(sc), sc.processing, algorithm="ffbp")


def test_rho_residual_restores_what_rounding_left_out():
    """|o - c| - rho for rho the float64 norm of a 560 km offset: within an ulp or two of rho, and
    rho + residual closer to the exact norm than rho (squares compared in exact rationals). Without
    it the last step differenced two ranges of 560 km at every pixel: a -64 dB floor at 1.55 um
    (tests/focus/test_exact_accuracy.py holds the -65 dB promise of ``accuracy: high`` there)."""
    from fractions import Fraction

    from salkit.focus.ffbp import rho_residual
    rng = np.random.default_rng(3)
    improved = 0
    for _ in range(20):
        c = rng.normal(size=3) * 3.2e5
        o = rng.normal(size=3) * 5.0
        rho = float(np.linalg.norm(o - c))
        res = rho_residual(o, c, rho)
        assert abs(res) <= 2.0 * np.spacing(rho)  # numpy's norm is not correctly rounded: an ulp or so
        exact = sum((Fraction(float(a)) - Fraction(float(b))) ** 2 for a, b in zip(o, c))
        better = (Fraction(rho) + Fraction(res)) ** 2 - exact
        assert abs(better) <= abs(Fraction(rho) ** 2 - exact)
        improved += abs(better) < abs(Fraction(rho) ** 2 - exact) / 1000
    assert improved == 20  # a thousand times closer at least, every time
    assert rho_residual(np.zeros(3), np.array([3.0, 4.0, 0.0]), 5.0) == 0.0


def test_image_keeps_no_larger_buffer():
    """The image is written into a spare polar-grid buffer and that buffer shrunk to it: what is
    returned holds the image's bytes and no more (and the image is the one a fresh buffer gives:
    tests above compare it with direct backprojection)."""
    from salkit.focus import phase_history
    from salkit.focus.ffbp import ffbp
    from salkit.focus.formers import ImageGrid
    from salkit.simulate.testbeds import wide_angle
    tb = wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.point_targets(64, count=3)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(64))
    P, M = ph.data.shape
    img, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M))
    assert info["ffbp_levels"] >= 4 and img.shape == (64, 64) and img.dtype == np.complex64
    assert img.base is not None  # a view of the shrunk spare buffer: that path was taken
    assert img.base.nbytes == img.nbytes
    assert np.isfinite(img).all() and np.abs(img).max() > 0


def _widening(tb, n):
    grid = tb.grid(n)
    ig = ImageGrid(tb.image_plane(), *grid_axes(grid), grid)
    pos = tb.positions
    return range_widening(_tree(pos, np.ones(pos.shape[0], np.float32), 16, 4), pos, ig, tb.frequency)


def line_geometry(plane: str):
    """A 30-degree arc's image plane (origin, e_a, e_r), one of its pulses as a line centre, and
    400 range samples of 5 cm from 10 m short of the origin: polar lines the kernels build."""
    tb = wide_angle(30.0, 0.5, plane, pulses=64)
    pl = tb.image_plane()
    o, ea, er = (np.ascontiguousarray(v, np.float64) for v in (pl.origin, pl.azimuth, pl.range))
    c = tb.positions[20]
    return o, ea, er, c, float(np.linalg.norm(o - c)) - 10.0, 0.05, 400


def test_polar_tangent_follows_the_kernels_polar_lines():
    """dx/dr of polar_tangent against central differences along the lines the kernels build
    (ffbp_leaves._polar_line), over a ground plane 7.3 km below (where the lines bend) and a slant
    plane, at direction cosines across a wide beam."""
    for plane in ("ground", "slant"):
        o, ea, er, c, r0, dr, n = line_geometry(plane)
        for u in (-0.3, 0.0, 0.12, 0.4):
            X0, X1, X2, rl = (np.empty(n) for _ in range(4))
            lo, top = _polar_line(o, ea, er, c, r0, dr, n, u, X0, X1, X2, rl)
            assert top - lo > 10
            X = np.stack([X0, X1, X2], axis=1)[lo:top + 1]
            fd = (X[2:] - X[:-2]) / (2.0 * dr)
            t = polar_tangent(X[1:-1], c, ea, er)
            assert np.allclose(t, fd, rtol=0, atol=1e-6)
            assert np.allclose(((X - c) @ ea) / np.linalg.norm(X - c, axis=1), u)  # the line's u


def test_range_widening_grows_with_the_aperture():
    """A short straight aperture keeps the pulse's band (the seed geometry at 5 km); over a wide
    arc the sub-images' range spectrum spreads (first order: parallax and curvature against the
    range; second: 1 - cos of the angle the pulses subtend), more on a ground plane far below
    than on the slant plane, and with the arc."""
    assert _widening(seed("5km", 64), 64) < 1.001
    ground = [_widening(wide_angle(a, 0.5, "ground", pulses=int(16 * a)), 101) for a in (4.0, 10.0, 30.0, 60.0)]
    slant = [_widening(wide_angle(a, 0.5, "slant", pulses=int(16 * a)), 101) for a in (4.0, 10.0, 30.0, 60.0)]
    assert np.all(np.diff(ground) > 0) and np.all(np.diff(slant) > 0)
    assert ground[0] < 1.03 and ground[2] > 1.3 and ground[3] > 3.0
    assert all(g > s for g, s in zip(ground[1:], slant[1:]))


def test_angle_sampling_follows_the_look_angle():
    """A straight 20 m sub-aperture broadside to its look direction, 7 km out at 7.3 km height: its
    band along the polar grid's direction cosine is that of its length straight ahead, and
    stretched by 1 / cos(theta) when it looks at the scene theta off the plane's range axis."""
    tb = wide_angle(4.0, 0.0, "ground", pulses=64)
    grid = tb.grid(32)
    ig = ImageGrid(tb.image_plane(), *grid_axes(grid), grid)
    ea, er = ig.plane.azimuth, ig.plane.range
    for deg in (0.0, 30.0, 60.0, 75.0):
        t = np.radians(deg)
        look = np.cos(t) * er + np.sin(t) * ea
        along = np.cross([0.0, 0.0, 1.0], look)
        pos = -7000.0 * look + np.array([0.0, 0.0, 7300.0]) + np.outer(np.linspace(-10.0, 10.0, 17), along)
        length = angle_lengths([(0, 17)], pos.mean(axis=0)[None], pos, ig)[0]
        assert length * np.cos(t) == pytest.approx(20.0, rel=5e-3)


def test_one_tree_refuses_an_aperture_past_the_scene_which_ffbp_forms_in_parts():
    """Over more than 180 degrees the arc's ends lie past the scene's near edge along the image's
    range axis, where one tree's polar grids cannot reach: one tree is refused before any work,
    naming the pulses and the distance; ``ffbp`` forms the arc in parts of at most 30 degrees, each
    on the quarter turn of the grid that looks at the scene from it, halved where its range widening
    passes 4x. With a narrow band (94 MHz at 9.3 GHz) the parts widen more: they are halved further,
    and some (30 to 60 degrees off the range axes) are backprojected directly, not formed by kernels
    designed past their limit."""
    from salkit.focus.ffbp import QUARTERS, ffbp, quarter_turn
    from salkit.simulate.testbeds import Testbed
    P = 2048
    phi = np.radians(np.linspace(-100.0, 100.0, P)) - np.pi / 2
    pos = np.stack([7000.0 * np.cos(phi), 7000.0 * np.sin(phi), np.full(P, 7300.0)], axis=1)
    for M in (424, 64):
        tb = Testbed("arc200", pos, 9.29e9 + 1.47e6 * np.arange(M), "ground", 0.01, 0.2)
        grid = tb.grid(32)
        ig = ImageGrid(tb.image_plane(), *grid_axes(grid), grid)
        args = (np.ones((P, M), np.complex64), tb.frequency, pos, np.linalg.norm(pos, axis=1), ig, np.ones(P),
                np.ones(M))
        with pytest.raises(ScenarioError, match=r"processing.algorithm = 'ffbp'.*pulses 0 to 15 lie [0-9.]+ m past it"):
            ffbp_layout(pos, tb.frequency, ig)
        with pytest.raises(ScenarioError, match=r"pulses 0 to 15 lie"):
            ffbp(*args, split=False)
        seen = []
        img, info = ffbp(*args, progress=lambda done, total: seen.append((done, total)))
        assert img.shape == (32, 32) and np.isfinite(img).all()
        # progress in levels over every part (more than the parts: each tree has two or more), rising to one total
        assert len({t for _, t in seen}) == 1 and seen[-1][0] == seen[-1][1] > info["ffbp_parts"]
        assert all(d1 >= d0 for (d0, _), (d1, _) in zip(seen[:-1], seen[1:]))
        assert len(aperture_parts(pos, ig)) == 7  # 200 degrees in parts of 30 at most
        parts = plan_parts(pos, tb.frequency, ig)
        assert info["ffbp_parts"] == len(parts)
        for kind, a, b in parts:  # every tree within the widening it may have
            if kind != "direct":
                t = quarter_turn(ig, QUARTERS.index(kind))
                levels = _tree(pos[a:b], np.ones(b - a, np.float32), 16, 4)
                assert range_widening(levels, pos[a:b], t, tb.frequency) <= 4.0
        if M == 424:
            assert len(parts) > 7 and {k for k, _, _ in parts} == {"left", "front", "right"}
            assert info["ffbp_direct_pulses"] == 0
        else:  # the parts over 30 to 60 degrees off the range axes widen past 4x even at 64 pulses
            assert 0 < info["ffbp_direct_pulses"] == sum(b - a for k, a, b in parts if k == "direct") < P
    assert ffbp_layout(pos[512:-512], tb.frequency, ig).widen > 1.0  # 100 degrees: one tree can


@pytest.mark.parametrize("quarter", [0, 1, 2, 3])
def test_quarter_turns_hold_the_same_pixels(quarter):
    """A grid turned by a quarter turn holds the same points (within rounding), its pixels brought
    back to the grid's order; its range axis looks from the side the turn names."""
    from salkit.focus.ffbp import from_quarter_turn, quarter_turn
    tb = wide_angle(4.0, 0.5, "ground", pulses=64)
    grid = tb.grid(32, 24)
    ig = ImageGrid(tb.image_plane(), *grid_axes(grid), grid)
    t = quarter_turn(ig, quarter)
    pts = ig.plane.points(ig.azimuth[:, None], ig.range[None, :])
    turned = t.plane.points(t.azimuth[:, None], t.range[None, :])
    back = np.stack([from_quarter_turn(turned[..., c], quarter) for c in range(3)], axis=-1)
    assert back.shape == pts.shape and np.abs(back - pts).max() < 1e-12
    assert np.all(np.diff(t.azimuth) > 0) and np.all(np.diff(t.range) > 0)
    look = [ig.plane.range, -ig.plane.azimuth, -ig.plane.range, ig.plane.azimuth][quarter]
    np.testing.assert_allclose(t.plane.range, look, atol=1e-15)
    np.testing.assert_allclose(np.cross(t.plane.azimuth, t.plane.range), np.cross(ig.plane.azimuth, ig.plane.range),
                               atol=1e-15)


def test_aperture_parts_cover_every_pulse_once_within_their_span():
    """Parts run in pulse order, cover every pulse once, and each FFBP part spans at most 30
    degrees of bearing, all of it before the scene as its quarter turn sees it; an arc within 30
    degrees is one part, as before."""
    from salkit.focus.ffbp import PART_SPAN_DEG, QUARTERS, _lead, quarter_turn
    for arc in (4.0, 30.0, 100.0, 250.0, 360.0):
        tb = wide_angle(arc, 0.5, "ground", pulses=1024)
        grid = tb.grid(48)
        ig = ImageGrid(tb.image_plane(), *grid_axes(grid), grid)
        parts = aperture_parts(tb.positions, ig)
        assert parts[0][1] == 0 and parts[-1][2] == 1024
        assert all(b0 == a1 for (_, _, b0), (_, a1, _) in zip(parts[:-1], parts[1:]))
        for kind, a, b in parts:
            if kind == "direct":
                continue
            d = tb.positions[a:b]
            t = quarter_turn(ig, QUARTERS.index(kind))
            assert (_lead(d, t) > 0).all()
            bearing = np.unwrap(np.arctan2(d @ t.plane.azimuth, -(d @ t.plane.range)))
            assert np.degrees(bearing.max() - bearing.min()) <= PART_SPAN_DEG * (1 + 1e-6)
        assert (len(parts) == 1) == (arc <= PART_SPAN_DEG)


@pytest.mark.parametrize("arc", [200.0, 360.0])
def test_past_180_degrees_and_a_full_circle_ffbp_keeps_its_promise(arc):
    """The X-band arc (7 km radius, 7.3 km height, climbing) over 200 degrees and a full circle,
    1024 pulses onto 64^2 pixels at 0.8 of the azimuth resolution (a speckled scene, 1 % of it 30
    times brighter), against the exact float64 matched filter: FFBP in parts keeps the accuracy it
    declares, -55 dB and bright-pixel phase p99 under 1 degree (measured -64.6 to -67.2 dB at 101^2
    and 2048 pulses; one tree was refused past 180 degrees), and -65 dB at accuracy high."""
    from salkit.focus import phase_history
    from salkit.focus.exact import exact_image
    from salkit.focus.formers import get_former
    from salkit.registry import FORMERS
    from salkit.signals.windows import Window
    tb = wide_angle(arc, 0.5, "ground", pulses=1024)
    pts, amp = tb.speckle(64, extent=1.0, density=0.15, seed=1)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(64))
    ro = ig.plane.points(ig.azimuth, np.zeros_like(ig.azimuth))
    truth = exact_image(ph.data, ph.freq, ph.positions, ph.reference_range, ro, ig.plane.range, ig.range)
    bright = np.abs(truth) >= np.abs(truth).max() * 10 ** (-1.5)
    assert bright.sum() >= 500
    for level in ("standard", "high"):
        r = get_former("ffbp")(ph, ig, Window("none"), accuracy=level)
        err = 10 * np.log10(np.sum(np.abs(r.image - truth) ** 2) / np.sum(np.abs(truth) ** 2))
        assert r.info["ffbp_parts"] >= 7 and err < FORMERS["ffbp"].accuracy[level].error_db, (level, err)
        if level == "standard":
            phase = np.degrees(np.abs(np.angle(r.image[bright] * np.conj(truth[bright]))))
            assert np.percentile(phase, 99) < 1.0


def test_polar_grids_beyond_the_memory_left_are_refused_before_any_work():
    """FFBP sizes its range profiles and every level's polar grids before any work (over a
    60-degree arc they hold several times what the sizes-only estimate counts) and refuses, naming
    them, when they exceed the memory this process may still use."""
    from salkit.errors import ResourceError
    from salkit.focus import phase_history
    from salkit.focus.formers import get_former
    from salkit.resources import set_limit
    from salkit.signals.windows import Window
    tb = wide_angle(60.0, 0.5, "ground", pulses=256)
    pts, amp = tb.speckle(32, extent=1.0, density=0.1, seed=1)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(32))
    set_limit(2 ** 19)
    try:
        with pytest.raises(ResourceError, match=r"FFBP of 256 pulses in 2 parts .*range profiles \(128 x \d+\) and "
                                                r"polar grids \(\d levels.*widened [2-4]\.\d+x.*32 x 32 image"):
            get_former("ffbp")(ph, ig, Window("none"))
    finally:
        set_limit(None)
    assert np.isfinite(get_former("ffbp")(ph, ig, Window("none")).image).all()


def test_narrow_strips_keep_the_promise():
    """A strip of one or two range pixels (or azimuth pixels) is all edge: FFBP forms it on a grid of
    at least 32 pixels a side and crops it, and keeps its -55 dB against the exact matched filter
    (one range column formed as it is came out at -38 dB). Uniform speckle, so that every strip
    holds its share of the energy."""
    from salkit.focus import phase_history
    from salkit.focus.exact import exact_image
    from salkit.focus.formers import get_former
    from salkit.signals.windows import Window
    tb = wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.speckle(101, extent=1.0, density=0.15, bright=0.0, seed=1)
    ph = phase_history(tb.dataset(pts, amp))
    for nx, ny in ((101, 1), (101, 2), (1, 101)):
        ig = ImageGrid.of(ph, tb.grid(101).model_copy(update={"nx": nx, "ny": ny}))
        ro = ig.plane.points(ig.azimuth, np.zeros_like(ig.azimuth))
        truth = exact_image(ph.data, ph.freq, ph.positions, ph.reference_range, ro, ig.plane.range, ig.range)
        img = get_former("ffbp")(ph, ig, Window("none")).image
        assert img.shape == (nx, ny)
        assert 10 * np.log10(np.sum(np.abs(img - truth) ** 2) / np.sum(np.abs(truth) ** 2)) < -55.0


@pytest.mark.parametrize("plane", ["ground", "slant"])
def test_planning_kernels_are_numpys_broadcast_forms(plane):
    """The angle sampling's and the range widening's one-pass kernels against the NumPy broadcasts
    they replaced (0.30.2), on a 30-degree arc's sub-apertures: the same numbers to the last bits."""
    from salkit.focus.ffbp import _band_rates, _range_rates, _sampled_pulses, _scene_points
    tb = wide_angle(30.0, 0.5, plane, pulses=256)
    grid = tb.grid(64)
    ig = ImageGrid(tb.image_plane(), *grid_axes(grid), grid)
    pos = tb.positions
    levels = _tree(pos, np.ones(pos.shape[0], np.float32), 16, 4)
    spans, centres = levels[1][0], levels[1][1]
    x = _scene_points(ig)
    ea, er = ig.plane.azimuth, ig.plane.range
    p = pos[_sampled_pulses(spans, 9)]
    d = x - centres[:, None, :]
    r = np.sqrt(np.einsum("skj,skj->sk", d, d))
    dxdu = r[..., None] * ea - (r * (d @ ea) / np.maximum(d @ er, 1e-9 * r))[..., None] * er
    v = x[None, None] - p[:, :, None]
    nv = v / np.sqrt(np.einsum("snkj,snkj->snk", v, v))[..., None] - (d / r[..., None])[:, None]
    want = np.abs(np.einsum("snkj,skj->snk", nv, dxdu)).max(axis=(1, 2))
    assert np.allclose(_band_rates(x, p, d / r[..., None], np.ascontiguousarray(dxdu)), want, rtol=1e-12, atol=0)
    t = polar_tangent(x, centres[:, None, :], ea, er)
    drc = np.maximum(np.einsum("skj,skj->sk", d, t) / r, 1e-9)
    D = np.einsum("snkj,skj->snk", v, t) / np.sqrt(np.einsum("snkj,snkj->snk", v, v)) / drc[:, None]
    lo, hi = _range_rates(x, p, np.ascontiguousarray(t), drc)
    assert lo == pytest.approx(D.min(), rel=1e-13) and hi == pytest.approx(D.max(), rel=1e-13)
    assert hi > lo
