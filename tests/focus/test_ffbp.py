"""Fast factorised backprojection against direct backprojection on the same data: point-target
figures (IRW within 2 %, PSLR within 0.5 dB, peak phase within 0.05 rad) at 5 km, 200 km and
560 km at 1.55 um, a curved trajectory, and a speckled scene's error energy below -40 dB."""
import numpy as np
import pytest

from salkit import focus, measure, simulate
from salkit.errors import ScenarioError
from salkit.params import parse_scenario

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


def test_final_step_point_by_point_agrees(monkeypatch):
    """Where image rows do not cross the sub-apertures' range bins in order, the last step
    interpolates point by point (48 taps): the same image as the separable row pass."""
    import salkit.focus.ffbp as ffbp_module
    sc, a, b = _images(CASES["5km"])
    monkeypatch.setattr(ffbp_module, "_rows_in_order", lambda *args: False)
    c = focus(simulate(sc), sc.processing, algorithm="ffbp")
    assert _error_db(a, c) < -40
    assert _error_db(b, c) < -40


def test_stripmap_refused():
    sc = parse_scenario(STRIP)
    with pytest.raises(ScenarioError, match="ffbp"):
        focus(simulate(sc), sc.processing, algorithm="ffbp")


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
    from salkit.focus.ffbp import interpolation_table
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
