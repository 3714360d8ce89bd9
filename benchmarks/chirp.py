"""chirp: milliseconds per pulse of 1e5 samples for each nonlinear-chirp correction.

``make bench NAME=chirp`` (or ``python benchmarks/chirp.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
from common import C, best_of


def bench_chirp(n=100_000):
    """Cost of each nonlinear-chirp correction per pulse of n samples (seed 002 chirp)."""
    from salkit.focus.chirpcorr import (
        correct_deskew,
        correct_paper,
        correct_resample,
        estimate_nonlinear_phase,
        reference_beat,
    )
    from salkit.focus.dechirp import deskew
    from salkit.systems.chirp import coefficients
    k, tp = 5.44e14, 7.8e-6
    fs = n / tp
    f0 = C / 1.55e-6
    t = (np.arange(n) - n // 2) / fs
    co = coefficients(k, tp, 50, 50)
    raw = reference_beat(t, f0, k, co, 2 * 26.9355 / C)[None].astype(np.complex64)
    ref = reference_beat(t, f0, k, co, 0.3 / C)
    out = {"chirp_samples_per_pulse": n}
    runs = {
        "none (deskew only)": lambda: deskew(raw, fs, k),
        "estimate e(t) from reference": lambda: estimate_nonlinear_phase(ref, t, f0, k, 0.3 / C),
        "resample": lambda: deskew(correct_resample(raw, e, t, k), fs, k),
        "deskew (Meta)": lambda: correct_deskew(raw, e, fs, k),
        "paper (eq 7)": lambda: correct_paper(raw, ref, t, fs, (2 * 26.9355 / C, 0.0), (0.8 / C, 0.5 / C)),
    }
    e = estimate_nonlinear_phase(ref, t, f0, k, 0.3 / C)
    for name, fn in runs.items():
        fn()
        dt, _ = best_of(fn, 3)
        out[f"chirp_ms_per_pulse_{name}"] = dt * 1e3
    return out


if __name__ == "__main__":
    import runner
    runner.main(["chirp"])
