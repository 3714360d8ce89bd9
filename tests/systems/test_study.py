"""Workflows as sweep points: range IRW against bandwidth on theory at every point through
``salkit.sweep``; a point that fails is recorded with its reason, not raised; the systems' loops
run through the engine."""
import numpy as np
import pytest

import salkit
from salkit.params import parse_scenario
from salkit.studies.engine import summary
from salkit.systems.study import run_point

from ..conftest import SPOT

C = 299792458.0


def test_range_irw_against_bandwidth_on_theory():
    ds = salkit.sweep(parse_scenario(SPOT), {"waveform.bandwidth": "lin:2.5e9:7.5e9:5"}, metrics=["irw_range_m"])
    irw = ds["irw_range_m"].isel(realisation=0).values
    th = ds["irw_range_theory_m"].isel(realisation=0).values
    B = ds["waveform.bandwidth"].values
    assert (ds["status"].values == "ok").all()
    assert np.all(np.abs(irw / th - 1) < 0.02), irw / th
    assert np.ptp(th * B) / np.mean(th * B) < 1e-3  # the theory falls as 1/B ...
    assert np.mean(th * B) == pytest.approx(0.886 * C / 2, rel=0.03)  # ... as 0.886 c / 2B
    assert ds["waveform.bandwidth"].attrs["units"] == "Hz" and ds["irw_range_m"].attrs["units"] == "m"
    assert summary(ds)["irw_range_m_over_theory_max_deviation"] < 0.02




def test_a_point_that_fails_is_recorded_not_raised():
    rec = run_point({**SPOT, "waveform": {**SPOT["waveform"], "prf": -1.0}})
    assert rec["status"].startswith("failed: ") and "waveform.prf" in rec["status"] and rec["metrics"] == {}
