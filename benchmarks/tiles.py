"""tiles: image formation under a memory budget (issue 25): an 8192^2 FFBP image formed tile by
tile into a chunked file under a 512 MiB budget, each job in a fresh process whose peak resident
memory (``ru_maxrss``, the whole process) is reported beside its baseline (the interpreter and
libraries with the file open) and after the kernels are loaded on 64 pulses; the history is
simulated and written by another process first.

``make bench NAME=tiles`` (or ``python benchmarks/tiles.py``) runs it alone.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SIMULATE = r'''
import sys
sys.path.insert(0, {bench!r})
from common import spotlight_problem
from salkit.io import write_dataset
from salkit.simulate import simulate
sc, _ = spotlight_problem(2048, {pulses}, speed=1.0)  # the ADC sized for a 2048-pixel swath: 1.8 k samples a pulse
write_dataset(simulate(sc), {folder!r} + "/raw.nc")
'''

JOB = r'''
import json, resource, sys, time
import numpy as np
sys.path.insert(0, {bench!r})
from common import spotlight_problem
from salkit.focus import focus_to_file
from salkit.io import open_dataset
from salkit.params import Grid
n_pix, pulses, limit, alg, folder = {n_pix}, {pulses}, {limit!r}, {alg!r}, {folder!r}
lazy = open_dataset(folder + "/raw.nc", lazy=True)
from salkit.params import stored_scenario
sc = stored_scenario(lazy.attrs)
g = Grid(nx=n_pix, ny=n_pix, dx=0.015, dy=0.015)
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # interpreter, libraries, the file open
small = focus_to_file(lazy.isel(slow_time=slice(0, 64)), folder + "/warm.nc", sc.processing, algorithm=alg,
                      grid=Grid(nx=64, ny=64, dx=0.015, dy=0.015))  # kernels loaded (64 pulses: a few MiB)
small.close()
warm = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
t0 = time.perf_counter()
img = focus_to_file(lazy, folder + "/image.nc", sc.processing, algorithm=alg, grid=g, memory_limit=limit)
dt = time.perf_counter() - t0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps({{"seconds": dt, "peak_rss": peak, "baseline_rss": base, "warm_rss": warm, "tiles": int(img.attrs.get("tiles", 1)),
                  "tile": [int(img.attrs.get("tile_nx", n_pix)), int(img.attrs.get("tile_ny", n_pix))],
                  "signal_shape": list(lazy["signal"].shape), "image_bytes": 8 * n_pix * n_pix}}))
'''


def run_job(n_pix: int, pulses: int, limit: str, alg: str) -> dict:
    """One job in a fresh Python process; its figures."""
    with tempfile.TemporaryDirectory(prefix="salkit-bench-tiles-") as d:
        fill = dict(bench=str(Path(__file__).parent), n_pix=n_pix, pulses=pulses, limit=limit, alg=alg, folder=d)
        subprocess.run([sys.executable, "-c", SIMULATE.format(**fill)], capture_output=True, text=True, check=True)
        r = subprocess.run([sys.executable, "-c", JOB.format(**fill)], capture_output=True, text=True, check=True)
        return json.loads(r.stdout.strip().splitlines()[-1])


def bench_tiles(jobs=((8192, 2048, "512MiB", "ffbp"),)):
    """Each job: pixels a side, pulses, budget, former; time, peak and baseline resident memory;
    then the strong scaling of an 8192^2 FFBP and a 2048^2 direct BP from 1 to 2 Dask workers."""
    out = bench_tiles_scaling()
    out.update(bench_tiles_scaling(n_pix=2048, pulses=1024, alg="bp"))
    for n, p, limit, alg in jobs:
        m = run_job(n, p, limit, alg)
        key = f"tiles_{alg}_{n}_{p}p_{limit}"
        out.update({f"{key}_s": m["seconds"], f"{key}_peak_rss_mib": m["peak_rss"] / 2 ** 20,
                    f"{key}_baseline_rss_mib": m["baseline_rss"] / 2 ** 20,
                    f"{key}_kernels_loaded_rss_mib": m["warm_rss"] / 2 ** 20,
                    f"{key}_job_rss_mib": (m["peak_rss"] - m["baseline_rss"]) / 2 ** 20,
                    f"{key}_tiles": m["tiles"], f"{key}_image_mib": m["image_bytes"] / 2 ** 20,
                    f"{key}_signal": "x".join(map(str, m["signal_shape"]))})
    return out


SCALING = r'''
import json, sys, time
sys.path.insert(0, {bench!r})
import numpy as np
from salkit.focus import phase_history
from salkit.focus.pipeline import form_image
from salkit.focus.tiles import InMemoryPulses, plan_tiling
from salkit.io import open_dataset
from salkit.params import Grid, stored_scenario
from salkit.resources import dask_client
n_pix, alg, folder, reps = {n_pix}, {alg!r}, {folder!r}, {reps}
raw = open_dataset(folder + "/raw.nc")
sc = stored_scenario(raw.attrs)
ph = phase_history(raw)
g = Grid(nx=n_pix, ny=n_pix, dx=0.015, dy=0.015)
P, N = raw["signal"].shape
tiling = plan_tiling(P, N, n_pix, n_pix, alg, 2 ** 40, min_tiles=8)  # the same 8 tiles on 1 and 2 workers
small = plan_tiling(P, N, 64, 64, alg, 2 ** 40, min_tiles=2)
times, first, diffs = {{1: [], 2: []}}, None, []
for rep in range(reps):  # 1 and 2 workers in turn, each a fresh local cluster as `salkit focus --workers` starts
    for n in (1, 2):
        with dask_client(workers=n) as client:
            form_image(ph, sc.processing, Grid(nx=64, ny=64, dx=0.015, dy=0.015), algorithm=alg, tiling=small,
                       pulses=InMemoryPulses(ph), client=client)  # kernels loaded on every worker
            t0 = time.perf_counter()
            res = form_image(ph, sc.processing, g, algorithm=alg, tiling=tiling, pulses=InMemoryPulses(ph),
                             client=client)[0]
            times[n].append(time.perf_counter() - t0)
        if first is None:
            first = res.image
        else:  # any difference from the first image recorded: pixels, energy, where
            d = res.image - first
            bad = np.argwhere(d != 0)
            if bad.size:
                e = float(np.sum(np.abs(d) ** 2) / np.sum(np.abs(first) ** 2))
                diffs.append(dict(rep=rep, workers=n, pixels=int(len(bad)), energy_db=10 * np.log10(e) if e else None,
                                  rows=[int(bad[:, 0].min()), int(bad[:, 0].max())],
                                  cols=[int(bad[:, 1].min()), int(bad[:, 1].max())]))
print(json.dumps({{"one": times[1], "two": times[2], "tiles": tiling.n_tiles, "same": not diffs, "diffs": diffs}}))
'''

PLAIN = r'''
import json, sys, time
import numpy as np
from salkit.focus import phase_history
from salkit.focus.formers import ImageGrid
from salkit.focus.tiles import InMemoryPulses, plan_tiling, tile_image
from salkit.io import open_dataset
from salkit.params import Grid, stored_scenario
from salkit.signals.windows import Window
n_pix, alg, folder, part, parts = {n_pix}, {alg!r}, {folder!r}, int(sys.argv[1]), int(sys.argv[2])
raw = open_dataset(folder + "/raw.nc")
sc = stored_scenario(raw.attrs)
ph = phase_history(raw)
p = sc.processing
win = Window(p.window, p.taylor_nbar, p.taylor_sll)
P, N = raw["signal"].shape
tiling = plan_tiling(P, N, n_pix, n_pix, alg, 2 ** 40, min_tiles=8)
small = plan_tiling(P, N, 64, 64, alg, 2 ** 40, min_tiles=2)
pul = InMemoryPulses(ph)
tile_image(pul, ImageGrid.of(ph, Grid(nx=64, ny=64, dx=0.015, dy=0.015)), win, small, small.tiles[0],
           p.range_upsample, p.accuracy)  # kernels loaded
ig = ImageGrid.of(ph, Grid(nx=n_pix, ny=n_pix, dx=0.015, dy=0.015))
t0 = time.perf_counter()
for k in range(part, tiling.n_tiles, parts):
    tile_image(pul, ig, win, tiling, tiling.tiles[k], p.range_upsample, p.accuracy)
print(json.dumps({{"seconds": time.perf_counter() - t0}}))
'''


def _plain(fill: dict, parts: int) -> float:
    # the same tiles in `parts` plain processes at once (one numba thread each, no Dask): the
    # machine's own scaling of the work, the ceiling of what any scheduler can reach
    env = dict(os.environ, NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1")
    procs = [subprocess.Popen([sys.executable, "-c", PLAIN.format(**fill), str(k), str(parts)], stdout=subprocess.PIPE,
                              text=True, env=env) for k in range(parts)]
    t0 = time.perf_counter()
    outs = [pr.communicate()[0] for pr in procs]
    assert all(pr.returncode == 0 for pr in procs)
    return max(json.loads(o.strip().splitlines()[-1])["seconds"] for o in outs), time.perf_counter() - t0


def bench_tiles_scaling(n_pix: int = 8192, pulses: int = 2048, alg: str = "ffbp", reps: int = 3) -> dict:
    """Strong scaling of one job's tiles on a local Dask cluster of 1 and 2 workers, as
    ``salkit focus --workers`` starts it (:func:`salkit.resources.dask_client`: one numba thread a
    worker): the same 8 tiles (so the same image, checked), the phase history in memory and
    scattered to the workers, the kernels loaded on every worker before the timing; ``reps``
    fresh clusters of each size in turn, the least and the median time of each. Beside it the
    same tiles in 1 and 2 plain processes (no Dask): the machine's own ceiling."""
    with tempfile.TemporaryDirectory(prefix="salkit-bench-tiles-") as d:
        fill = dict(bench=str(Path(__file__).parent), n_pix=n_pix, pulses=pulses, limit="", alg=alg, folder=d,
                    reps=reps)
        subprocess.run([sys.executable, "-c", SIMULATE.format(**fill)], capture_output=True, text=True, check=True)
        r = subprocess.run([sys.executable, "-c", SCALING.format(**fill)], capture_output=True, text=True, check=True)
        m = json.loads(r.stdout.strip().splitlines()[-1])
        plain1, plain2 = _plain(fill, 1)[0], _plain(fill, 2)[0]
    key = f"tiles_scaling_{alg}_{n_pix}_{pulses}p"
    one, two = sorted(m["one"]), sorted(m["two"])
    return {f"{key}_1_worker_min_s": one[0], f"{key}_2_workers_min_s": two[0],
            f"{key}_speedup_of_min": one[0] / two[0],
            f"{key}_speedup_of_median": one[len(one) // 2] / two[len(two) // 2],
            f"{key}_speedups_each_rep": " ".join(f"{a / b:.2f}" for a, b in zip(m["one"], m["two"])),
            f"{key}_plain_processes_speedup": plain1 / plain2,
            f"{key}_plain_1_process_s": plain1, f"{key}_plain_2_processes_s": plain2,
            f"{key}_tiles": m["tiles"], f"{key}_same_image": m["same"],
            **({f"{key}_differences": json.dumps(m["diffs"])} if m["diffs"] else {})}


BIG_SIMULATE = r'''
import json, resource, sys, time
sys.path.insert(0, {bench!r})
from common import spotlight_scenario
from salkit.simulate.sal import simulate_to_file
sc = spotlight_scenario({swath}, {pulses}, speed={speed})  # an ADC for a {swath}-pixel range swath
t0 = time.perf_counter()
simulate_to_file(sc, {folder!r} + "/raw.nc", memory_limit=4 * 2 ** 30)
print(json.dumps({{"seconds": time.perf_counter() - t0,
                  "peak_rss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}}))
'''

BIG_FOCUS = r'''
import json, os, resource, sys, time
from salkit.focus import focus_to_file
from salkit.io import open_dataset
from salkit.params import Grid, stored_scenario
folder = {folder!r}
lazy = open_dataset(folder + "/raw.nc", lazy=True)
sc = stored_scenario(lazy.attrs)
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
t0 = time.perf_counter()
img = focus_to_file(lazy, folder + "/image.nc", sc.processing, algorithm={alg!r},
                    grid=Grid(nx={n_pix}, ny={n_pix}, dx=0.015, dy=0.015), memory_limit={limit!r})
dt = time.perf_counter() - t0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
from salkit.io import brightest_window
from salkit.metrics import measure
m = measure(brightest_window(img))  # the brightest point: where, how sharp, against theory
check = {{k: float(m[k]) for k in ("peak_amplitude", "irw_range_m", "irw_range_theory_m", "irw_azimuth_m",
                                  "irw_azimuth_theory_m", "peak_offset_range_m", "peak_offset_azimuth_m") if k in m}}
print(json.dumps({{"seconds": dt, "peak_rss": peak, "baseline_rss": base, "tiles": int(img.attrs.get("tiles", 1)),
                  "check": check,
                  "pulse_block": int(img.attrs.get("pulse_block", 0)), "history_bytes": os.path.getsize(folder + "/raw.nc"),
                  "signal_shape": list(lazy["signal"].shape), "tiling": str(img.attrs.get("tiling", ""))}}))
'''


def bench_big_history(swath: int = 45_500, pulses: int = 65_536, n_pix: int = 4096, limit: str = "4GiB",
                      alg: str = "ffbp", speed: float = 0.25) -> dict:
    """A history larger than memory (about 20 GiB: 65536 pulses x 41 k samples) simulated into a
    file a block at a time (one process), then focused onto n_pix^2 in pulse blocks read from the
    file (FFBP by default), under ``limit`` (another process, its peak resident memory measured)."""
    with tempfile.TemporaryDirectory(prefix="salkit-bench-big-") as d:
        fill = dict(bench=str(Path(__file__).parent), swath=swath, pulses=pulses, n_pix=n_pix, limit=limit, folder=d,
                    alg=alg, speed=speed)
        r = subprocess.run([sys.executable, "-c", BIG_SIMULATE.format(**fill)], capture_output=True, text=True, check=True)
        sim = json.loads(r.stdout.strip().splitlines()[-1])
        r = subprocess.run([sys.executable, "-c", BIG_FOCUS.format(**fill)], capture_output=True, text=True, check=True)
        m = json.loads(r.stdout.strip().splitlines()[-1])
    key = f"big_history_{alg}_{n_pix}_{limit}"
    return {f"{key}_history_gib": m["history_bytes"] / 2 ** 30, f"{key}_signal": "x".join(map(str, m["signal_shape"])),
            f"{key}_simulate_s": sim["seconds"], f"{key}_simulate_peak_rss_mib": sim["peak_rss"] / 2 ** 20,
            f"{key}_focus_s": m["seconds"], f"{key}_focus_peak_rss_mib": m["peak_rss"] / 2 ** 20,
            f"{key}_focus_baseline_rss_mib": m["baseline_rss"] / 2 ** 20, f"{key}_tiles": m["tiles"],
            f"{key}_pulse_block": m["pulse_block"], f"{key}_tiling": m["tiling"],
            **{f"{key}_brightest_{k}": v for k, v in m["check"].items()}}


if __name__ == "__main__":
    import runner
    runner.main(["tiles"])
