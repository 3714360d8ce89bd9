"""Reliability of the command line: atomic folders under signals and concurrency, disk full,
corrupted files, memory guards, validated choices, never a traceback."""
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

from salkit.cli.main import app

from ..conftest import EXAMPLES, SPOT, merge
from .conftest import salkit as here

runner = CliRunner()
# about 6 s: 220,000 scatterers
SLOW = merge(SPOT, processing__grid={"nx": 512, "ny": 512, "dx": 0.005, "dy": 0.005},
             scene={"points": [{"x": 0.0, "y": 0.0}], "extended": {"kind": "pattern", "pattern": "uniform",
                                                               "extent": [1.4, 1.4], "spacing": 0.003}})


def cli(*args, **kw):  # a real process (signals, the entry point, its stderr); ``here`` runs the rest in-process
    return subprocess.run([sys.executable, "-m", "salkit.cli.main", *map(str, args)], capture_output=True,
                          text=True, **kw)


def popen(*args):
    return subprocess.Popen([sys.executable, "-m", "salkit.cli.main", *map(str, args)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


@pytest.fixture
def scen(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump(SPOT))
    return p


@pytest.fixture
def slow(tmp_path):
    p = tmp_path / "slow.yaml"
    p.write_text(yaml.safe_dump(SLOW))
    return p


def _wait_for_tmp(parent: Path, name: str, proc, timeout=60):
    t0 = time.time()
    while time.time() - t0 < timeout:
        if any(p.name.startswith(f".{name}.tmp-") and any(p.iterdir()) for p in parent.iterdir()):
            return True
        if proc.poll() is not None:
            return False
        time.sleep(0.05)
    return False


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_interrupted_run_leaves_nothing(tmp_path, slow, sig):
    p = popen("run", slow, "--out", tmp_path / "out")
    assert _wait_for_tmp(tmp_path, "out", p), p.communicate()
    p.send_signal(sig)
    _, err = p.communicate(timeout=60)
    left = sorted(x.name for x in tmp_path.iterdir())
    assert p.returncode == 130 and "Traceback" not in err, (p.returncode, err, left)
    assert left == ["slow.yaml"], (left, err)


def test_interrupted_overwrite_keeps_the_old_run(tmp_path, scen, slow):
    assert here("run", scen, "--out", tmp_path / "out").returncode == 0
    before = (tmp_path / "out" / "manifest.json").read_text()
    p = popen("run", slow, "--out", tmp_path / "out", "--overwrite")
    assert _wait_for_tmp(tmp_path, "out", p)
    p.send_signal(signal.SIGINT)
    p.communicate(timeout=60)
    assert (tmp_path / "out" / "manifest.json").read_text() == before
    assert here("verify", tmp_path / "out").returncode == 0
    assert sorted(x.name for x in tmp_path.iterdir()) == ["out", "s.yaml", "slow.yaml"]


def test_concurrent_runs_leave_exactly_one(tmp_path, slow):
    a = popen("run", slow, "--out", tmp_path / "out")
    assert _wait_for_tmp(tmp_path, "out", a)
    b = here("run", slow, "--out", tmp_path / "out")
    assert b.returncode == 1 and "another salkit run" in b.stderr, b.stderr
    a.communicate(timeout=300)
    assert a.returncode == 0
    assert here("verify", tmp_path / "out").returncode == 0
    c = here("run", slow, "--out", tmp_path / "out")  # finished folder: refused without --overwrite
    assert c.returncode == 2 and "--overwrite" in c.stderr


def test_manifest_and_verify(tmp_path, scen):
    out = tmp_path / "out"
    assert here("run", scen, "--out", out).returncode == 0
    m = json.loads((out / "manifest.json").read_text())
    assert m["status"] == "complete" and m["salkit_version"] and m["scenario_sha256"] and m["run_id"]
    names = {f["path"] for f in m["files"]}
    assert {"raw.nc", "image.nc", "metrics.json", "scenario.yaml", "report.html"} <= names
    r = runner.invoke(app, ["verify", str(out)])
    assert r.exit_code == 0 and "match manifest.json" in " ".join(r.output.split())
    with open(out / "image.nc", "r+b") as fh:
        fh.seek(-100, 2)
        fh.write(b"\xff" * 10)
    r = runner.invoke(app, ["verify", str(out)])
    assert r.exit_code == 2 and "image.nc: SHA-256 differs" in " ".join(r.output.split())


def test_corrupted_signal_refused_naming_the_variable(tmp_path, scen):
    import h5py
    raw = tmp_path / "raw.nc"
    assert here("simulate", scen, "--out", raw).returncode == 0
    with h5py.File(raw, "r") as f:
        assert f["signal"].fletcher32
        off = f["signal"].id.get_chunk_info(0).byte_offset
    with open(raw, "r+b") as fh:  # 20 kB of the signal zeroed
        fh.seek(off)
        fh.write(bytes(20000))
    r = runner.invoke(app, ["focus", str(raw), "--out", str(tmp_path / "f")])
    assert r.exit_code == 2 and "variable 'signal' fails its checksum" in r.output, r.output


def _tmpfs(path: Path, opts: str) -> bool:
    path.mkdir()
    return subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", str(path)], capture_output=True).returncode == 0


def test_disk_full_exits_1_and_leaves_nothing(tmp_path, scen, monkeypatch):
    mnt = tmp_path / "small"
    if _tmpfs(mnt, "size=600k"):
        try:
            r = cli("run", scen, "--out", mnt / "o")
            assert r.returncode == 1 and "no space left on the device" in r.stderr, r.stderr
            assert "Traceback" not in r.stderr and list(mnt.iterdir()) == []
        finally:
            subprocess.run(["umount", str(mnt)])
        return
    import builtins  # no tmpfs here: file writes that fail as on a full disk
    import errno
    real_open = builtins.open

    class Full:
        def __init__(self, fh):
            self.fh = fh

        def write(self, b):
            raise OSError(errno.ENOSPC, "No space left on device")

        def __getattr__(self, k):
            return getattr(self.fh, k)

        def __enter__(self):
            return self

        def __exit__(self, *a):
            self.fh.close()

    def full_open(f, mode="r", *a, **k):
        fh = real_open(f, mode, *a, **k)
        return Full(fh) if ("w" in mode and str(f).startswith(str(mnt))) else fh
    mnt.mkdir(exist_ok=True)
    monkeypatch.setattr(builtins, "open", full_open)
    r = runner.invoke(app, ["run", str(scen), "--out", str(mnt / "o")])
    assert r.exit_code == 1 and "no space left on the device" in r.output
    assert list(mnt.iterdir()) == []


def test_read_only_place_exits_1(tmp_path, scen):
    mnt = tmp_path / "ro"
    if not _tmpfs(mnt, "size=1m,ro"):
        pytest.skip("cannot mount a read-only tmpfs here (as root, permissions do not stop writes)")
    try:
        r = cli("run", scen, "--out", mnt / "o")
        assert r.returncode == 1 and "Read-only file system" in r.stderr and "Traceback" not in r.stderr
    finally:
        subprocess.run(["umount", str(mnt)])


@pytest.mark.parametrize("args,code,msg", [
    (["run", "{scen}", "--out", "{tmp}/a", "--set", "receiver.adc_rate=1e12"], 2, "needs about"),
    (["run", "{scen}", "--out", "{tmp}/a", "--set", "platform.aperture_length=1e6"], 2, "needs about"),
    (["--max-memory", "1MiB", "run", "{scen}", "--out", "{tmp}/a"], 2, "1 MiB available" if False else "available"),
    (["screen", "--n", "1000000", "--dx", "0.01", "--r0", "0.05", "--out", "{tmp}/s.nc"], 2, "needs about"),
    (["screen", "--n", "256", "--count", "1000000000", "--dx", "0.01", "--r0", "0.05", "--out", "{tmp}/s.nc"], 2,
     "needs about"),
    (["screen", "--n", "64", "--dx", "0.01", "--r0", "0.05", "--seed", "-4", "--out", "{tmp}/s.nc"], 2, "seed"),
    (["screen", "--n", "64", "--dx", "0.01", "--r0", "0.05", "--inner-scale", "10", "--outer-scale", "1",
      "--out", "{tmp}/s.nc"], 2, "below the outer scale"),
    (["run", "{bin}", "--out", "{tmp}/a"], 2, "not UTF-8 text"),
    (["run", "{scen}", "--out", "{scen}"], 2, "names an existing file"),
    (["run", "{scen}", "--out", ""], 2, "--out"),
    (["simulate", "{scen}", "--out", "{tmp}"], 2, "is a folder"),
    (["screen", "--n", "64", "--dx", "0.01", "--r0", "0.05", "--out", "{tmp}"], 2, "is a folder"),
    (["simulate", "{scen}", "--out", "{scen}"], 2, "exists; pass --overwrite"),
    (["run", "{geo}", "--out", "{tmp}/g", "--scheduler", "foo"], 2, "tcp://HOST:PORT"),
    (["run", "{geo}", "--out", "{tmp}/g", "--workers", "-1"], 2, "stack.workers"),
    (["run", "{geo}", "--out", "{tmp}/g", "--workers", "0", "--scheduler", "tcp://h:8786"], 2, "contradict"),
    (["run", "{scen}", "--out", "{tmp}/a", "--set", "waveform.bandwidth.x=1"], 2, "is a value, not a section"),
    (["--max-memory", "lots", "info", "{scen}"], 2, "--max-memory"),
])
def test_bad_input_one_line_no_traceback(tmp_path, scen, args, code, msg):
    b = tmp_path / "bin.yaml"
    b.write_bytes(bytes(range(256)))
    fill = {"{scen}": str(scen), "{tmp}": str(tmp_path), "{bin}": str(b), "{geo}": str(EXAMPLES / "spaceborne_geo.yaml")}
    argv = [fill.get(a, a) for a in args]
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    t0 = time.perf_counter()
    r = runner.invoke(app, argv)
    assert r.exit_code == code, (argv, r.output)
    assert msg in " ".join(r.output.split()), (argv, r.output)
    assert r.exception is None or isinstance(r.exception, SystemExit)
    assert time.perf_counter() - t0 < 20
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())


def test_one_real_subprocess_has_no_traceback(tmp_path):
    b = tmp_path / "bin.yaml"
    b.write_bytes(os.urandom(300))
    r = cli("run", b, "--out", tmp_path / "x")
    assert r.returncode == 2 and "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_debug_shows_the_traceback(tmp_path):
    b = tmp_path / "bin.yaml"
    b.write_bytes(bytes(range(256)))
    r = cli("--debug", "run", b, "--out", tmp_path / "x")
    assert r.returncode != 0 and "Traceback" in r.stderr


def test_examples_copy_keeps_edits(tmp_path):
    assert runner.invoke(app, ["examples", "--copy", str(tmp_path)]).exit_code == 0
    f = tmp_path / "spotlight_points.yaml"
    f.write_text(f.read_text() + "# my edit\n")
    r = runner.invoke(app, ["examples", "--copy", str(tmp_path)])
    assert r.exit_code == 0 and "kept" in r.output and f.read_text().endswith("# my edit\n")
    r = runner.invoke(app, ["examples", "--copy", str(tmp_path), "--overwrite"])
    assert not f.read_text().endswith("# my edit\n")


def test_version():
    from salkit import __version__
    r = runner.invoke(app, ["--version"])
    assert r.exit_code == 0 and __version__ in r.output


def _session_of(pid):
    try:
        return os.getsid(pid)
    except OSError:
        return None


def _workers_under(proc):
    """The worker processes below ``proc``: spawned (``spawn_main`` in their command line) or
    forked by multiprocessing's fork server (its children; salkit's local clusters start them so
    where the platform has one)."""
    import psutil
    found = []
    try:
        kids = proc.children(recursive=True)
        servers = {c.pid for c in kids if "forkserver" in " ".join(c.cmdline())}
        for c in kids:
            if c.ppid() in servers or "spawn_main" in " ".join(c.cmdline()):
                found.append(c)
    except psutil.Error:  # one ended while looked at: look again
        pass
    return found


@pytest.mark.parametrize("when", ["while the workers start", "while the tiles run"])
def test_interrupted_focus_on_a_dask_cluster_leaves_nothing(tmp_path, when):
    """Ctrl-C at the terminal (SIGINT to the whole process group, workers included) on a local Dask
    cluster of 2 workers, as soon as the first worker process exists (while the cluster starts: a
    Ctrl-C then was once lost, and the job ran to its end) or once the tiles run: exit 130, only
    salkit's own lines (no traceback, no Dask log), no folder or partly written file, no worker
    process left running."""
    import psutil
    scen = tmp_path / "s.yaml"
    scen.write_text(yaml.safe_dump(merge(SPOT, processing__grid={"nx": 1024, "ny": 1024, "dx": 0.005,
                                                                  "dy": 0.005})))
    assert here("simulate", scen, "--out", tmp_path / "raw.nc").returncode == 0
    p = subprocess.Popen([sys.executable, "-m", "salkit.cli.main", "focus", tmp_path / "raw.nc", "--algorithm", "bp",
                          "--workers", "2", "--memory-limit", "8MiB", "--out", tmp_path / "out"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True)
    err_lines, planned = [], threading.Event()

    def read_stderr():
        for line in p.stderr:
            err_lines.append(line)
            planned.set() if line.startswith("note: focusing") else None

    reader = threading.Thread(target=read_stderr, daemon=True)
    reader.start()
    me, workers, t0 = psutil.Process(p.pid), [], time.time()
    while len(workers) < (1 if when == "while the workers start" else 2) and p.poll() is None \
            and time.time() - t0 < 60:
        workers = _workers_under(me)
        time.sleep(0.02)
    assert workers, "".join(err_lines)
    if when == "while the tiles run":
        assert planned.wait(60), "".join(err_lines)  # the plan is printed once the cluster is up
        time.sleep(1.0)
    os.killpg(p.pid, signal.SIGINT)
    p.wait(timeout=60)
    reader.join(10)
    err = "".join(err_lines)
    workers = [q for q in psutil.process_iter() if _session_of(q.pid) == p.pid]  # all it started
    lines = [x for x in err.splitlines() if x.strip() and "\u2501" not in x]
    assert p.returncode == 130, (p.returncode, err)
    assert all(x.startswith(("note:", "warning:", "interrupted:")) for x in lines), err
    assert sorted(x.name for x in tmp_path.iterdir()) == ["raw.nc", "s.yaml"]
    _, alive = psutil.wait_procs(workers, timeout=20)
    assert not alive, alive
