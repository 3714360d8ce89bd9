"""budgets: every ``--memory-limit`` promise measured over the whole command. Each case runs the
``salkit`` command in a process of its own and reports its peak resident memory (``ru_maxrss``)
beside the same command on a 64 x 64 grid of the shipped example (the baseline: the same code
loaded, negligible data)
and the budget; ``*_within`` is 1 where peak - baseline <= 1.1 x budget.

``make bench NAME=budgets`` (or ``python benchmarks/budgets.py``) runs it alone (about 2 min).
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

HERE = Path(__file__).resolve().parent
EXAMPLE = HERE.parent / "examples" / "spotlight_points.yaml"
MIB = 2 ** 20
_PEAK = ("import resource, subprocess, sys\n"
         "r = subprocess.run(sys.argv[1:], capture_output=True, text=True)\n"
         "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024)\n"
         "sys.stderr.write(r.stderr[-3000:])\n")


def _peak(args) -> tuple[int, float]:
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-c", _PEAK, sys.executable, "-m", "salkit.cli.main", *map(str, args)],
                       capture_output=True, text=True)
    code, peak = (int(v) for v in r.stdout.split())
    if code != 0:
        raise RuntimeError(f"salkit {' '.join(map(str, args))} exited {code}: {r.stderr}")
    return peak, time.perf_counter() - t0


def _sets(n, d, alg):
    return ["--set", f"processing.grid.nx={n}", "--set", f"processing.grid.ny={n}", "--set", f"processing.grid.dx={d}",
            "--set", f"processing.grid.dy={d}", "--set", f"processing.algorithm={alg}"]


def bench_budgets() -> dict:
    """Peak RSS of focus (out of core and in memory), run, simulate and sweep under a budget."""
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        raw = d / "raw.nc"
        subprocess.run([sys.executable, "-m", "salkit.cli.main", "simulate", EXAMPLE, "--out", raw], check=True,
                       capture_output=True)
        big = yaml.safe_load(EXAMPLE.read_text())
        big["receiver"]["adc_rate"] = 200e6  # 2422 pulses x 2001 samples: 37 MiB of signal
        big["platform"]["aperture_length"] = 1.9375
        big["processing"]["grid"].update(dx=0.0015, dy=0.0015)
        (d / "big.yaml").write_text(yaml.safe_dump(big))

        def grid(n, s):
            return ["--nx", n, "--ny", n, "--dx", s, "--dy", s]
        # name: (budget MiB, arguments of the full job, arguments of the baseline)
        cases = {
            "focus_ffbp_8192_2mm": (512, ["focus", raw, "--algorithm", "ffbp", *grid(8192, 0.002)],
                                    ["focus", raw, "--algorithm", "ffbp", *grid(64, 0.002)]),
            "focus_ffbp_4096_1mm": (64, ["focus", raw, "--algorithm", "ffbp", *grid(4096, 0.001)],
                                    ["focus", raw, "--algorithm", "ffbp", *grid(64, 0.001)]),
            "focus_bp_2048_1mm": (128, ["focus", raw, "--algorithm", "bp", *grid(2048, 0.001)],
                                  ["focus", raw, "--algorithm", "bp", *grid(64, 0.001)]),
            "run_ffbp_4096_1mm": (160, ["run", EXAMPLE, *_sets(4096, 0.001, "ffbp")],
                                  ["run", EXAMPLE, *_sets(64, 0.001, "ffbp")]),
            "run_bp_big_history": (160, ["run", d / "big.yaml", *_sets(1024, 0.0015, "bp")],
                                   ["run", EXAMPLE, *_sets(64, 0.0015, "bp")]),
            "simulate_big_history": (16, ["simulate", d / "big.yaml"], ["simulate", EXAMPLE]),
            "sweep_big_history": (160, ["sweep", d / "big.yaml", "--vary", "waveform.bandwidth=lin:5e9:7.5e9:2",
                                        *_sets(1024, 0.0015, "bp")],
                                  ["sweep", EXAMPLE, "--vary", "waveform.bandwidth=lin:5e9:7.5e9:2",
                                   *_sets(64, 0.0015, "bp")]),
        }
        for name, (budget, full, small) in cases.items():
            def limited(args, tag):
                target = d / f"{name}_{tag}" / ("raw.nc" if args[0] == "simulate" else "out")
                target.parent.mkdir(exist_ok=True)
                if args[0] == "sweep":  # the sweep's budget is the global --max-memory
                    return ["--max-memory", f"{budget}MiB", *args, "--out", target]
                return [*args, "--memory-limit", f"{budget}MiB", "--out", target]
            peak, sec = _peak(limited(full, "full"))
            base, _ = _peak(limited(small, "base"))
            out[f"{name}_budget_mib"] = float(budget)
            out[f"{name}_peak_rss_mib"] = peak / MIB
            out[f"{name}_baseline_rss_mib"] = base / MIB
            out[f"{name}_above_baseline_mib"] = (peak - base) / MIB
            out[f"{name}_within"] = int(peak - base <= 1.1 * budget * MIB)
            out[f"{name}_s"] = sec
    return out


if __name__ == "__main__":
    import runner
    runner.main(["budgets"])
