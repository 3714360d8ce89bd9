"""Helpers the commands share: a grid takes all four options or none, the origin is LAT,LON,HAE,
an output file is a file; an input that is a directory is named as one (exit 2)."""
import pytest

from salkit.cli.options import _check_out_file, _grid, _origin
from salkit.errors import ScenarioError

from ..conftest import fresh_command
from .conftest import salkit


def test_grid_all_or_none():
    assert _grid(None, None, None, None, "slant") is None
    g = _grid(64, 32, 0.01, 0.02, "ground")
    assert (g.nx, g.ny, g.dx, g.dy, g.plane) == (64, 32, 0.01, 0.02, "ground")
    with pytest.raises(ScenarioError, match="missing --dx, --dy"):
        _grid(64, 32, None, None, "slant")
    with pytest.raises(ScenarioError, match="--dx"):
        _grid(64, 32, -0.01, 0.02, "slant")


def test_origin_and_out_file(tmp_path):
    assert _origin(None) is None and _origin("45,7.5,100") == [45.0, 7.5, 100.0]
    for bad in ("91,0,0", "1,2", "a,b,c", "nan,0,0"):
        with pytest.raises(ScenarioError, match="--origin"):
            _origin(bad)
    with pytest.raises(ScenarioError, match="is a folder"):
        _check_out_file(tmp_path, False)
    (tmp_path / "f.nc").write_text("x")
    with pytest.raises(ScenarioError, match="exists; pass --overwrite"):
        _check_out_file(tmp_path / "f.nc", False)
    _check_out_file(tmp_path / "f.nc", True)


@pytest.mark.parametrize("command,suffix", [("focus", ".nc"), ("focus", ".cphd"), ("focus", ".mat"), ("info", ".nc"),
                                            ("convert", ".nc")])
def test_directory_given_as_a_file(tmp_path, command, suffix):
    d = tmp_path / f"data{suffix}"
    d.mkdir()
    args = {"focus": ["--out", tmp_path / "o"], "info": [], "convert": [tmp_path / "x.nc"]}[command]
    r = salkit(command, d, *args)
    assert r.returncode == 2
    assert f"{d}: is a directory, not a file" in r.stderr and "Traceback" not in r.stderr


def test_a_misspelt_key_is_named_as_written_with_the_nearest_valid_key(tmp_path):
    """A typo in a scenario file, in --set, in --vary or in a sweep file's keys names the key as the
    user wrote it and the nearest valid key (it used to say "waveform.bandwidth is required" and never
    name the typo)."""
    import yaml
    from ..conftest import SPOT
    from .conftest import salkit
    d = yaml.safe_load(yaml.safe_dump(SPOT))
    d["waveform"]["bandwidht"] = d["waveform"].pop("bandwidth")
    bad = tmp_path / "typo.yaml"
    bad.write_text(yaml.safe_dump(d))
    r = salkit("run", bad, "--out", tmp_path / "o")
    assert r.returncode == 2 and "waveform.bandwidht" in r.stderr and "did you mean 'bandwidth'?" in r.stderr
    good = tmp_path / "good.yaml"
    good.write_text(yaml.safe_dump(SPOT))
    r = salkit("run", good, "--out", tmp_path / "o", "--set", "waveform.bandwdth=5e9")
    assert r.returncode == 2 and "waveform.bandwdth" in r.stderr and "did you mean 'bandwidth'?" in r.stderr
    r = salkit("run", good, "--out", tmp_path / "o", "--set", "wavefrom.prf=5e3")
    assert r.returncode == 2 and "did you mean 'waveform'?" in r.stderr
    r = salkit("sweep", good, "--out", tmp_path / "o", "--vary", "waveform.bandwdth=1e9,2e9")
    assert r.returncode == 2 and "waveform.bandwdth" in r.stderr and "did you mean 'bandwidth'?" in r.stderr
    sw = tmp_path / "sw.yaml"
    sw.write_text(yaml.safe_dump({"sweep": 1, "scenario": str(good), "vary": {"waveform.bandwidth": "5e9,6e9"},
                                  "realisatons": 2}))
    r = salkit("sweep", sw, "--out", tmp_path / "o")
    assert r.returncode == 2 and "realisatons" in r.stderr and "did you mean 'realisations'?" in r.stderr
    assert not (tmp_path / "o").exists()


def test_a_scenario_given_where_data_are_expected_says_so(tmp_path):
    """`salkit focus scenario.yaml` (or a scenario renamed .nc) says it is a scenario and names
    `salkit run`, instead of "cannot be read as NetCDF4/HDF5 (truncated or corrupt?)"."""
    import shutil
    from ..conftest import EXAMPLES
    from .conftest import salkit
    src = EXAMPLES / "spotlight_points.yaml"
    for path in (src, tmp_path / "looks_like_data.nc"):
        if path != src:
            shutil.copy(src, path)
        r = salkit("focus", path, "--out", tmp_path / "o")
        assert r.returncode == 2 and "scenario file" in r.stderr and "salkit run" in r.stderr, r.stderr


@pytest.mark.parametrize("argv", [["run", "{missing}", "--out", "{tmp}/o"], ["simulate", "{tmp}", "--out", "{tmp}/r.nc"],
                                  ["sweep", "{missing}", "--vary", "waveform.prf=1,2", "--out", "{tmp}/s"]])
def test_a_missing_scenario_is_refused_before_the_library_loads(tmp_path, argv):
    """A mistyped scenario path is told in under a second, not after 3 s of imports (a slow core)."""
    args = [a.replace("{missing}", str(tmp_path / "nothere.yaml")).replace("{tmp}", str(tmp_path)) for a in argv]
    code, loaded, _, stderr = fresh_command(args, ("xarray", "numba.core", "matplotlib", "salkit.io", "salkit.params"))
    assert (code, loaded) == ("2", "[]"), (code, loaded, stderr)
    assert ("file does not exist" if "{missing}" in argv else "is a folder") in " ".join(stderr.split())
    assert sorted(p.name for p in tmp_path.iterdir()) == []
