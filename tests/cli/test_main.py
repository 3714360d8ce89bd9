"""The command line: outputs, flat numeric metrics.json, and exit status 2 without tracebacks."""
import json

import pytest
import yaml

from ..conftest import EXAMPLES, SPOT

KEYS = ["irw_range_m", "irw_azimuth_m", "pslr_range_db", "pslr_azimuth_db", "islr_range_db", "islr_azimuth_db",
        "peak_offset_range_m", "peak_offset_azimuth_m", "irw_range_theory_m", "irw_azimuth_theory_m",
        "pslr_range_theory_db", "pslr_azimuth_theory_db", "islr_range_theory_db", "islr_azimuth_theory_db",
        "peak_offset_range_theory_m", "peak_offset_azimuth_theory_m"]


class _Result:
    def __init__(self, r):
        self.returncode, self.stdout, self.stderr = r.exit_code, r.stdout, r.stderr
        self.exception = r.exception


def salkit(*args):
    """Run the command line in-process (typer's CliRunner), wide enough that no line wraps.
    Real subprocesses are exercised in test_reliability.py (signals, the entry point)."""
    from typer.testing import CliRunner
    from salkit.cli.main import app
    r = CliRunner().invoke(app, [str(a) for a in args], env={"COLUMNS": "400"})
    assert r.exception is None or isinstance(r.exception, SystemExit), repr(r.exception)
    return _Result(r)


@pytest.fixture
def scen(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump(SPOT))
    return p


def test_run_writes_everything(tmp_path, scen):
    out = tmp_path / "out"
    r = salkit("run", scen, "--out", out)
    assert r.returncode == 0, r.stderr
    for f in ["raw.nc", "image.nc", "metrics.json", "scenario.yaml", "image.png", "cuts.png", "report.html"]:
        assert (out / f).is_file(), f
    m = json.loads((out / "metrics.json").read_text())
    assert all(isinstance(v, (int, float)) for v in m.values())
    for k in KEYS:
        assert k in m, k
    assert m["irw_range_m"] == pytest.approx(m["irw_range_theory_m"], rel=0.03)
    html = (out / "report.html").read_text()
    assert "image.png" in html and "cuts.png" in html
    resolved = yaml.safe_load((out / "scenario.yaml").read_text())
    assert resolved["receiver"]["noise"]["enabled"] is False  # defaults filled in
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temporaries left


def test_simulate_then_focus_with_other_algorithm(tmp_path, scen):
    raw = tmp_path / "raw.nc"
    assert salkit("simulate", scen, "--out", raw).returncode == 0
    r = salkit("focus", raw, "--algorithm", "pfa", "--out", tmp_path / "f")
    assert r.returncode == 0, r.stderr
    m = json.loads((tmp_path / "f" / "metrics.json").read_text())
    assert m["irw_azimuth_m"] == pytest.approx(m["irw_azimuth_theory_m"], rel=0.03)
    r = salkit("info", raw)
    assert r.returncode == 0
    d = json.loads(r.stdout)  # typed: flags are booleans, numbers numbers, with their units
    assert d["iq"] is True and d["noise_added"] is False and isinstance(d["prf"], float)
    assert d["units"]["prf"] == "Hz" and d["units"]["pulse_width"] == "s" and d["units"]["center_position"] == "m"
    assert salkit("info", scen).returncode == 0


@pytest.mark.parametrize("name", sorted(p.stem for p in EXAMPLES.glob("*.yaml")))
def test_info_on_every_shipped_example(name):
    """`salkit info` works where `salkit run` does (an experiment checks its own sampling), and says
    the unit of every quantity it prints."""
    r = salkit("info", EXAMPLES / f"{name}.yaml")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["name"] == name and d["units"]
    from salkit.units import NAMED
    for k, v in d.items():
        if k.endswith("_m") and k not in NAMED and isinstance(v, (int, float)):
            assert d["units"][k] == "m", k


def test_help_names_units_and_no_python_types():
    for cmd in ("run", "simulate", "focus", "screen", "export", "convert"):
        out = salkit(cmd, "--help").stdout
        assert "<bool>" not in out and "<list[str]>" not in out and "{" not in out.split("\n")[0], cmd
    focus_help = salkit("focus", "--help").stdout
    for opt in ("--nx PIXELS", "--dx METRES", "--dy METRES"):
        assert opt in focus_help
    assert "salkit " in salkit("--version").stdout


