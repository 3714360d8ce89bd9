"""``salkit sweep``: a complete folder (sweep.nc, figures, report, metrics), bad axes exit 2 before
any work, an interrupted sweep leaves no --out and --resume completes it with the same numbers."""
import json

import numpy as np
import pytest

from salkit.io import open_dataset

from .conftest import salkit


def test_sweep_writes_a_complete_folder(tmp_path, scen):
    out = tmp_path / "s"
    r = salkit("sweep", scen, "--vary", "waveform.bandwidth=lin:5e9:7.5e9:2", "--vary", "processing.window=none,hamming",
               "--metric", "irw_range_m", "--out", out, "--workers", "0", "--keep-images")
    assert r.returncode == 0, r.stderr
    kept = sorted(p.name for p in (out / "images").iterdir())
    assert kept == [f"p{i:06d}_r0000_image.nc" for i in range(4)]
    first = open_dataset(out / "images" / kept[0])
    assert first.attrs["window"] == "none" and first.attrs["bandwidth"] == pytest.approx(5e9, rel=0.02)
    for f in ("sweep.nc", "sweep.csv", "metrics.json", "report.html", "scenario.yaml", "manifest.json",
              "sweep_irw_range_m.png"):
        assert (out / f).is_file(), f
    assert not (out / "checkpoint").exists()
    ds = open_dataset(out / "sweep.nc")
    assert ds["irw_range_m"].dims == ("waveform.bandwidth", "processing.window", "realisation")
    assert json.loads((out / "metrics.json").read_text())["sweep_points_ok"] == 4
    info = salkit("info", out / "sweep.nc", "--json")
    assert info.returncode == 0 and '"kind": "sweep"' in info.stdout
    assert salkit("verify", out).returncode == 0


@pytest.mark.parametrize("args,needle", [
    (["--vary", "waveform.bandwith=1e9,2e9"], "waveform.bandwith"),
    (["--vary", "waveform.bandwidth=log:0:1e9:3"], "cannot pass through zero"),
    (["--vary", "waveform.bandwidth=lin:1e9:2e9:0"], "positive integer"),
    (["--vary", "waveform.prf=10,20"], "none can run"),
    (["--vary", "waveform.bandwidth=1e9,2e9", "--realisations", "0"], "--realisations"),
    (["--vary", "waveform.bandwidth=1e9,2e9", "--metric", "bogus_rad"], "--metric = 'bogus_rad': is not a metric"),
    (["--vary", "waveform.bandwidth=1e9,2e9", "--metric", "irw_rnge_m"], "the nearest: 'irw_range_m'"),
])
def test_bad_sweeps_exit_2_before_any_work(tmp_path, scen, args, needle):
    r = salkit("sweep", scen, "--out", tmp_path / "o", "--workers", "0", *args)
    assert r.returncode == 2 and needle in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "o").exists()


def test_spaceborne_stacking_sweep_on_dask_nests_its_stack(tmp_path):
    """A space-borne stacking scenario swept on 2 Dask workers: each run's sub-images go to the same
    cluster (nested tasks, no cluster per run), and the numbers equal the run in this process."""
    import yaml

    from salkit.io import open_dataset
    from salkit.systems.study import run_point

    from ..conftest import EXAMPLES
    sets = ["stack.max_subimages=4", "scene.extended.extent=[1.0,1.0]", "processing.grid.nx=48", "processing.grid.ny=48"]
    r = salkit("sweep", EXAMPLES / "spaceborne_geo.yaml", *[a for x in sets for a in ("--set", x)],
               "--vary", "receiver.noise.signal_photons=0.5,2", "--metric", "snr_stack", "--out", tmp_path / "o",
               "--workers", "2")
    assert r.returncode == 0, r.stderr
    ds = open_dataset(tmp_path / "o" / "sweep.nc")
    assert (ds["status"].values == "ok").all()
    data = yaml.safe_load(ds.attrs["scenario"])
    data["receiver"]["noise"]["signal_photons"] = 2.0
    here = run_point(data, ["snr_stack"])  # in this process (the stack on a cluster of its own)
    assert here["metrics"]["snr_stack"] == ds["snr_stack"].values[1, 0]
    assert ds["snr_stack"].values[1, 0] > ds["snr_stack"].values[0, 0]  # more photons, better stack


def test_interrupted_sweep_resumes(tmp_path, scen, monkeypatch):
    """Ctrl-C, then the machine 'killed' (its staging folder left behind): --resume adopts the
    checkpoint, runs only what is missing, and equals the uninterrupted sweep."""
    import salkit.report.sweeps as engine  # where the sweep command finds its runner
    args = ["sweep", scen, "--vary", "waveform.bandwidth=5e9,6e9,7.5e9", "--metric", "peak_amplitude",
            "--workers", "0"]
    whole = tmp_path / "whole"
    assert salkit(*args, "--out", whole).returncode == 0
    real, calls = engine.run_point, []

    def dies_on_the_third(*a, **k):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(*a, **k)

    monkeypatch.setattr(engine, "run_point", dies_on_the_third)
    out = tmp_path / "cut"
    r = salkit(*args, "--out", out)
    assert r.returncode == 130 and not out.exists()
    assert "kept in" in r.stderr and ".cut.resume" in r.stderr and "--resume" in r.stderr  # not "nothing left"
    # a killed machine leaves its staging folder, not .cut.resume: make it look like that
    resume = tmp_path / ".cut.resume"
    assert (resume / "checkpoint").is_dir()
    resume.rename(tmp_path / ".cut.tmp-20261124T000000-dead")
    monkeypatch.setattr(engine, "run_point", lambda *a, **k: (calls.append(1), real(*a, **k))[1])
    calls.clear()
    r = salkit(*args, "--out", out, "--resume")
    assert not list(tmp_path.glob(".cut.*"))  # the stale staging folder adopted and removed
    assert r.returncode == 0, r.stderr
    assert len(calls) == 1  # two runs were in the checkpoint
    a, b = open_dataset(whole / "sweep.nc"), open_dataset(out / "sweep.nc")
    np.testing.assert_array_equal(a["peak_amplitude"].values, b["peak_amplitude"].values)
    # --resume into the completed folder: nothing to resume, said so (it said "holds 18 entries;
    # choose a new or empty folder"), the folder untouched
    before = sorted(p.name for p in out.iterdir())
    r = salkit(*args, "--out", out, "--resume")
    assert r.returncode == 2 and "the sweep there is complete (sweep.nc): nothing to resume" in r.stderr
    assert sorted(p.name for p in out.iterdir()) == before and len(calls) == 1
