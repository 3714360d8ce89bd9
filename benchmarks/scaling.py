"""scaling: time and peak memory of each stage (simulate, phase history, BP, FFBP, PFA, PGA) at N =
256, 512, 1024 (N x N pixels, N pulses), and the fitted exponent of time ~ N^a.

``make bench NAME=scaling`` (or ``python benchmarks/scaling.py``) runs it alone.
"""
from __future__ import annotations

import time

import numpy as np
from common import spotlight_problem


def _traced(fn):
    """Wall time (s), peak memory the call allocated through NumPy/Python (bytes, tracemalloc:
    numba's own scratch arrays inside kernels are not seen) and the result."""
    import tracemalloc
    tracemalloc.start()
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    t0 = time.perf_counter()
    out = fn()
    dt = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    return dt, peak, out


def bench_scaling(sizes=(256, 512, 1024)):
    """Growth of each stage's cost with size: simulation, phase history, direct BP, FFBP, PFA and
    PGA on N x N pixels from N pulses (the shared spotlight problem), wall time and peak memory at
    each N, and the exponent a of time ~ N^a fitted over the sizes (least squares in log-log)."""
    from salkit.autofocus.pga import pga
    from salkit.focus import phase_history
    from salkit.focus.formers import ImageGrid, get_former
    from salkit.signals.windows import Window
    from salkit.simulate import simulate
    times: dict = {}
    out = {}
    win = Window("none")
    for n in sizes:
        sc, _ = spotlight_problem(n, n)
        if n == sizes[0]:  # compile every kernel once, untimed
            raw = simulate(sc)
            ph = phase_history(raw)
            grid = ImageGrid.of(ph, sc.processing.grid)
            for name in ("bp", "ffbp", "pfa"):
                img = get_former(name)(ph, grid, win).image
            pga(img, max_iter=2)
        stages = {}
        stages["simulate"] = _traced(lambda: simulate(sc))
        raw = stages["simulate"][2]
        stages["phase_history"] = _traced(lambda: phase_history(raw))
        ph = stages["phase_history"][2]
        grid = ImageGrid.of(ph, sc.processing.grid)
        for name in ("bp", "ffbp", "pfa"):
            stages[name] = _traced(lambda: get_former(name)(ph, grid, win))
        img = stages["bp"][2].image
        stages["pga_10_iterations"] = _traced(lambda: pga(img, max_iter=10, tol=0.0))
        for k, (dt, peak, _) in stages.items():
            times.setdefault(k, []).append(dt)
            out[f"scaling_{k}_N{n}_s"] = dt
            out[f"scaling_{k}_N{n}_peak_MiB"] = peak / 2**20
    x = np.log(np.asarray(sizes, float))
    for k, ts in times.items():
        out[f"scaling_{k}_exponent"] = float(np.polyfit(x, np.log(ts), 1)[0])
    return out


if __name__ == "__main__":
    import runner
    runner.main(["scaling"])
