"""Seed 001: orbital geometry, resolution against squint (eq 12), single-look SNR (eq 14-15) and
the stacking gain sqrt(P) (eq 16)."""
import math

import numpy as np
import pytest

from salkit import focus, measure, simulate
from salkit.errors import ScenarioError
from salkit.geometry.orbit import (collection_span, max_squint_for, n_subimages, relative_speed,
                                   resolution_vs_squint, straight_line_error, subaperture_length)
from salkit.params import parse_scenario
from salkit.systems.spaceborne import stack, stack_snr, subimage

from ..conftest import GEO, merge

R1, R2 = 41978e3, 42178e3


def test_paper_geometry():
    V = relative_speed(R1, R2)
    assert V == pytest.approx(7.3, abs=0.02)
    D = collection_span(R2 - R1, 5.0)
    assert D == pytest.approx(35e3, rel=0.001)
    L = subaperture_length(1.55e-6, R2 - R1, 0.05)
    assert L == pytest.approx(3.1, rel=1e-9)
    assert n_subimages(D, L) == pytest.approx(11290, abs=5)
    assert resolution_vs_squint(1.55e-6, R2 - R1, L, 0.0) == pytest.approx(0.05)
    th = max_squint_for(1.1)
    assert resolution_vs_squint(1.55e-6, R2 - R1, L, th) == pytest.approx(0.055)
    # the true two-orbit motion bends away from the straight line: differential gravity
    err = straight_line_error(R1, R2, 5.0)
    a = 3.986004418e14 * (1 / R1 ** 2 - 1 / R2 ** 2)
    assert err["max_range_difference_m"] == pytest.approx(0.5 * a * (err["collection_time_s"] / 2) ** 2, rel=0.05)


def test_bad_geometry():
    with pytest.raises(ScenarioError, match="squint_max_deg"):
        collection_span(2e5, 95)
    with pytest.raises(ScenarioError, match="longer than the collection"):
        n_subimages(10.0, 20.0)
    with pytest.raises(ScenarioError, match="R1 < R2"):
        relative_speed(R2, R1)


@pytest.mark.parametrize("squint", [-5.0, 0.0, 5.0, 10.0])
def test_resolution_against_squint_follows_eq12(squint):
    sc = parse_scenario(merge(GEO, platform__squint_deg=squint, platform__real_aperture=0.05,
                              processing={"algorithm": "bp", "grid": {"nx": 96, "ny": 96, "dx": 0.03, "dy": 0.03}}))
    raw = simulate(sc)
    m = measure(focus(raw, sc.processing))
    L = raw.sizes["slow_time"] * sc.platform.speed / sc.waveform.prf
    assert m["irw_azimuth_m"] == pytest.approx(0.886 * resolution_vs_squint(1.55e-6, 2e5, L, squint), rel=0.05)


def _geo_scene(ns):
    # a 5 cm telescope (15 m footprint) illuminates the 0.8 m target uniformly; with the 19 cm one
    # the two-way beam falls to 0.78 in intensity across it, a pattern common to every sub-image
    return parse_scenario(merge(GEO, platform__real_aperture=0.05, scene={"extended": {"kind": "pattern", "pattern": "uniform", "extent": [0.8, 0.8],
                                                         "spacing": 0.015, "speckle": True}},
                                receiver={"adc_rate": 12e6, "noise": {"enabled": True, "signal_photons": ns}},
                                processing={"algorithm": "bp", "grid": {"nx": 64, "ny": 64, "dx": 0.03, "dy": 0.03}}))


def test_stacking_gain_is_sqrt_p():
    """N_s = 0.5 (eta = 1): single-look SNR 0.33 (eq 15); 16 sub-apertures over +-5 deg give sqrt(16)."""
    sc = _geo_scene(0.5)
    clean = np.abs(subimage(sc, 0.0, 0, noise=False)) ** 2
    mask = np.zeros(clean.shape, bool)
    mask[20:44, 20:44] = True  # inside the 0.8 m target
    single = np.abs(subimage(sc, 0.0, 1)) ** 2
    snr1 = stack_snr(single, clean, mask)
    assert snr1 == pytest.approx(sc.receiver.noise.snr_theory, rel=0.15)
    stacked, _ = stack(sc, 16, 5.0)
    clean_stack, _ = stack(sc, 16, 5.0, noise=False)
    snr16 = stack_snr(stacked, clean_stack, mask)
    assert snr16 / snr1 == pytest.approx(4.0, rel=0.10)


def test_dask_stack_checkpoint_and_resume(tmp_path):
    """A real two-worker LocalCluster; a run killed after 2 of 6 sub-images resumes and computes
    only the remaining 4; the result equals the sequential stack."""
    from salkit.systems.spaceborne import run_stack
    sc = parse_scenario(merge(_geo_scene(5.0).model_dump(mode="json"),
                              processing={"algorithm": "bp", "grid": {"nx": 32, "ny": 32, "dx": 0.04, "dy": 0.04}}))
    store = tmp_path / "stack.zarr"
    from salkit.systems.spaceborne import squint_of
    squints = [squint_of(i, 6, 5.0) for i in range(6)]
    with pytest.raises(KeyboardInterrupt):
        run_stack(sc, squints, store, workers=2, stop_after=2)
    stacked, computed = run_stack(sc, squints, store, workers=2)
    assert computed == 4
    seq, _ = stack(sc, 6, 5.0)
    np.testing.assert_allclose(stacked, seq, rtol=1e-4, atol=1e-6 * seq.max())


