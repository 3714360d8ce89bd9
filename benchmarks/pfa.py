"""pfa: time as a multiple of one complex FFT of the output size (scipy.fft, same workers).

``make bench NAME=pfa`` (or ``python benchmarks/pfa.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
import scipy.fft as sfft
from common import best_of, spotlight_problem


def bench_pfa(n_pix=1024, n_pulses=1024):
    from salkit.focus import focus
    from salkit.simulate import simulate
    sc, _ = spotlight_problem(n_pix, n_pulses)
    raw = simulate(sc)
    from salkit.focus import phase_history
    ph = phase_history(raw)
    from salkit.focus.pfa import pfa
    from salkit.geometry.collection import grid_axes, plane_from
    from salkit.signals.windows import window
    plane = plane_from(ph.track, ph.center_position, "slant")
    az, rg = grid_axes(sc.processing.grid)
    w = lambda n: window("none", n)  # noqa: E731
    run = lambda: pfa(ph.data, ph.freq, ph.positions, ph.reference_range, plane, az, rg, w, w)  # noqa: E731
    run()
    t_pfa, _ = best_of(run, 3)
    x = (np.random.default_rng(0).standard_normal((n_pix, n_pix)) + 0j).astype(np.complex64)
    sfft.fft2(x, workers=-1)
    t_fft, _ = best_of(lambda: sfft.fft2(x, workers=-1), 5)
    del focus
    return {"pfa_output": f"{n_pix}x{n_pix}", "pfa_input": f"{ph.data.shape[0]}x{ph.data.shape[1]}",
            "pfa_s": t_pfa, "fft2_output_s": t_fft, "pfa_over_fft": t_pfa / t_fft}


if __name__ == "__main__":
    import runner
    runner.main(["pfa"])
