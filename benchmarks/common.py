"""Shared benchmark problems (built from salkit's own simulator, so every method sees the same data;
the FFBP problem from a closed-form phase history) and the best-of timer."""
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


def spotlight_scenario(n_pix: int, n_pulses: int, standoff: float = 4000.0, altitude: float = 3000.0,
                       speed: float = 5.0):
    """A spotlight scenario at 1.55 um with n_pulses pulses and an ADC for an n_pix-pixel range swath,
    imaged on n_pix x n_pix pixels (at most 4096; a slower platform for many pulses: the PRF stays
    below 1 / pulse width)."""
    from salkit.params import parse_scenario
    R = float(np.hypot(standoff, altitude))
    rho = 0.02
    L = 1.55e-6 * R / (2 * rho)
    prf = n_pulses * speed / L
    sc = parse_scenario({
        "name": "bench", "seed": 0,
        "waveform": {"wavelength": 1.55e-6, "bandwidth": C / (2 * rho), "pulse_width": 10e-6, "prf": prf},
        "platform": {"mode": "spotlight", "speed": speed, "altitude": altitude, "standoff": standoff,
                     "real_aperture": 0.002, "aperture_length": L * (1 - 0.5 / n_pulses)},
        "scene": {"points": [{"x": 0.0, "y": 0.0}, {"x": 0.3, "y": -0.2}, {"x": -0.5, "y": 0.4}]},
        "receiver": {"adc_rate": 1.2 * 2 * (C / (2 * rho) / 10e-6) * n_pix * 0.015 / C},
        "processing": {"algorithm": "bp", "grid": {"nx": min(n_pix, 4096), "ny": min(n_pix, 4096), "dx": 0.015, "dy": 0.015}},
    })
    return sc


def spotlight_problem(n_pix: int, n_pulses: int, standoff: float = 4000.0, altitude: float = 3000.0,
                      speed: float = 5.0):
    """The scenario of :func:`spotlight_scenario` and its simulated phase history."""
    from salkit.focus import phase_history
    from salkit.simulate import simulate
    sc = spotlight_scenario(n_pix, n_pulses, standoff, altitude, speed)
    return sc, phase_history(simulate(sc))



def synthetic_collection(P, M, R=5000.0, lam=1.55e-6, res=0.02):
    """A spotlight phase history of three points at range R (float64 geometry), P pulses x M
    frequencies, for the given resolution in both dimensions."""
    fc = C / lam
    B = C / (2 * res)
    f = fc + (np.arange(M) - M // 2) * B / M
    L = lam * R / (2 * res)
    y = np.linspace(-L / 2, L / 2, P)
    pos = np.stack([y, np.full(P, -R * 0.8), np.full(P, R * 0.6)], axis=1)
    ref = np.linalg.norm(pos, axis=1)
    ph = np.zeros((P, M), np.complex64)
    for t in np.array([[0, 0, 0], [0.3, 0.2, 0], [-0.5, -0.4, 0]]):
        dR = np.linalg.norm(pos - t, axis=1) - ref
        ph += np.exp(-4j * np.pi * f[None, :] * dR[:, None] / C).astype(np.complex64)
    return ph, f, pos, ref, res


def ffbp_problem(n):
    """The synthetic collection of N pulses and its N x N grid at 0.8 of the resolution, with the
    FFBP kernels compiled on a small part of it."""
    from salkit.focus.ffbp import ffbp
    from salkit.focus.formers import ImageGrid
    from salkit.geometry.collection import grid_axes, plane_from
    from salkit.params import Grid
    ph, f, pos, ref, res = synthetic_collection(n, n)
    g = Grid(nx=n, ny=n, dx=0.8 * res, dy=0.8 * res)
    plane = plane_from(np.array([1.0, 0, 0]), pos[n // 2], "slant")
    az, rg = grid_axes(g)
    M = ph.shape[1]
    ffbp(ph[:256], f, pos[:256], ref[:256], ImageGrid(plane, az[:32], rg[:32], g), np.ones(256), np.ones(M))  # every level compiled
    return ph, f, pos, ref, ImageGrid(plane, az, rg, g)
