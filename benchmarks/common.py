"""Shared benchmark problems (built from salkit's own simulator, so every method sees the same data)."""
from __future__ import annotations

import time

import numpy as np

C = 299792458.0


def best_of(fn, repeat=3):
    """Best wall time of ``repeat`` calls (s) and the last result."""
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def spotlight_problem(n_pix: int, n_pulses: int, standoff: float = 4000.0, altitude: float = 3000.0):
    """A spotlight phase history at 1.55 um with n_pulses pulses, imaged on n_pix x n_pix."""
    from salkit.focus import phase_history
    from salkit.params import parse_scenario
    from salkit.simulate import simulate
    R = float(np.hypot(standoff, altitude))
    rho = 0.02
    speed = 5.0
    L = 1.55e-6 * R / (2 * rho)
    prf = n_pulses * speed / L
    sc = parse_scenario({
        "name": "bench", "seed": 0,
        "waveform": {"wavelength": 1.55e-6, "bandwidth": C / (2 * rho), "pulse_width": 10e-6, "prf": prf},
        "platform": {"mode": "spotlight", "speed": speed, "altitude": altitude, "standoff": standoff,
                     "real_aperture": 0.002, "aperture_length": L * (1 - 0.5 / n_pulses)},
        "scene": {"points": [{"x": 0.0, "y": 0.0}, {"x": 0.3, "y": -0.2}, {"x": -0.5, "y": 0.4}]},
        "receiver": {"adc_rate": 1.2 * 2 * (C / (2 * rho) / 10e-6) * n_pix * 0.015 / C},
        "processing": {"algorithm": "bp", "grid": {"nx": n_pix, "ny": n_pix, "dx": 0.015, "dy": 0.015}},
    })
    return sc, phase_history(simulate(sc))
