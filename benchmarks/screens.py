"""screens: phase screens per second at N = 256, 1024, 4096 against aotools' ft_sh_phase_screen
(install with ``pip install -e .[bench]``), and both generators' ensemble structure function against
Kolmogorov theory from 2 pixels to N/4.

``make bench NAME=screens`` (or ``python benchmarks/screens.py``) runs it alone.
"""
from __future__ import annotations

import time

import numpy as np
from common import best_of


def bench_screens(sizes=(256, 1024, 4096)):
    """Phase screens per second against aotools' ft_sh_phase_screen, and accuracy at N/4."""
    from salkit.atmosphere import phase_screens, structure_function, structure_function_estimate
    try:
        from aotools.turbulence.phasescreen import ft_sh_phase_screen
    except ImportError:
        ft_sh_phase_screen = None
    out = {}
    r0, dx = 0.1, 0.01
    for n in sizes:
        k = {256: 32, 1024: 8, 4096: 2}.get(n, 4)
        phase_screens(n, dx, r0, count=2, seed=0)
        t, _ = best_of(lambda: phase_screens(n, dx, r0, count=k, seed=1), 2)
        out[f"screens_salkit_per_s_N{n}"] = k / t
        t32, _ = best_of(lambda: phase_screens(n, dx, r0, count=k, seed=1, dtype=np.float32), 2)
        out[f"screens_salkit_f32_per_s_N{n}"] = k / t32
        if ft_sh_phase_screen is not None:
            ka = max(1, min(k, 8 if n <= 1024 else 1))
            t0 = time.perf_counter()
            for i in range(ka):
                ft_sh_phase_screen(r0, n, dx, 1e8, 1e-9, seed=i)
            ta = (time.perf_counter() - t0) / ka
            out[f"screens_aotools_per_s_N{n}"] = 1 / ta
            out[f"screens_speedup_vs_aotools_N{n}"] = ta / (t / k)
            out[f"screens_f32_speedup_vs_aotools_N{n}"] = ta / (t32 / k)
    # accuracy: ensemble structure function at N/4 against Kolmogorov, same ensemble size
    n, K = 64, 1000
    s = phase_screens(n, dx, r0, count=K, seed=7)
    r, d, e = structure_function_estimate(s, dx)
    th = structure_function(r, r0)
    out["screens_salkit_sf_ratio_at_N4"] = float(d[-1] / th[-1])
    out["screens_salkit_sf_worst_2px_to_N4"] = float(np.max(np.abs(d[1:] / th[1:] - 1)))
    if ft_sh_phase_screen is not None:
        sa = np.stack([ft_sh_phase_screen(r0, n, dx, 1e8, 1e-9, seed=1000 + i) for i in range(K)])
        r, d, e = structure_function_estimate(sa, dx)
        out["screens_aotools_sf_ratio_at_N4"] = float(d[-1] / th[-1])
        out["screens_aotools_sf_worst_2px_to_N4"] = float(np.max(np.abs(d[1:] / th[1:] - 1)))
    out["screens_sf_stderr_at_N4"] = float(e[-1] / th[-1])
    return out


if __name__ == "__main__":
    import runner
    runner.main(["screens"])