def test_unreachable_scheduler_fails_fast(tmp_path):
    import time
    from salkit.errors import SalkitError
    from salkit.systems.spaceborne import run_stack
    t0 = time.time()
    with pytest.raises(SalkitError, match="no Dask scheduler answers"):
        run_stack(_geo_scene(5.0), [0.0, 1.0], tmp_path / "s.zarr", scheduler="tcp://127.0.0.1:9")
    assert time.time() - t0 < 15
    assert not (tmp_path / "s.zarr").exists()


def test_spaceborne_experiment_outputs(tmp_path):
    import json

    import xarray as xr

    from salkit.params import load_scenario
    from salkit.report import run_scenario as run_experiment
    from ..conftest import EXAMPLES
    sc = load_scenario(EXAMPLES / "spaceborne_geo.yaml", ["stack.max_subimages=6",
                                                          "processing.grid={nx: 64, ny: 48, dx: 0.08, dy: 0.08}",
                                                          "waveform.bandwidth=1.5e9", "experiment.resolution=0.1"])
    m = run_experiment(sc, tmp_path)
    for f in ("truth.nc", "image_single.nc", "image_stack.nc", "metrics.json", "report.html", "subimages.png",
              "stack.png", "snr_vs_p.png", "scenario.yaml"):
        assert (tmp_path / f).is_file(), f
    for f in ("truth.nc", "image_single.nc", "image_stack.nc"):
        ds = xr.open_dataset(tmp_path / f)
        assert ds["image"].dims == ("azimuth", "range") and np.iscomplexobj(ds["image"].values)
    saved = json.loads((tmp_path / "metrics.json").read_text())
    for k in ("snr_single", "snr_single_theory", "snr_stack", "stack_count"):
        assert k in saved
    assert saved["stack_count"] == 6 and saved["subimages_in_collection"] > 5000
    assert m["snr_stack"] > m["snr_single"]


def test_corrected_subimages_match_across_squint():
    """High SNR, smooth (speckle-free) target: the geometrically corrected sub-images at -5, 0 and
    +5 deg agree (normalised correlation of the magnitudes >= 0.95)."""
    sc = parse_scenario(merge(GEO, platform__real_aperture=0.05, scene={"extended": {
        "kind": "pattern", "pattern": "satellite", "extent": [2.0, 1.5], "spacing": 0.02, "speckle": False}},
        processing={"algorithm": "bp", "grid": {"nx": 64, "ny": 48, "dx": 0.04, "dy": 0.04}}))
    ims = {q: np.abs(subimage(sc, q, 0, noise=False)) for q in (-5.0, 0.0, 5.0)}
    for q in (-5.0, 5.0):
        a, b = ims[q].ravel(), ims[0.0].ravel()
        corr = np.dot(a - a.mean(), b - b.mean()) / (np.std(a) * np.std(b) * a.size)
        assert corr >= 0.95, (q, corr)


def test_single_subimage_snr_within_10_percent():
    """N_s = 0.5, eta = 1 (eq 15: 1/3): over four independent sub-images of a uniform target."""
    sc = _geo_scene(0.5)
    mask = np.zeros((64, 64), bool)
    mask[20:44, 20:44] = True
    vals = []
    for i in range(4):
        q = 0.01 * i  # different aspects: independent speckle
        clean = np.abs(subimage(sc, q, 100 + i, noise=False)) ** 2
        noisy = np.abs(subimage(sc, q, 100 + i)) ** 2
        vals.append(stack_snr(noisy, clean, mask))
    assert np.mean(vals) == pytest.approx(sc.receiver.noise.snr_theory, rel=0.10)


def test_coherent_stacking_with_phase_alignment():
    """Four adjacent sub-apertures of a point target added coherently form a 4x longer aperture:
    along-track resolution 4x finer. With random phase drifts between sub-apertures the aligned sum
    recovers it; the unaligned sum does not."""
    from salkit.geometry.orbit import subaperture_length
    from salkit.metrics import analyse_point
    from salkit.systems.spaceborne import coherent_stack, nearest_squints
    sc = parse_scenario(merge(GEO, processing={"algorithm": "bp", "grid": {"nx": 96, "ny": 64, "dx": 0.008,
                                                                          "dy": 0.04}}))
    L = sc.platform.aperture_length
    squints = nearest_squints(4, L * 1.0005, 2e5)  # consecutive, touching sub-apertures
    ims = [subimage(sc, q, i, noise=False) for i, q in enumerate(squints)]
    g = sc.processing.grid
    az = (np.arange(g.nx) - g.nx // 2) * g.dx
    rg = (np.arange(g.ny) - g.ny // 2) * g.dy
    res = 1.55e-6 * 2e5 / (2 * L)
    single = analyse_point(ims[0], az, rg, res, 0.05)["irw_azimuth_m"]
    drift = np.exp(1j * np.random.default_rng(0).uniform(-np.pi, np.pi, 4))
    aligned, offs = coherent_stack([im * d for im, d in zip(ims, drift)])
    peak1 = analyse_point(ims[0], az, rg, res, 0.05)["peak_amplitude"]
    ma = analyse_point(aligned, az, rg, res / 4, 0.05)
    assert ma["irw_azimuth_m"] == pytest.approx(single / 4, rel=0.10)
    assert ma["peak_amplitude"] == pytest.approx(4 * peak1, rel=0.05)  # the full coherent gain
    # without alignment random drifts lose gain: E|sum of 4 unit phasors| / 4 is about 0.5
    lost = []
    for seed in range(5):
        d = np.exp(1j * np.random.default_rng(seed).uniform(-np.pi, np.pi, 4))
        plain, _ = coherent_stack([im * x for im, x in zip(ims, d)], align=False)
        lost.append(np.abs(plain).max() / np.abs(aligned).max())
    assert np.mean(lost) < 0.75
