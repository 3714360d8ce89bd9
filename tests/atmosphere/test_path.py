"""Multi-layer frozen-screen paths: pulse-to-pulse phase statistics against the path theory."""

import numpy as np
import pytest

from salkit.atmosphere import r0_from_cn2
from salkit.atmosphere.path import build_path, path_frame, two_way_phases
from salkit.errors import ScenarioError


def test_two_way_phase_difference_matches_path_theory():
    """Seed 004 geometry: 10 km, 2 um, 50 layers, Cn2 = 1e-14, 0.5 m aperture. Over an ensemble
    of paths, <(phi(u + d) - phi(u))^2> of the two-way phase = 4 x the layered one-way theory
    sum_i 6.88 (d z_i / (R r0_i))^(5/3) (spherical-wave weighting), and the phase's variance
    about its least-squares line across the aperture = -tr(P D P) / 2N (D the theory's
    structure function between the N positions, P the projection that removes piston and tilt).

    Both statistics are dominated by a few Gaussian modes of the whole path (tilt, then focus),
    so one path's estimate spreads by 80-110 % of its mean however many layers it crosses (sets
    of 40 paths gave 0.78 to 1.24 of theory): the ensemble has 160 paths and each comparison is
    bounded by three standard errors of its own mean (from the sample, 6-9 % here) plus 3 % for
    the screens' model, the standard errors held below 10 %. The lags stay within a quarter of
    the 80-sample screens on the top layer (0.125 m is 16 samples), where the screens hold their
    structure function to about 1 %; at 0.25 m (31 samples) 400 paths gave 1.12 +- 0.08 of theory
    with these screens, and 1.06 +- 0.07 with 128-sample screens.
    """
    R, lam, L = 1e4, 2e-6, 0.5
    u0, a = np.array([0.0, -0.6, 0.8]), np.array([1.0, 0.0, 0.0])
    u = np.linspace(-L / 2, L / 2, 101)
    pos = (R * u0)[None, :] + u[:, None] * a[None, :]
    tgt = np.zeros((1, 3))
    lags = np.array([10, 25])  # pulses: d = 0.05, 0.125 m
    V = np.vander(u, 2)
    proj = np.eye(u.size) - V @ np.linalg.pinv(V)  # removes piston and tilt
    K = 160
    sf = np.zeros((K, lags.size))
    res = np.zeros(K)
    for seed in range(K):
        path = build_path(1e-14, R, lam, 50, 80, 0.008, u0, a, seed=seed)
        phi = two_way_phases(pos, tgt, path.screens, path.z, path.origin, path.dx, path.u0, path.a, path.b)[:, 0]
        for i, g in enumerate(lags):
            sf[seed, i] = np.mean((phi[g:] - phi[:-g]) ** 2)
        res[seed] = np.mean((proj @ phi) ** 2)
    d = lags * (u[1] - u[0])
    theory = 4 * path.one_way_structure_function(d, R)
    D = 4 * path.one_way_structure_function(np.abs(u[:, None] - u[None, :]).ravel(), R).reshape(u.size, u.size)
    theory_res = -np.trace(proj @ D @ proj) / (2 * u.size)
    for est, th in [(sf[:, i], theory[i]) for i in range(lags.size)] + [(res, theory_res)]:
        ratio = est / th
        se = ratio.std(ddof=1) / np.sqrt(K)
        assert se < 0.10, se
        assert abs(ratio.mean() - 1.0) <= 3.0 * se + 0.03, (ratio.mean(), se)
    # the layered theory is the spherical-wave r0 of the path: 6.88 (d / r0_sph)^(5/3)
    r0_sph = r0_from_cn2(1e-14, R, lam, "spherical")
    assert path.one_way_structure_function(d, R) == pytest.approx(6.88 * (d / r0_sph) ** (5 / 3), rel=0.02)


def test_spacing_warning_and_bad_cn2():
    with pytest.warns(UserWarning, match="Fresnel limit"):
        build_path(1e-13, 1e4, 2e-6, 10, 32, 0.01, np.array([0, 0, 1.0]), np.array([1.0, 0, 0]))
    with pytest.raises(ScenarioError, match="cn2"):
        build_path(-1e-14, 1e4, 2e-6, 10, 32, 0.01, np.array([0, 0, 1.0]), np.array([1.0, 0, 0]))


def test_profiled_cn2_path():
    """A Cn2 profile: each layer's r0 from its own Cn2; the path theory weights them by (z/R)^(5/3)."""
    R, lam, L = 1e4, 2e-6, 10
    prof = np.geomspace(1e-13, 1e-16, L)  # strong near the ground (scene), weak near the platform
    with pytest.warns(UserWarning, match="Fresnel limit"):  # 10 layers are too few for the 1e-13 layer
        path = build_path(prof, R, lam, L, 64, 0.01, np.array([0, 0, 1.0]), np.array([1.0, 0, 0]))
    assert path.r0 == pytest.approx(r0_from_cn2(prof, R / L, lam))
    d = np.array([0.1])
    expect = sum(6.8839 * (d * z / (R * r)) ** (5 / 3) for z, r in zip(path.z, path.r0))
    assert path.one_way_structure_function(d, R) == pytest.approx(expect, rel=1e-3)
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    with pytest.raises(ScenarioError, match="one value per layer"):
        parse_scenario(merge(SPOT, atmosphere={"cn2": [1e-14, 1e-15], "layers": 3}))
    sc = parse_scenario(merge(SPOT, atmosphere={"cn2": [1e-14, 1e-15, 1e-16], "layers": 3}))
    assert sc.atmosphere.cn2 == (1e-14, 1e-15, 1e-16)


