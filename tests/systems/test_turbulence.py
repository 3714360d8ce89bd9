"""The seed 004 experiment end to end: turbulence classes, PFA, PGA (issue criteria)."""
import json

import numpy as np
import pytest
import xarray as xr

from salkit.params import load_scenario
from salkit.report import run_scenario as run

from ..conftest import EXAMPLES


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("seed004")
    sc = load_scenario(EXAMPLES / "turbulence_pga.yaml", ["experiment.ensemble_screens=100"])
    m = run(sc, out)
    return out, m


def test_outputs(result):
    out, m = result
    for c in ("none", "weak", "medium", "strong"):
        for suffix in ("", "_pga"):
            ds = xr.open_dataset(out / f"image_{c}{suffix}.nc")
            assert ds["image"].dims == ("azimuth", "range") and np.iscomplexobj(ds["image"].values)
    for f in ("screens.png", "structure_function.png", "ipr_classes.png", "i_target.png", "pga_iterations.png",
              "report.html", "metrics.json", "scenario.yaml"):
        assert (out / f).is_file(), f
    saved = json.loads((out / "metrics.json").read_text())
    assert "medium_pga_irw_azimuth_m" in saved and all(isinstance(v, (int, float)) for v in saved.values())


def test_pga_restores_weak_and_medium_and_improves_strong(result):
    """Turbulence degrades the image: the medium class's peak falls below 0.7 of the
    turbulence-free one and its entropy rises by more than 1 (over 30 other screen seeds: peak
    0.33-0.55, entropy +1.95 to +2.59). Its azimuth IRW is no such measure: over the same seeds
    it ranged from 0.85 to 2.2 times the free one, below 1.3 times for 21 of the 30 (the energy
    leaves the main lobe without always widening it). PGA then brings the weak and medium IRWs
    within 10 % of the free one (over those seeds: weak always, to 0.2 %; medium in 29 of 30,
    the other at 0.59)."""
    _, m = result
    ref = m["none_irw_azimuth_m"]
    assert ref == pytest.approx(m["none_irw_azimuth_theory_m"], rel=0.03)
    assert m["medium_peak_amplitude"] < 0.7 * m["none_peak_amplitude"]
    assert m["medium_entropy"] > m["none_entropy"] + 1.0
    for c in ("weak", "medium"):
        assert m[f"{c}_pga_irw_azimuth_m"] == pytest.approx(ref, rel=0.10)
    assert m["strong_pga_entropy"] < m["strong_entropy"] - 0.5  # measurably better
    assert m["none_pga_entropy"] <= m["none_entropy"] + 1e-6  # left alone (complex64 storage rounding)


def test_more_iterations_never_worse(result):
    _, m = result
    e = [m[f"strong_i_pga{n}_entropy"] for n in (5, 10, 20)]
    assert e[1] <= e[0] + 1e-9 and e[2] <= e[1] + 1e-9
    assert m["strong_i_pga5_entropy"] <= m["strong_i_entropy"] + 1e-9


def test_screens_within_3_percent(result):
    _, m = result
    assert m["screens_sf_max_deviation_2px_to_N4"] < 0.05  # 100 screens: ~2 % standard error at N/4


@pytest.fixture(scope="module")
def wave_result(tmp_path_factory):
    out = tmp_path_factory.mktemp("seed004wo")
    sc = load_scenario(EXAMPLES / "turbulence_pga.yaml",
                       ["experiment.ensemble_screens=100", "atmosphere.model=wave_optics",
                        'experiment.classes={"none": 0.0, "weak": 1.0e-15}', "experiment.pga_iterations=[5]"])
    m = run(sc, out)
    return out, m


def test_wave_optics_side_by_side(wave_result):
    """atmosphere.model = wave_optics runs the point target through the same screens with both
    models: the report's side-by-side table and figure, the wave-optics images, and the metrics of
    both. Without turbulence the two are one simulation; through the weak class's screens (Rytov
    0.41) wave optics makes another image than the phase-only model, which keeps |g| = 1 (their
    difference carries more than a tenth of the image's energy: -3.3 to +3.0 dB over 7 screen
    seeds), and PGA, which corrects phase only, brings the azimuth IRW within 30 % of the
    turbulence-free one. Over 28 other screen seeds (0.21.0's draws) that IRW was 0.92-1.26 times
    the free one (mean 1.05, sd 0.09; beyond 10 % for 6 of them), 0.79 on this seed, where the
    phase-only model's PGA restores it to 0.2 %: the amplitude scintillation left behind widens or
    narrows the main lobe. (The two
    models' peak ratios differed by less than 0.02 for 2 of 12 seeds: no test of scintillation.)"""
    out, m = wave_result
    html = (out / "report.html").read_text()
    assert "Phase screens against wave optics" in html and "ipr_classes_wave_optics.png" in html
    assert (out / "ipr_classes_wave_optics.png").is_file()
    for suffix in ("", "_pga"):
        assert (out / f"image_weak_wave_optics{suffix}.nc").is_file()
    assert m["none_wo_irw_azimuth_m"] == m["none_irw_azimuth_m"]
    assert m["weak_rytov_spherical"] == pytest.approx(0.41, rel=0.01)
    assert m["weak_wo_pga_irw_azimuth_m"] == pytest.approx(m["none_irw_azimuth_m"], rel=0.30)
    assert m["weak_pga_irw_azimuth_m"] == pytest.approx(m["none_irw_azimuth_m"], rel=0.02)
    po = xr.open_dataset(out / "image_weak.nc")["image"].values
    wo = xr.open_dataset(out / "image_weak_wave_optics.nc")["image"].values
    assert np.sum(np.abs(wo - po) ** 2) > 0.1 * np.sum(np.abs(po) ** 2)


def test_classes_run_as_a_sweep_of_cn2(result):
    """The class loop is a sweep of atmosphere.cn2 through the study engine: classes.nc holds each
    class's metrics against Cn2 (0: the turbulence-free path), equal to the class metrics."""
    from salkit.io import open_dataset
    out, m = result
    ds = open_dataset(out / "classes.nc")
    assert ds.attrs["salkit_kind"] == "sweep" and (ds["status"].values == "ok").all()
    assert list(ds["atmosphere.cn2"].values) == [0.0, 1e-15, 1e-14, 1e-13]
    for name, cn2 in (("none", 0.0), ("medium", 1e-14)):
        for k in ("peak_amplitude", "pga_irw_azimuth_m", "i_pga_entropy"):
            assert ds[f"class_{k}"].sel({"atmosphere.cn2": cn2}).item() == m[f"{name}_{k}"], (name, k)
