"""Helpers the commands share: a grid takes all four options or none, the origin is LAT,LON,HAE,
an output file is a file; an input that is a directory is named as one (exit 2)."""
import pytest

from salkit.cli.options import _check_out_file, _grid, _origin
from salkit.errors import ScenarioError

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
