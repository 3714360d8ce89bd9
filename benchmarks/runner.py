"""The benchmark runner: runs the benchmarks of this folder (one a file, ``<name>.py`` with a
function ``bench_<name>()`` returning flat numbers), prints each figure, and writes every result
with the machine's description to ``benchmarks/last_run.json``.

``make bench`` runs them all in :data:`ORDER`; ``make bench NAME=ffbp`` (``python
benchmarks/run_all.py ffbp``, or ``python benchmarks/ffbp.py``) runs one, several names several.
"""
from __future__ import annotations

import importlib
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

#: Every benchmark, in the order ``make bench`` runs them (each ``benchmarks/<name>.py``).
ORDER = ("backprojection", "pfa", "simulation", "fast_simulation", "screens", "pga", "chirp", "spaceborne", "downlooking", "outside",
         "startup", "ffbp", "ffbp_knobs", "ffbp_arcs", "ffbp_scaling", "accuracy", "peers", "scaling", "propagation", "turbulence_wave_optics",
         "wave_structure_function", "sweep", "tiles", "budgets")


def machine() -> dict:
    """The machine a figure comes from: processor, CPUs, AVX level, Python and NumPy versions."""
    try:
        cpuinfo = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:
        cpuinfo = []
    flags = next((ln for ln in cpuinfo if ln.startswith("flags")), "")
    model = next((ln.split(":", 1)[1].strip() for ln in cpuinfo if ln.startswith("model name")), "")
    avx = "AVX-512" if " avx512f" in flags else ("AVX2" if " avx2" in flags else "none seen")
    return {"machine": model or platform.processor() or platform.machine(), "cpus": os.cpu_count(), "avx": avx,
            "python": platform.python_version(), "numpy": np.__version__}


def cpu_ticks() -> tuple[int, int] | None:
    """The machine's CPU time stolen by the hypervisor and its total CPU time so far, in clock ticks
    (``/proc/stat``; None where there is none): a virtual machine's figures move with what its
    host's other guests take, and a benchmark says how much that was while it ran."""
    try:
        fields = Path("/proc/stat").read_text().splitlines()[0].split()
    except (OSError, IndexError):
        return None
    if fields[0] != "cpu" or len(fields) < 9:
        return None
    ticks = [int(v) for v in fields[1:]]
    return ticks[7], sum(ticks[:8])  # steal; user, nice, system, idle, iowait, irq, softirq, steal


def steal_percent(before, after) -> float | None:
    """Percent of the CPUs' time the hypervisor took between two :func:`cpu_ticks` readings."""
    if before is None or after is None or after[1] <= before[1]:
        return None
    return 100.0 * (after[0] - before[0]) / (after[1] - before[1])


def main(names=None) -> dict:
    """Run the named benchmarks (all of :data:`ORDER` when none), print and store their figures.

    Parameters
    ----------
    names : list of str, optional
        Benchmark names; an unknown one is refused before anything runs.

    Returns
    -------
    dict
        Every figure, by name.
    """
    names = list(names or ORDER)
    unknown = [n for n in names if n not in ORDER]
    if unknown:
        print(f"error: unknown benchmark(s) {', '.join(unknown)}; known: {', '.join(ORDER)}", file=sys.stderr)
        sys.exit(2)
    info, res = machine(), {}
    print(f"machine: {info['machine']}, {info['cpus']} CPUs, {info['avx']}")
    for name in names:
        fn = getattr(importlib.import_module(name), f"bench_{name}")
        t0, c0 = time.perf_counter(), cpu_ticks()
        r = fn()
        steal = steal_percent(c0, cpu_ticks())
        if steal is not None:
            r[f"{name}_steal_percent"] = steal
        res.update(r)
        took = "" if steal is None else f"; the hypervisor took {steal:.1f} % of the CPUs' time"
        print(f"== {name} ({time.perf_counter() - t0:.1f} s{took})")
        for k, v in r.items():
            print(f"   {k:<34} {v:.4g}" if isinstance(v, float) else f"   {k:<34} {v}")
    out = HERE / "last_run.json"
    tmp = out.with_name(f".{out.name}.tmp")
    tmp.write_text(json.dumps({"info": info, "results": res}, indent=2) + "\n")
    os.replace(tmp, out)
    print(f"wrote {out}")
    return res


if __name__ == "__main__":
    main(sys.argv[1:])
