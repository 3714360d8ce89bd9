"""The command line on outside data: convert, focus a CPHD, grid options, bad files exit 2."""

import pytest
from typer.testing import CliRunner

from salkit.cli.main import app
from salkit.io import write_dataset

runner = CliRunner()


@pytest.fixture(scope="module")
def raw_file(tmp_path_factory):
    from salkit import simulate
    from salkit.params import parse_scenario
    from ..conftest import SPOT
    d = tmp_path_factory.mktemp("cli")
    return write_dataset(simulate(parse_scenario(SPOT)), d / "raw.nc")


def test_convert_cphd_and_focus_it(tmp_path, raw_file):
    r = runner.invoke(app, ["convert", str(raw_file), str(tmp_path / "r.cphd")])  # where on the earth?
    assert r.exit_code == 2 and "--origin" in r.output and not (tmp_path / "r.cphd").exists()
    r = runner.invoke(app, ["convert", str(raw_file), str(tmp_path / "r.cphd"), "--origin", "48.1,11.6,520"])
    assert r.exit_code == 0, r.output
    assert "0 errors" in r.output
    r = runner.invoke(app, ["focus", str(tmp_path / "r.cphd"), "--out", str(tmp_path / "f"), "--algorithm", "pfa"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "f" / "image.nc").is_file()


def test_plane_alone_is_completed_with_a_message(tmp_path, raw_file):
    r = runner.invoke(app, ["focus", str(raw_file), "--out", str(tmp_path / "g"), "--plane", "ground"])
    assert r.exit_code == 0, r.output
    assert "--plane ground without --nx/--ny/--dx/--dy" in r.output
    from salkit.io import read_image
    assert read_image(tmp_path / "g" / "image.nc").attrs["plane"] == "ground"


@pytest.mark.parametrize("args,msg", [
    (["--nx", "64", "--dx", "0.01"], "missing --ny, --dy"),
    (["--plane", "sideways"], "must be one of slant, ground"),
    (["--autofocus", "magic"], "must be one of none, pga, min-entropy, pulse"),
])
def test_bad_grid_options_exit_2(tmp_path, raw_file, args, msg):
    r = runner.invoke(app, ["focus", str(raw_file), "--out", str(tmp_path / "h")] + args)
    assert r.exit_code == 2 and msg in " ".join(r.output.split()), r.output


def test_bad_files_exit_2_without_traceback(tmp_path):
    (tmp_path / "bad.cphd").write_bytes(b"junk")
    (tmp_path / "bad.mat").write_bytes(b"junk")
    for name in ("bad.cphd", "bad.mat"):  # in process; a real subprocess: test_main_reliability.py
        p = runner.invoke(app, ["focus", str(tmp_path / name), "--out", str(tmp_path / "o")])
        assert p.exit_code == 2 and "Traceback" not in p.output and "cannot be read" in p.output


def test_pulse_autofocus_from_cli(tmp_path, raw_file):
    r = runner.invoke(app, ["focus", str(raw_file), "--out", str(tmp_path / "p"), "--autofocus", "pulse"])
    assert r.exit_code == 0, r.output
    import json
    m = json.loads((tmp_path / "p" / "metrics.json").read_text())
    assert m["autofocus_iterations"] >= 1 and "autofocus_sharpness_0" in m


def test_focus_with_sicd_and_export(tmp_path, raw_file):
    """SICD places the image on the earth: without a geographic reference (scene.origin, the file's
    origin_llh, --origin) --sicd and export refuse naming --origin (the image used to land at 0 N 0 E
    without a word); with --origin the image carries its corners' and centre's geodetic positions."""
    r = runner.invoke(app, ["focus", str(raw_file), "--out", str(tmp_path / "s"), "--sicd"])
    assert r.exit_code == 2 and "--origin" in r.output and not (tmp_path / "s").exists()
    r = runner.invoke(app, ["focus", str(raw_file), "--out", str(tmp_path / "n")])
    assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["export", str(tmp_path / "n" / "image.nc"), str(tmp_path / "n.nitf")])
    assert r.exit_code == 2 and "--origin" in r.output and not (tmp_path / "n.nitf").exists()
    r = runner.invoke(app, ["focus", str(raw_file), "--out", str(tmp_path / "s"), "--sicd",
                            "--origin", "48.8583,2.2945,35"])
    assert r.exit_code == 0, r.output
    from salkit.io import open_dataset
    img = open_dataset(tmp_path / "s" / "image.nc")
    assert img.attrs["center_latitude"] == pytest.approx(48.8583, abs=1e-9)  # the target sits at the centre
    assert img.attrs["center_longitude"] == pytest.approx(2.2945, abs=1e-9)
    lat, lon = img.attrs["corner_latitude"], img.attrs["corner_longitude"]
    # 128 x 1.5 cm a side: the corners lie about 0.96 m apart along each axis
    assert len(lat) == 4 and abs(lat.max() - lat.min()) * 111_000 < 2.0 and abs(lon.max() - lon.min()) > 0
    assert (tmp_path / "s" / "image.nitf").is_file() and "0 errors" in r.output
    r = runner.invoke(app, ["export", str(tmp_path / "s" / "image.nc"), str(tmp_path / "x.nitf"),
                            "--origin", "48.1,11.6,520"])
    assert r.exit_code == 0 and "0 errors" in r.output, r.output
    r = runner.invoke(app, ["export", str(tmp_path / "s" / "image.nc"), str(tmp_path / "x.nitf")])
    assert r.exit_code == 2 and "exists; pass --overwrite" in " ".join(r.output.split())
    r = runner.invoke(app, ["export", str(tmp_path / "s" / "image.nc"), str(tmp_path / "x.png")])
    assert r.exit_code == 2 and ".nitf or .ntf" in r.output


@pytest.mark.parametrize("defect,msg", [
    ("nonmonotonic", "strictly monotonic"),
    ("shape", "'position' has shape"),
    ("missing", "lacks the variable 'reference_range'"),
])
def test_unusable_phase_history_exits_2(tmp_path, raw_file, defect, msg):
    import xarray as xr
    from salkit.focus import range_compress
    from salkit.io import read_raw
    ph = range_compress(read_raw(raw_file))
    f = ph["frequency"].values.copy()
    pos = ph["position"].values
    if defect == "nonmonotonic":
        f[5], f[6] = f[6], f[5]
    if defect == "shape":
        pos = pos[:, :2]
    ds = xr.Dataset({"signal": (("slow_time", "frequency"), ph["signal"].values),
                     "position": (("slow_time", "c"), pos),
                     "reference_range": (("slow_time",), ph["reference_range"].values)},
                    coords={"frequency": f}, attrs={"salkit_kind": "phase_history"})
    if defect == "missing":
        ds = ds.drop_vars("reference_range")
    p = write_dataset(ds, tmp_path / "bad.nc")
    r = runner.invoke(app, ["focus", str(p), "--out", str(tmp_path / "o")])
    assert r.exit_code == 2 and msg in " ".join(r.output.split()), r.output
    assert not isinstance(r.exception, Exception) or isinstance(r.exception, SystemExit)
