"""simulation: scatterer-samples per second of the dechirped-echo simulator.

``make bench NAME=simulation`` (or ``python benchmarks/simulation.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
from common import best_of, spotlight_problem


def bench_simulation(n_scat=2000, n_pulses=256):
    from salkit.geometry import build_collection
    from salkit.simulate import echo_signal, fast_time_axis
    sc, _ = spotlight_problem(256, n_pulses)
    col = build_collection(sc)
    rng = np.random.default_rng(1)
    pos = np.c_[rng.uniform(-1, 1, (n_scat, 2)), np.zeros(n_scat)]
    amp = (rng.standard_normal(n_scat) + 1j * rng.standard_normal(n_scat)).astype(np.complex128)
    t = fast_time_axis(1024, sc.receiver.adc_rate)
    run = lambda: echo_signal(col, pos, amp, sc, t)  # noqa: E731
    echo_signal(col, pos[:10], amp[:10], sc, t)
    ts, _ = best_of(run, 3)
    n = n_scat * n_pulses * t.size
    return {"sim_scatterer_samples": n, "sim_s": ts, "sim_scatterer_samples_per_s": n / ts}


if __name__ == "__main__":
    import runner
    runner.main(["simulation"])
