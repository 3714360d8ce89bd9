"""Stacks of sub-images: sqrt(P) gain, Dask checkpoint and resume, coherent stacking and its resolution."""

import numpy as np
import pytest

from salkit.params import parse_scenario
from salkit.metrics import stack_snr
from salkit.stack import stack, subimage

from ..conftest import GEO, merge


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
    from salkit.stack import run_stack
    sc = parse_scenario(merge(_geo_scene(5.0).model_dump(mode="json"),
                              processing={"algorithm": "bp", "grid": {"nx": 32, "ny": 32, "dx": 0.04, "dy": 0.04}}))
    store = tmp_path / "stack.zarr"
    from salkit.stack import squint_of
    squints = [squint_of(i, 6, 5.0) for i in range(6)]
    with pytest.raises(KeyboardInterrupt):
        run_stack(sc, squints, store, workers=2, stop_after=2)
    stacked, computed = run_stack(sc, squints, store, workers=2)
    assert computed == 4
    seq, _ = stack(sc, 6, 5.0)
    np.testing.assert_allclose(stacked, seq, rtol=1e-4, atol=1e-6 * seq.max())


def test_stack_in_this_process_checkpoints_resumes_and_equals_the_sequential_stack(tmp_path):
    """workers=0: no cluster; a run killed after 2 of 6 sub-images resumes and computes only the
    remaining 4, and the stack equals the sequential one (the same seeds, the same kernels). A
    worker count below 0, or 0 beside a scheduler, is refused before anything is written."""
    from salkit.stack import run_stack, squint_of
    sc = parse_scenario(merge(_geo_scene(5.0).model_dump(mode="json"),
                              processing={"algorithm": "bp", "grid": {"nx": 32, "ny": 32, "dx": 0.04, "dy": 0.04}}))
    store = tmp_path / "stack.zarr"
    squints = [squint_of(i, 6, 5.0) for i in range(6)]
    seen = []
    with pytest.raises(KeyboardInterrupt):
        run_stack(sc, squints, store, workers=0, stop_after=2, progress=lambda d, n: seen.append((d, n)))
    assert seen == [(1, 6), (2, 6)]
    stacked, computed = run_stack(sc, squints, store, workers=0)
    assert computed == 4
    seq, _ = stack(sc, 6, 5.0)
    np.testing.assert_allclose(stacked, seq, rtol=1e-6, atol=1e-9 * seq.max())
    for workers, scheduler in ((-1, None), (0, "tcp://127.0.0.1:9")):
        with pytest.raises(ValueError, match=f"workers = {workers}"):
            run_stack(sc, squints, tmp_path / "no.zarr", workers=workers, scheduler=scheduler)
    assert not (tmp_path / "no.zarr").exists()


def test_unreachable_scheduler_fails_fast(tmp_path):
    import time
    from salkit.errors import SalkitError
    from salkit.stack import run_stack
    t0 = time.time()
    with pytest.raises(SalkitError, match="no Dask scheduler answers"):
        run_stack(_geo_scene(5.0), [0.0, 1.0], tmp_path / "s.zarr", scheduler="tcp://127.0.0.1:9")
    assert time.time() - t0 < 15
    assert not (tmp_path / "s.zarr").exists()


def test_coherent_stacking_with_phase_alignment():
    """Four adjacent sub-apertures of a point target added coherently form a 4x longer aperture:
    along-track resolution 4x finer. With random phase drifts between sub-apertures the aligned sum
    recovers it; the unaligned sum does not."""
    from salkit.metrics import analyse_point
    from salkit.stack import coherent_stack, nearest_squints
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


def test_coherent_resolution_narrows_as_one_over_p():
    """P contiguous sub-apertures summed coherently image with the combined aperture: IRW =
    0.886 lambda L0 / (2 P L_sa), within 1 % for P = 1, 2, 4, 8 (noise-free point target)."""
    from salkit.params import load_scenario
    from salkit.stack import coherent_resolution, geo_base
    from ..conftest import EXAMPLES
    base = geo_base(load_scenario(EXAMPLES / "spaceborne_geo.yaml"))
    r = coherent_resolution(base, [1, 2, 4, 8])
    for irw, th in zip(r["irw_m"], r["irw_theory_m"]):
        assert irw == pytest.approx(th, rel=0.01)
