"""The seed 002 experiment end to end (reduced sweeps)."""
import json

import numpy as np
import pytest
import xarray as xr
import yaml

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


def test_tables_are_sweeps_through_the_study_engine(result):
    """Tables 2 and 3 come from the study engine: table2.nc / table3.nc are sweeps whose cells equal
    the CSV grids; the zero-length reference cell (d_r = d_rlo) is an invalid point, named."""
    from salkit.io import describe, open_dataset
    from salkit.systems.chirp import table_point
    out, m = result
    t2 = open_dataset(out / "table2.nc")
    assert t2.attrs["salkit_kind"] == "sweep" and describe(out / "table2.nc")["kind"] == "sweep"
    assert t2["paper_irw_m"].dims == ("experiment.d_rlo", "experiment.d_r", "realisation")
    assert (t2["status"].values == "ok").all()  # no d_r = d_rlo cell in this reduced table
    t3 = open_dataset(out / "table3.nc")
    grid = np.genfromtxt(out / "table3_resample_irw_m.csv", delimiter=",", skip_header=1)[:, 1:]
    np.testing.assert_allclose(grid, t3["resample_irw_m"].values[..., 0], rtol=1e-3)  # the CSV keeps 4 digits
    # one cell again, by hand: the point function on that cell's scenario
    cell = yaml.safe_load(t3.attrs["scenario"])
    cell["experiment"].update(r1=300.0, r2=10.0)
    rec = table_point(cell)
    assert rec["metrics"]["resample_irw_m"] == t3["resample_irw_m"].sel(
        {"experiment.r2": 10.0, "experiment.r1": 300.0}).item()


def test_zero_length_reference_cell_is_invalid(tmp_path):
    from salkit.systems.chirp import table
    sc = load_scenario(EXAMPLES / "nonlinear_chirp.yaml", ["experiment.sweep_d_r=[0.5, 0.8]",
                                                           "experiment.sweep_d_rlo=[0.5]"])
    ds, grids = table(sc, "table2")
    assert ds["status"].values[0, 0].startswith("invalid: ") and "zero-length reference" in ds["status"].values[0, 0]
    assert ds["status"].values[0, 1] == "ok"
    assert np.isnan(grids["irw"]["ideal"][0, 0]) and np.isfinite(grids["irw"]["ideal"][0, 1])
