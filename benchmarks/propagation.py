"""propagation: split-step wave-optics propagation per realisation (10 screens) at N = 256, 512, 1024
against the same propagation written plainly with np.fft; fields compared.

``make bench NAME=propagation`` (or ``python benchmarks/propagation.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
from common import best_of


def numpy_propagation(field, wavelength, dx, distance, screens):
    """The same split-step propagation written plainly: np.fft, the transfer function made for
    every step, the screen phasor and the field in complex128."""
    n = field.shape[0]
    f = np.fft.fftfreq(n, dx)
    fx, fy = np.meshgrid(f, f, indexing="ij")
    dz = distance / len(screens)
    u = field.astype(np.complex128)
    steps = [dz / 2] + [dz] * (len(screens) - 1) + [dz / 2]
    for i, step in enumerate(steps):
        u = np.fft.ifft2(np.fft.fft2(u) * np.exp(-1j * np.pi * wavelength * step * (fx ** 2 + fy ** 2)))
        if i < len(screens):
            u = u * np.exp(1j * screens[i])
    return u


def bench_propagation(sizes=(256, 512, 1024), layers=10):
    """Wave-optics propagation per realisation (10 screens) against the plain NumPy version, same
    screens, same machine; the fields compared."""
    from salkit.atmosphere.waveoptics import periodic_screens, propagate
    out = {}
    lam, L = 1.55e-6, 1000.0
    for n in sizes:
        dx = 0.004
        scr = periodic_screens(n, dx, 0.2, layers, np.random.default_rng(0))
        u0 = np.ones((n, n), np.complex128)
        propagate(u0, lam, dx, L, scr)
        t_s, a = best_of(lambda: propagate(u0, lam, dx, L, scr), 3)
        t_n, b = best_of(lambda: numpy_propagation(u0, lam, dx, L, scr), 2)
        out[f"propagation_{n}_salkit_s"] = t_s
        out[f"propagation_{n}_numpy_s"] = t_n
        out[f"propagation_{n}_speedup"] = t_n / t_s
        out[f"propagation_{n}_max_difference"] = float(np.abs(a - b).max())
    return out


if __name__ == "__main__":
    import runner
    runner.main(["propagation"])
