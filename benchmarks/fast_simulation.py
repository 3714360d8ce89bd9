"""fast_simulation: the fast simulator (one non-uniform FFT a pulse, finufft) against the direct
sum on a million-scatterer scene: 10^6 scatterers x 1024 pulses x 1024 samples, its error against
the direct sum on a sample of pulses, and the direct sum's time (measured on a subset of pulses and
scatterers, scaled: it is linear in both).

``make bench NAME=fast_simulation`` (or ``python benchmarks/fast_simulation.py``) runs it alone.
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np
from common import spotlight_scenario


def _scene(sc, n_scat, seed=1):
    rng = np.random.default_rng(seed)
    pos = np.c_[rng.uniform(-0.5, 0.5, (n_scat, 2)), np.zeros(n_scat)]
    amp = (rng.standard_normal(n_scat) + 1j * rng.standard_normal(n_scat)).astype(np.complex128)
    return pos, amp


def bench_fast_simulation(n_scat=1_000_000, n_pulses=1024, n_samples=1024):
    from salkit.geometry import build_collection
    from salkit.simulate import echo_signal, fast_time_axis
    sc = spotlight_scenario(256, n_pulses)
    sc = sc.model_copy(update={"waveform": sc.waveform.model_copy(update={"pulse_width": 4 * n_samples / sc.receiver.adc_rate})})
    col = build_collection(sc)
    t = fast_time_axis(n_samples, sc.receiver.adc_rate)
    pos, amp = _scene(sc, n_scat)
    fast = sc.model_copy(update={"simulation": sc.simulation.model_copy(update={"method": "nufft"})})
    echo_signal(dataclasses.replace(col, positions=col.positions[:2], reference_range=col.reference_range[:2],
                                    boresight=col.boresight[:2], velocity=col.velocity[:2], slow_time=col.slow_time[:2]),
                pos[:100], amp[:100], fast, t)  # compile
    t0 = time.perf_counter()
    sig = echo_signal(col, pos, amp, fast, t)
    t_fast = time.perf_counter() - t0
    # the direct sum on 8 pulses and 10^5 scatterers: its time scaled, and the fast one's error there
    sub = dataclasses.replace(col, positions=col.positions[::128], reference_range=col.reference_range[::128],
                              boresight=col.boresight[::128], velocity=col.velocity[::128], slow_time=col.slow_time[::128])
    k = min(100_000, n_scat)  # the subset of scatterers the direct sum is timed on
    echo_signal(sub, pos[:10], amp[:10], sc, t)
    t0 = time.perf_counter()
    ref = echo_signal(sub, pos[:k], amp[:k], sc, t)
    t_direct = (time.perf_counter() - t0) * (n_scat / k) * (n_pulses / sub.n_pulses)
    part = echo_signal(sub, pos[:k], amp[:k], fast, t)
    err = 10 * np.log10(np.sum(np.abs(part - ref) ** 2) / np.sum(np.abs(ref) ** 2))
    return {"fast_sim_scatterers": n_scat, "fast_sim_pulses": n_pulses, "fast_sim_samples": n_samples,
            "fast_sim_s": t_fast, "direct_sim_s_estimated": t_direct, "fast_over_direct_speed": t_direct / t_fast,
            "fast_sim_error_db": float(err), "fast_sim_finite": int(np.isfinite(sig).all())}


if __name__ == "__main__":
    import runner
    runner.main(["fast_simulation"])
