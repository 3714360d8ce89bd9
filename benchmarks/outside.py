"""outside: a 500-pulse collection converted to CPHD (sarkit check included) and the GOTCHA .mat layout
and back, focused; per-pulse sharpness autofocus per sweep against PGA per iteration at 1024 x 1024.

``make bench NAME=outside`` (or ``python benchmarks/outside.py``) runs it alone.
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from common import spotlight_problem


def bench_outside(n_pulses=500, n_pix=256):
    """Outside data: a 500-pulse collection converted NetCDF -> CPHD (with sarkit's consistency
    check) -> GOTCHA .mat -> read back, and focused from each; per-pulse sharpness autofocus time
    per sweep on 1024 x 1024 pixels (the contribution matrix built once) against PGA per iteration
    on the same 1024 x 1024 image."""
    import tempfile

    from salkit.autofocus.pga import pga
    from salkit.autofocus.pulses import as_dataset
    from salkit.autofocus.sharpness import pulse_sharpness
    from salkit.focus import focus
    from salkit.focus.bp_kernel import pulse_contributions
    from salkit.geometry.collection import grid_axes, plane_from
    from salkit.io import check_cphd, read_cphd, read_gotcha, write_cphd, write_dataset, write_gotcha
    out = {}
    sc, ph = spotlight_problem(n_pix, n_pulses)
    ds = as_dataset(ph, ph.data)
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        write_dataset(ds, d / "ph.nc")
        t0 = time.perf_counter()
        write_cphd(ds, d / "c.cphd")
        out["outside_write_cphd_s_P500"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        res = check_cphd(d / "c.cphd")
        out["outside_cphd_check_s_P500"] = time.perf_counter() - t0
        out["outside_cphd_check_errors"] = len(res["errors"])
        t0 = time.perf_counter()
        back = read_cphd(d / "c.cphd")
        out["outside_read_cphd_s_P500"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        write_gotcha(back, d / "g.mat")
        g = read_gotcha(d / "g.mat")
        out["outside_mat_write_read_s_P500"] = time.perf_counter() - t0
        focus(back, sc.processing)
        t0 = time.perf_counter()
        focus(g, sc.processing)
        out[f"outside_focus_bp_s_P500_N{n_pix}"] = time.perf_counter() - t0
    # autofocus at 1024 x 1024
    sc, ph = spotlight_problem(1024, 1024)
    plane = plane_from(ph.track, ph.center_position, "slant")
    az, rg = grid_axes(sc.processing.grid)
    rows = az[::16]  # 64 rows x 1024 columns x 1024 pulses = 2**26 entries (512 MiB)
    A, R = np.meshgrid(rows, rg, indexing="ij")
    t0 = time.perf_counter()
    B = pulse_contributions(ph.data, ph.freq, ph.positions, ph.reference_range, plane.points(A.ravel(), R.ravel()))
    out["pulse_af_contributions_s_P1024_K65536"] = time.perf_counter() - t0
    pulse_sharpness(B[:, :64], max_sweeps=1)
    t0 = time.perf_counter()
    r = pulse_sharpness(B, max_sweeps=3, tol=0.0)
    out["pulse_af_s_per_sweep_P1024_K65536"] = (time.perf_counter() - t0) / (len(r.history) - 1)
    del B
    image = focus(as_dataset(ph, ph.data), sc.processing)["image"].values
    pga(image[:, :8], max_iter=1)
    t0 = time.perf_counter()
    res = pga(image, max_iter=5, tol=0.0)
    out["pga_s_per_iteration_1024x1024"] = (time.perf_counter() - t0) / (len(res.history) - 1)
    out["pulse_af_sweep_over_pga_iteration"] = out["pulse_af_s_per_sweep_P1024_K65536"] / out["pga_s_per_iteration_1024x1024"]
    return out


if __name__ == "__main__":
    import runner
    runner.main(["outside"])
