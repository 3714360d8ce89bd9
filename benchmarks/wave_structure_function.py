"""wave_structure_function: the wave structure function of a spherical wave through the layered path
against 6.88 (r / r0)^(5/3), with its standard error, and the seconds per realisation.

``make bench NAME=wave_structure_function`` (or ``python benchmarks/wave_structure_function.py``) runs it alone.
"""
from __future__ import annotations

import time


def bench_wave_structure_function(count=256):
    """The spherical wave's structure function against 6.88 (rho/r0_sph)^(5/3) on a large ensemble
    (1 um over 1 km, spherical sigma_R^2 = 0.2, receiver disc 16 cm): ratio and standard error
    (16 batches) at 4 mm, 2 cm and 4 cm, and the time per realisation."""
    import math as _m

    from salkit.atmosphere import r0_from_cn2
    from salkit.atmosphere.scintillation import wave_structure_function
    from salkit.atmosphere.spherical import plan_spherical, spherical_wave_ensemble
    lam, L = 1e-6, 1000.0
    cn2 = 0.2 / (0.5 * (2 * _m.pi / lam) ** (7 / 6) * L ** (11 / 6))
    s = plan_spherical(lam, L, cn2, receiver=0.16)
    t0 = time.perf_counter()
    f, s = spherical_wave_ensemble(lam, L, cn2, count, seed=11, sampling=s)
    t = time.perf_counter() - t0
    r, d, se = wave_structure_function(f, s.deltan, max_lag=10, batches=16)
    th = 6.88 * (r / r0_from_cn2(cn2, L, lam, "spherical")) ** (5 / 3)
    out = {"wsf_realisations": count, "wsf_grid_n": s.n, "wsf_s_per_realisation": t / count}
    for i in (0, 4, 9):
        mm = round(r[i] * 1e3)
        out[f"wsf_ratio_{mm}mm"] = float(d[i] / th[i])
        out[f"wsf_standard_error_{mm}mm"] = float(se[i] / th[i])
    return out


if __name__ == "__main__":
    import runner
    runner.main(["wave_structure_function"])
