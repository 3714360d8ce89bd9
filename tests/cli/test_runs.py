"""``salkit run`` and ``salkit simulate``: every output of a run, flat numeric metrics.json, bad
scenarios exit 2 without a traceback."""
import json

import pytest
import yaml

from .conftest import KEYS, salkit


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
    r = salkit("info", raw, "--json")
    assert r.returncode == 0
    d = json.loads(r.stdout)  # typed: flags are booleans, numbers numbers, with their units
    assert d["iq"] is True and d["noise_added"] is False and isinstance(d["prf"], float)
    assert d["units"]["prf"] == "Hz" and d["units"]["pulse_width"] == "s" and d["units"]["center_position"] == "m"
    assert salkit("info", scen).returncode == 0


def test_simulate_refuses_an_out_file_it_could_not_read_back(tmp_path, scen):
    """``simulate --out raw`` wrote a NetCDF file without a suffix, which ``focus`` then refused
    ("unknown suffix ''"): it is refused before any work, naming the suffixes and an example."""
    r = salkit("simulate", scen, "--out", tmp_path / "raw")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "--out" in r.stderr and ".nc" in r.stderr and "raw.nc" in r.stderr
    assert not (tmp_path / "raw").exists()


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


def test_simulate_a_history_larger_than_its_budget_in_blocks(tmp_path):
    """--memory-limit below the history's size: simulated and written a block of pulses at a time
    (a note says so), the file equal bit for bit to the one simulated at once; a budget below one
    block: exit 2, nothing written."""
    import numpy as np
    import yaml

    from salkit.io import open_dataset

    from ..conftest import SPOT, merge
    scen = tmp_path / "s.yaml"
    scen.write_text(yaml.safe_dump(merge(SPOT, waveform__prf=90000.0, waveform__pulse_width=5e-6,
                                         receiver__noise={"enabled": True, "signal_photons": 5.0})))
    assert salkit("simulate", scen, "--out", tmp_path / "whole.nc").returncode == 0
    r = salkit("simulate", scen, "--out", tmp_path / "blocks.nc", "--memory-limit", "3MiB")
    assert r.returncode == 0, r.stderr
    assert "blocks of pulses" in r.stderr
    a, b = open_dataset(tmp_path / "whole.nc"), open_dataset(tmp_path / "blocks.nc")
    assert a.sizes["slow_time"] > 512 and b["signal"].encoding["chunksizes"][0] <= 512  # chunks of blocks
    np.testing.assert_array_equal(a["signal"].values, b["signal"].values)
    r = salkit("simulate", scen, "--out", tmp_path / "no.nc", "--memory-limit", "200KiB")
    assert r.returncode == 2 and "one block of 512 pulses" in r.stderr and not (tmp_path / "no.nc").exists()
