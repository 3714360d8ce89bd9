"""Photon-limited heterodyne noise: image CNR and speckle SNR against seed 001 eqs 14-15."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.metrics import snr_against_truth
from salkit.params import parse_scenario

from ..conftest import SPOT, merge


def _noisy_pair(ns, model="gaussian", seed=0, extended=None, points=None):
    scene = {"points": points or []}
    if extended:
        scene["extended"] = extended
    sc = parse_scenario(merge(SPOT, seed=seed, scene=scene, receiver={"adc_rate": 20e6, "noise": {
        "enabled": True, "model": model, "signal_photons": ns, "lo_photons": 1e8,
        "quantum_efficiency": 0.8, "mixing_efficiency": 0.9}},
        processing={"algorithm": "bp", "grid": {"nx": 96, "ny": 96, "dx": 0.015, "dy": 0.015}}))
    noisy = focus(simulate(sc), sc.processing)["image"].values
    clean = focus(simulate(sc, noise=False), sc.processing)["image"].values
    return sc, noisy, clean


@pytest.mark.parametrize("model", ["gaussian", "poisson"])
def test_point_target_cnr_is_eta_ns(model):
    """Peak power over noise power per pixel = eta_d eta_mix N_s for a unit point at beam centre."""
    ns = 20.0
    ratios = []
    for seed in range(4):
        sc, noisy, clean = _noisy_pair(ns, model, seed, points=[{"x": 0.0, "y": 0.0}])
        noise = noisy - clean
        ratios.append(np.abs(clean).max() ** 2 / np.mean(np.abs(noise) ** 2))
    assert np.mean(ratios) == pytest.approx(sc.receiver.noise.cnr, rel=0.05)


@pytest.mark.parametrize("ns", [0.5, 2.0, 20.0])
def test_speckle_image_snr_follows_eq14(ns):
    """Over an ensemble of speckle and noise realisations: SNR = eta N_s / (1 + eta N_s) within 10 %."""
    ext = {"kind": "pattern", "pattern": "uniform", "extent": [1.0, 1.0], "spacing": 0.007, "speckle": True}
    snr = []
    for seed in range(3):
        sc, noisy, clean = _noisy_pair(ns, seed=seed, extended=ext)
        core = np.zeros(noisy.shape, bool)
        core[24:72, 24:72] = True  # away from the scene edge
        snr.append(snr_against_truth(noisy, clean, core))
    theory = sc.receiver.noise.snr_theory
    assert np.mean(snr) == pytest.approx(theory, rel=0.10)


@pytest.mark.parametrize("alg", ["omegak", "bp"])
def test_stripmap_cnr_includes_beam_equalisation(alg):
    """Stripmap equalises the two-way beam over the 3 dB aperture: CNR = eta N_s / mean(1/g^2)."""
    from salkit.geometry.collection import equalisation_efficiency
    from ..conftest import STRIP
    ratios = []
    for seed in range(3):
        sc = parse_scenario(merge(STRIP, seed=seed, processing={"algorithm": alg, "grid": STRIP["processing"]["grid"]},
                                  scene={"points": [{"x": 0.0, "y": 0.0}]},
                                  receiver={"adc_rate": 6e6, "noise": {"enabled": True, "signal_photons": 20.0}}))
        noisy = focus(simulate(sc), sc.processing)["image"].values
        clean = focus(simulate(sc, noise=False), sc.processing)["image"].values
        core = (slice(64 - 15, 64 + 15), slice(None))  # rows with the whole aperture
        ratios.append(np.abs(clean).max() ** 2 / np.mean(np.abs(noisy - clean)[core] ** 2))
    eff = equalisation_efficiency(sc)
    assert 0.75 < eff < 0.85
    assert np.mean(ratios) == pytest.approx(sc.receiver.noise.cnr * eff, rel=0.08)