def test_path_frame_is_orthonormal_and_right_handed():
    u0, a, b = path_frame(np.array([0.0, -3.0, 4.0]), np.array([1.0, 2.0, 0.0]))
    m = np.stack([u0, a, b])
    np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(m) == pytest.approx(1.0)
    np.testing.assert_allclose(u0, [0.0, -0.6, 0.8])


def test_aperture_strehl_limits():
    """The synthetic aperture's long-exposure Strehl: 1 for a single pulse, falls with Cn2, a
    tapered window (weight in the centre: shorter effective aperture) raises it, and for one
    layer with a uniform window equals the closed form 2/L^2 int (L-u) exp(-D2(u)/2) du."""
    from salkit.atmosphere.path import aperture_strehl, path_layers
    R, lam, n = 10e3, 2e-6, 2001
    pos = np.zeros((n, 3))
    pos[:, 0] = np.linspace(-0.25, 0.25, n)
    u0 = np.array([0.0, 0.0, 1.0])
    z1, r1 = path_layers(1e-15, R, lam, 50)
    z2, r2 = path_layers(1e-14, R, lam, 50)
    s1 = aperture_strehl(z1, r1, R, pos, np.ones(n), u0)
    s2 = aperture_strehl(z2, r2, R, pos, np.ones(n), u0)
    assert 0 < s2 < s1 < 1
    assert aperture_strehl(z1, r1, R, pos[:1], np.ones(1), u0) == 1.0
    assert aperture_strehl(z1, r1, R, pos, np.hamming(n), u0) > s1
    z, r0 = np.array([R]), np.array([0.05])  # one layer at the antenna: D1(d) = 6.88 (d / r0)^(5/3)
    u = np.linspace(0, 0.5, 200001)
    closed = 2 / 0.5 ** 2 * np.trapezoid((0.5 - u) * np.exp(-2 * 6.88 * (u / 0.05) ** (5 / 3)), u)
    assert aperture_strehl(z, r0, R, pos, np.ones(n), u0) == pytest.approx(closed, rel=2e-3)


def test_paths_of_one_seed_share_their_draws_scaled_by_r0():
    """Two Cn2 with one seed: the same draws, each layer's screen scaled by r0^(-5/6) (a screen of
    Fried parameter r0 is the r0 = 1 m screen times r0^(-5/6)), to float32 rounding; another seed
    draws other screens; a path's screens are its own (writing them leaves the next path alone)."""
    from salkit.atmosphere.screens import phase_screens
    args = (1e3, 2e-6, 4, 48, 0.01, np.array([0.0, -0.6, 0.8]), np.array([1.0, 0.0, 0.0]))
    a = build_path(1e-15, *args, seed=3)
    b = build_path(1e-14, *args, seed=3)
    ratio = (a.r0 / b.r0) ** (-5.0 / 6.0)
    np.testing.assert_allclose(a.screens, b.screens * ratio[:, None, None].astype(np.float32), rtol=1e-5, atol=1e-6)
    # all the layers in one draw from one generator (two a complex FFT), as drawn at the layer's r0
    drawn = phase_screens(48, 0.01, float(a.r0[0]), count=4, rng=np.random.default_rng(3), dtype=np.float32)
    for k in range(4):
        np.testing.assert_allclose(a.screens[k] * (a.r0[k] / a.r0[0]) ** (5.0 / 6.0), drawn[k], rtol=1e-5,
                                   atol=1e-5 * np.abs(drawn[k]).max())
    assert not np.allclose(build_path(1e-15, *args, seed=4).screens, a.screens)
    a.screens[:] = 0.0
    assert np.abs(build_path(1e-15, *args, seed=3).screens).max() > 0


def test_screens_memory_counts_the_kept_draw():
    """A path's screens are counted twice while their unit draw is kept beside them, once beyond
    the cache's bound (never kept); a path without a seed draws afresh every time."""
    from salkit.atmosphere.path import UNIT_SCREEN_CACHE_BYTES, screens_memory
    assert screens_memory(50, 256) == 2 * 4.0 * 50 * 256 * 256
    big = int((UNIT_SCREEN_CACHE_BYTES / 4.0 / 50) ** 0.5) + 1
    assert screens_memory(50, big) == 4.0 * 50 * big * big
    args = (1e3, 2e-6, 4, 32, 0.01, np.array([0.0, -0.6, 0.8]), np.array([1.0, 0.0, 0.0]))
    assert not np.allclose(build_path(1e-15, *args, seed=None).screens, build_path(1e-15, *args, seed=None).screens)
