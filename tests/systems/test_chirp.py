"""The seed 002 experiment end to end (reduced sweeps)."""
import json

import numpy as np
import pytest
import xarray as xr

from salkit.params import load_scenario
from salkit.report import run_scenario as run_experiment

from ..conftest import EXAMPLES


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("seed002")
    sc = load_scenario(EXAMPLES / "nonlinear_chirp.yaml", [
        "experiment.sweep_d_r=[0.6, 1.0, 1.9]", "experiment.sweep_d_rlo=[0.5, 1.1]",
        "experiment.sweep_r1=[10, 50, 300]", "experiment.sweep_r2=[10, 50, 300]"])
    return out, run_experiment(sc, out)


def test_outputs_and_profiles(result):
    out, m = result
    ds = xr.open_dataset(out / "profiles.nc")
    assert set(ds.data_vars) == {"none", "paper", "deskew", "resample", "ideal"}
    assert ds["resample"].dims == ("point", "range") and list(ds["point"].values) == ["A", "B", "C"]
    assert ds["range"].attrs["units"] == "m" and np.iscomplexobj(ds["ideal"].values)
    for f in ("table1.csv", "table2_paper.csv", "table3_resample.csv", "table2.png", "table3.png", "report.html"):
        assert (out / f).is_file(), f
    assert all(isinstance(v, (int, float)) for v in json.loads((out / "metrics.json").read_text()).values())


def test_corrections_against_ideal_at_r50(result):
    _, m = result
    for p in ("A", "B", "C"):
        ideal = m[f"{p}_ideal_irw_m"]
        assert m[f"{p}_none_irw_m"] > 5 * ideal  # uncorrected: range image destroyed
        assert m[f"{p}_resample_irw_m"] == pytest.approx(ideal, rel=0.05)
        assert abs(m[f"{p}_resample_pslr_db"] - m[f"{p}_ideal_pslr_db"]) < 1.0
        assert m[f"{p}_paper_irw_m"] == pytest.approx(ideal, rel=0.05)  # matched to its own delay
    # matched to A's delay, the paper's method leaves B and C (7 m nearer) blurred
    assert m["B_paper_matched_A_irw_m"] > 2 * m["B_ideal_irw_m"]
