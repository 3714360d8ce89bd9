"""The shipped sweeps (examples/sweeps/) reproduce seed results as studies, their physics checked:
range IRW against bandwidth on 0.886 c / 2B at every point; the single sub-image SNR of a uniform
speckled area against the photon count on eq 15; the turbulence point target at a class's Cn2
equal, realisation 0, to the seed 004 experiment's."""
import numpy as np
import pytest

from salkit.params import load_scenario
from salkit.systems.study import sweep
from salkit.studies.spec import read_sweep_file
from salkit.systems.turbulence import point_images

from ..conftest import EXAMPLES

SWEEPS = EXAMPLES / "sweeps"


def _load(name, **changes):
    sf = read_sweep_file(SWEEPS / f"{name}.yaml")
    vary = dict(v.split("=", 1) for v in sf.vary)
    vary.update(changes.pop("vary", {}))
    return load_scenario(sf.scenario, list(sf.sets)), vary, sf


def test_every_shipped_sweep_reads():
    files = sorted(SWEEPS.glob("*.yaml"))
    assert len(files) >= 3
    for f in files:
        sf = read_sweep_file(f)
        assert sf.scenario.is_file() and sf.vary and sf.description


def test_irw_against_bandwidth_within_2pct_at_every_point():
    sc, vary, sf = _load("irw_vs_bandwidth")
    ds = sweep(sc, vary, metrics=sf.metrics)
    ratio = (ds["irw_range_m"] / ds["irw_range_theory_m"]).values
    assert ds.sizes["waveform.bandwidth"] == 6 and np.all(np.abs(ratio - 1) < 0.02), ratio


def test_single_subimage_snr_against_photons_on_eq15():
    """Eq 15, SNR = c / (1 + c) with c the cell's carrier-to-noise ratio eta N_s (times the two-way
    beam's mean weight over the area, here 0.9-1): measured within 5 % of it at every count."""
    sc, vary, sf = _load("geo_snr_vs_photons")
    ns = np.array([0.3, 3.0, 30.0])
    ds = sweep(sc, {"receiver.noise.signal_photons": "0.3,3,30"}, realisations=2,
               metrics=list(sf.metrics) + ["image_snr_mean_cell_cnr"])
    c = ds["image_snr_mean_cell_cnr"].isel(realisation=0).values
    weight = c / (sc.receiver.noise.quantum_efficiency * ns)
    assert np.all((weight > 0.9) & (weight <= 1.0)) and np.ptp(weight) / weight.mean() < 0.01, weight
    snr = ds["image_snr"].mean("realisation").values
    np.testing.assert_allclose(snr, c / (1 + c), rtol=0.05)
    np.testing.assert_allclose(ds["image_snr_theory"].isel(realisation=0).values, c / (1 + c), rtol=1e-9)


def test_turbulence_class_point_equals_the_experiment():
    sc, vary, sf = _load("turbulence_cn2")
    base = load_scenario(EXAMPLES / "turbulence_pga.yaml")
    cn2 = base.experiment.classes["medium"]
    ds = sweep(sc, {"atmosphere.cn2": [cn2], "processing.autofocus": ["none", "pga"]}, metrics=sf.metrics)
    m, _, _ = point_images(base, "medium", cn2)
    at = ds.isel({"atmosphere.cn2": 0, "realisation": 0})
    for k in ("peak_amplitude", "irw_azimuth_m", "entropy"):
        assert float(at[k].sel({"processing.autofocus": "none"})) == pytest.approx(m[f"medium_{k}"], rel=1e-9), k
        assert float(at[k].sel({"processing.autofocus": "pga"})) == pytest.approx(m[f"medium_pga_{k}"], rel=1e-9), k


def test_strehl_at_target_against_r0_expectation():
    """The shipped turbulence study's r0-based theory: over 24 realisations of the screens the mean
    intensity at the target (before autofocus) over the turbulence-free one equals the synthetic
    aperture's long-exposure Strehl ratio within 3 standard errors, at the weak and medium classes;
    a sweep may start at Cn2 = 0 (the turbulence-free path, where these metrics do not exist)."""
    sc, _, _ = _load("turbulence_cn2")
    kw = {"metrics": ["strehl_at_target", "peak_ratio"]}
    ds = sweep(sc, {"atmosphere.cn2": [0.0, 1e-15], "processing.autofocus": ["none"]}, realisations=2, **kw)
    assert (ds["status"].values == "ok").all()
    for name in ("strehl_at_target", "strehl_at_target_theory"):  # no turbulence, no turbulence metrics
        v = ds[name].isel({"processing.autofocus": 0})
        assert np.isnan(v.sel({"atmosphere.cn2": 0.0})).all() and np.isfinite(v.sel({"atmosphere.cn2": 1e-15})).all()
    # the ensemble: the turbulence-free path left out (its 24 realisations would be one run 24 times)
    ds = sweep(sc, {"atmosphere.cn2": [1e-15, 1e-14], "processing.autofocus": ["none"]}, realisations=24, **kw)
    s = ds["strehl_at_target"].isel({"processing.autofocus": 0})
    th = ds["strehl_at_target_theory"].isel({"processing.autofocus": 0})
    assert (ds["status"].values == "ok").all()
    for cn2 in (1e-15, 1e-14):
        v = s.sel({"atmosphere.cn2": cn2}).values
        t = float(th.sel({"atmosphere.cn2": cn2}).values[0])
        se = v.std(ddof=1) / np.sqrt(v.size)
        assert abs(v.mean() - t) < 3 * se, (cn2, v.mean(), t, se)
        assert t < (0.2 if cn2 == 1e-15 else 0.06)  # L = 0.5 m spans many r0: the theory is far from 1


def test_linewidth_study_follows_the_expected_peak_loss():
    """The linewidth study (5 km, undelayed LO), 8 realisations: the mean intensity at the target
    over the coherent laser's within 10 % of exp(-2 pi linewidth tau) where that is above 0.1, and
    within 3 standard errors of its ensemble mean (the pedestal included) everywhere."""
    sc, vary, sf = _load("linewidth")
    ds = sweep(sc, vary, metrics=sf.metrics, realisations=8)
    m, th = ds["peak_power_loss"].values, ds["peak_power_loss_theory"].values
    mean, se = m.mean(axis=1), m.std(axis=1, ddof=1) / np.sqrt(m.shape[1])
    strong = th[:, 0] > 0.1
    assert np.all(np.abs(mean[strong] / th[strong, 0] - 1) < 0.10), mean / th[:, 0]
    assert np.all(np.abs(mean - th[:, 0]) <= 3 * se + 1e-12), (mean, th[:, 0], se)