@pytest.mark.parametrize("args,needle", [
    (["--set", "waveform.bandwidth=-1"], "waveform.bandwidth"),
    (["--set", "waveform.prf=2e5"], "duty cycle"),
    (["--set", "platform.real_aperture=0.0"], "platform.real_aperture"),
    (["--set", "receiver.adc_rate=1e5", "--set", "scene.points.0.y=1.0"], "receiver.adc_rate"),
    (["--set", "processing.grid.dy=0.5"], "processing.grid.dy"),
    (["--set", "scene.points.0.x=.nan"], "scene.points.0.x"),
])
def test_bad_scenarios_exit_2_without_traceback(tmp_path, scen, args, needle):
    out = tmp_path / "o"
    r = salkit("run", scen, "--out", out, *args)
    assert r.returncode == 2
    assert needle in r.stderr
    assert "Traceback" not in r.stderr + r.stdout
    assert not out.exists()  # checked before any work or output


def test_bad_files_exit_2(tmp_path, scen):
    raw = tmp_path / "raw.nc"
    salkit("simulate", scen, "--out", raw)
    t = tmp_path / "t.nc"
    t.write_bytes(raw.read_bytes()[:2000])
    import numpy as np
    from salkit.io import read_raw, write_dataset
    bad = read_raw(raw)
    bad["signal"].values[0, 0] = np.nan
    nan_file = write_dataset(bad, tmp_path / "nan.nc")
    r = salkit("focus", nan_file, "--out", tmp_path / "y")
    assert r.returncode == 2 and "non-finite" in r.stderr and "Traceback" not in r.stderr
    for args in (["focus", t, "--out", tmp_path / "x"], ["focus", tmp_path / "none.nc", "--out", tmp_path / "x"],
                 ["focus", raw, "--algorithm", "magic", "--out", tmp_path / "x"], ["run", tmp_path / "no.yaml", "--out", tmp_path / "x"]):
        r = salkit(*args)
        assert r.returncode == 2, args
        assert "Traceback" not in r.stderr


def test_examples_listed():
    r = salkit("examples")
    assert r.returncode == 0
    for f in EXAMPLES.glob("*.yaml"):
        assert f.name in r.stdout


def test_run_with_autofocus_records_history(tmp_path, scen):
    out = tmp_path / "af"
    r = salkit("run", scen, "--out", out, "--set", "platform.phase_error.amplitude=8",
               "--set", "processing.autofocus=pga", "--set", "processing.autofocus_kernel=ev")
    assert r.returncode == 0, r.stderr
    m = json.loads((out / "metrics.json").read_text())
    assert m["before_autofocus_irw_azimuth_m"] > 1.3 * m["irw_azimuth_theory_m"]
    assert m["irw_azimuth_m"] == pytest.approx(m["irw_azimuth_theory_m"], rel=0.05)
    assert m["autofocus_entropy_0"] > m[f"autofocus_entropy_{m['autofocus_best_iteration']}"]
    for f in ("autofocus.png", "image_focus.nc"):
        assert (out / f).is_file()
    assert "autofocus.png" in (out / "report.html").read_text()


def test_propagate_writes_the_field_and_its_scintillation(tmp_path):
    import xarray as xr
    r = salkit("propagate", "--wavelength", "1.55e-6", "--cn2", "1e-14", "--distance", "1000", "--count", "4",
               "--out", tmp_path / "p")
    assert r.returncode == 0, r.stderr
    m = json.loads((tmp_path / "p" / "metrics.json").read_text())
    for k in ("rytov_variance", "scintillation_index", "scintillation_index_theory", "r0_spherical_m"):
        assert k in m
    ds = xr.open_dataset(tmp_path / "p" / "field.nc")
    assert ds["field"].dims == ("realisation", "y", "x") and ds["x"].attrs["units"] == "m"
    r = salkit("propagate", "--wave", "conical", "--wavelength", "1.55e-6", "--cn2", "1e-14", "--distance", "1000",
               "--out", tmp_path / "s")
    assert r.returncode == 2 and "--wave" in r.stderr and not (tmp_path / "s").exists()
    r = salkit("propagate", "--wavelength", "2e-6", "--cn2", "1e-13", "--distance", "50000", "--out", tmp_path / "b")
    assert r.returncode == 2 and "more than" in r.stderr and not (tmp_path / "b").exists()
