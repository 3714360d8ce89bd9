"""``salkit info`` on every shipped example, ``salkit examples``."""
import json

import pytest

from ..conftest import EXAMPLES
from .conftest import salkit


@pytest.mark.parametrize("name", sorted(p.stem for p in EXAMPLES.glob("*.yaml")))
def test_info_on_every_shipped_example(name):
    """`salkit info` works where `salkit run` does (an experiment checks its own sampling), and says
    the unit of every quantity it prints."""
    r = salkit("info", EXAMPLES / f"{name}.yaml", "--json")
    assert r.returncode == 0, r.stderr
    assert salkit("info", EXAMPLES / f"{name}.yaml").returncode == 0
    d = json.loads(r.stdout)
    assert d["name"] == name and d["units"]
    from salkit.units import NAMED
    for k, v in d.items():
        if k.endswith("_m") and k not in NAMED and isinstance(v, (int, float)):
            assert d["units"][k] == "m", k


def test_examples_listed():
    r = salkit("examples")
    assert r.returncode == 0
    for f in EXAMPLES.glob("*.yaml"):
        assert f.name in r.stdout


def test_info_prints_a_human_summary_and_verifies_every_chunk(tmp_path):
    """`salkit info FILE` says in a few lines what a file holds (kind, sizes, grid, frequencies,
    brightest sample) after reading every chunk against its checksum; `--json` gives the same to
    machines, flags as booleans; a file with a corrupted chunk exits 2 naming the file and the
    variable (it used to exit 0 without a word)."""
    import numpy as np
    from ..conftest import SPOT
    import yaml
    scen = tmp_path / "s.yaml"
    scen.write_text(yaml.safe_dump(SPOT))
    out = tmp_path / "run"
    assert salkit("run", scen, "--out", out).returncode == 0
    r = salkit("info", out / "image.nc")
    assert r.returncode == 0, r.stderr
    text = r.stdout
    assert "salkit image file" in text and "128 azimuth x 128 range complex64" in text
    assert "pixel 1.5 cm" in text and "brightest image sample" in text and "checksums: verified" in text
    assert "THz" in text and "GHz" in text and len(text.splitlines()) <= 12
    d = json.loads(salkit("info", out / "image.nc", "--json").stdout)
    assert d["checksums_verified"] is True and d["collection_time_nominal"] in (True, False)
    assert "collection_time_nominal" not in d["units"]  # a flag, not a time
    i, j = d["brightest_image_index"]
    assert abs(i - 64) <= 1 and abs(j - 64) <= 1  # the target at the grid's centre
    raw = out / "raw.nc"
    assert "salkit raw file" in salkit("info", raw).stdout
    # corrupt one byte pattern in the middle of the image's data
    bad = tmp_path / "bad.nc"
    data = bytearray((out / "image.nc").read_bytes())
    from salkit.io import open_dataset
    img = np.asarray(open_dataset(out / "image.nc")["image"].values)
    needle = img[60:61, :].tobytes()[:64]
    k = data.find(needle)
    assert k > 0
    data[k:k + 16] = bytes(16)
    bad.write_bytes(bytes(data))
    r = salkit("info", bad)
    assert r.returncode == 2 and str(bad) in r.stderr and "'image'" in r.stderr and "corrupt" in r.stderr


def test_info_on_an_outside_file_claims_no_checksum_it_does_not_hold(tmp_path):
    """An image written by plain xarray (contiguous, no fletcher32, no salkit attributes): `info`
    raised TypeError ('NoneType' object is not iterable) on its chunk sizes, and for other such files
    said "checksums: verified" and "salkit unknown file (format ?, written by salkit ?)". It now says
    the file is not salkit's and that it holds no checksums; `--json` says checksums_verified false
    and names the variables without one."""
    import numpy as np
    import xarray as xr
    p = tmp_path / "outside.nc"
    xr.Dataset({"image": (("azimuth", "range"), np.ones((16, 8), np.complex64))},
               coords={"azimuth": np.arange(16) * 0.01, "range": np.arange(8) * 0.01}).to_netcdf(p)
    r = salkit("info", p)
    assert r.returncode == 0, r.stderr
    assert "file not written by salkit" in r.stdout and "format ?" not in r.stdout
    assert "checksums: none in this file" in r.stdout and "checksums: verified" not in r.stdout
    d = json.loads(salkit("info", p, "--json").stdout)
    assert d["checksums_verified"] is False and d["checksums_missing"] == ["image", "azimuth", "range"]


def test_examples_copy_holds_everything_the_readme_runs(tmp_path):
    """`salkit examples --copy DIR` copies the sweep files too (they were left out), beside the
    scenarios they name, so `salkit sweep DIR/sweeps/X.yaml` finds its scenario."""
    from salkit.studies.spec import resolve_request
    r = salkit("examples", "--copy", tmp_path / "ex")
    assert r.returncode == 0, r.stderr
    shipped = sorted(p.relative_to(EXAMPLES).as_posix() for p in EXAMPLES.rglob("*.yaml"))
    copied = sorted(p.relative_to(tmp_path / "ex").as_posix() for p in (tmp_path / "ex").rglob("*.yaml"))
    assert copied == shipped and any(c.startswith("sweeps/") for c in copied)
    for f in (tmp_path / "ex" / "sweeps").glob("*.yaml"):
        assert resolve_request(f).description
    assert "sweeps/turbulence_cn2.yaml" in r.stdout


def test_info_describes_a_sweep_file_and_run_refuses_one_saying_what_it_is(tmp_path):
    """`salkit info` of a sweep file (and `salkit run` of one) said "sweep = 1: 'sweep' is not a field
    of the scenario (...) (and 10 more problems ...)". `info` now describes it: base scenario, axes,
    points and runs, every point checked; `run` and `simulate` say it is a sweep file."""
    f = EXAMPLES / "sweeps" / "irw_vs_bandwidth.yaml"
    r = salkit("info", f)
    assert r.returncode == 0, r.stderr
    assert "sweep file 'irw_vs_bandwidth' over" in r.stdout and "spotlight_points.yaml (sal)" in r.stdout
    assert "waveform.bandwidth: 6 values (lin): 1e+09, 2.3e+09" in r.stdout and "6 points x 1 realisation: 6 runs" in r.stdout
    d = json.loads(salkit("info", f, "--json").stdout)
    assert d["kind"] == "sweep" and d["points"] == 6 and d["axes"][0]["field"] == "waveform.bandwidth"
    for cmd in (["run", f, "--out", tmp_path / "o"], ["simulate", f, "--out", tmp_path / "r.nc"]):
        r = salkit(*cmd)
        assert r.returncode == 2 and "is a sweep file (sweep, scenario, vary), not a scenario: run it with salkit sweep" \
            in r.stderr
    assert not (tmp_path / "o").exists()
