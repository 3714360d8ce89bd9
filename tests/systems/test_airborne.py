"""The foundation workflow: noise figures against the model."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.metrics import snr_against_truth
from salkit.params import parse_scenario

from ..conftest import SPOT, merge


def test_run_reports_noise_against_model(tmp_path):
    from salkit import tolerances as tol
    from salkit.report import run_scenario as run
    from ..conftest import STRIP
    sc = parse_scenario(merge(STRIP, scene={"points": [{"x": 0.2, "y": 0.0, "amplitude": 5.0}], "extended": {
        "kind": "pattern", "pattern": "uniform", "extent": [1.0, 0.5], "spacing": 0.007, "speckle": True}},
        receiver={"adc_rate": 6e6, "noise": {"enabled": True, "signal_photons": 2.0, "quantum_efficiency": 0.8}}))
    m = run(sc, tmp_path)
    assert m["noise_power"] == pytest.approx(m["noise_power_theory"], rel=0.1)
    assert m["cnr_peak"] == pytest.approx(m["cnr_peak_theory"], rel=tol.CNR_RATIO)
    assert m["image_snr"] == pytest.approx(m["image_snr_theory"], rel=tol.SNR_RATIO)
