"""The pages of a run: the Files section names every file with its size and what it holds, the
metrics carry units, datasets describe themselves."""
import numpy as np
import xarray as xr

from salkit.report.pages import describe_dataset, file_rows, human_size, metric_rows
from salkit.systems.result import RunResult


def test_file_rows_describe_every_file(tmp_path):
    ds = xr.Dataset({"image": (("azimuth", "range"), np.zeros((3, 4), np.complex64))})
    result = RunResult("airborne", "n", "d", "a: 1\n", {}, datasets={"image.nc": ds},
                       tables={"t.csv": "a,b\n1,2\n"})
    (tmp_path / "image.nc").write_bytes(b"x" * 1500)
    (tmp_path / "t.csv").write_text("a,b\n1,2\n")
    (tmp_path / "scenario.yaml").write_text("a: 1\n")
    (tmp_path / "f.png").write_bytes(b"png")
    (tmp_path / "stack.zarr").mkdir()
    (tmp_path / "stack.zarr" / "chunk").write_bytes(b"y" * 2000)
    (tmp_path / ".hidden.tmp").write_text("partial")
    rows = {r["name"]: r for r in file_rows(tmp_path, result, {"f.png": "the image"})}
    assert set(rows) == {"image.nc", "t.csv", "scenario.yaml", "f.png", "stack.zarr", "report.html"}
    assert rows["image.nc"]["size"] == "1.5 kB" and "image (complex64, azimuth 3 x range 4)" in rows["image.nc"]["what"]
    assert rows["t.csv"]["what"] == "table (CSV): a, b"
    assert rows["f.png"]["what"] == "figure: the image"
    assert rows["stack.zarr"]["link"] == "stack.zarr/" and rows["stack.zarr"]["size"] == "2.0 kB"
    assert rows["report.html"]["size"] == "-"  # written after the page
    assert "resolved scenario" in rows["scenario.yaml"]["what"]


def test_metric_rows_carry_units():
    rows = {name: (value, unit) for name, value, unit in metric_rows({"irw_range_m": 0.0179, "pslr_range_db": -13.3})}
    assert rows["irw_range_m"][1] and rows["pslr_range_db"][1] == "dB"
    assert human_size(999) == "999 B"
    ds = xr.Dataset({f"v{i}": ("x", np.zeros(2)) for i in range(8)})
    assert describe_dataset(ds).endswith("and 2 more; coordinates in m and s, parameters as attributes")
