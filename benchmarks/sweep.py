"""sweep: a 24-point design study (the GEO single sub-image SNR against the photon count, about one
second a point) run by salkit.sweep in this process, on a local Dask cluster of 1 worker and of
2 workers: the speed-up of 2 workers over 1 and the per-point overhead of the engine (wall time
over the sum of the runs' own times).

``make bench NAME=sweep`` (or ``python benchmarks/sweep.py``) runs it alone.
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "sweeps" / "geo_snr_vs_photons.yaml"


def bench_sweep(points=24):
    from salkit.params import load_scenario
    from salkit.resources import dask_client
    from salkit.systems.study import sweep
    from salkit.studies.spec import read_sweep_file
    sf = read_sweep_file(EXAMPLE)
    sc = load_scenario(sf.scenario, list(sf.sets))
    vary = {"receiver.noise.signal_photons": f"log:0.3:30:{points}"}
    out = {"sweep_points": points}
    sweep(sc, {"receiver.noise.signal_photons": "1"}, metrics=sf.metrics)  # compile the kernels once
    t0 = time.perf_counter()
    ds = sweep(sc, vary, metrics=sf.metrics)
    wall = time.perf_counter() - t0
    runs = float(np.nansum(ds["run_seconds"].values))
    out.update({"sweep_inprocess_s": wall, "sweep_run_median_s": float(np.nanmedian(ds["run_seconds"].values)),
                "sweep_inprocess_overhead_per_point": (wall - runs) / runs})
    ref = ds["image_snr"].values
    for w in (1, 2):
        with dask_client(workers=w) as client:
            client.run(lambda: __import__("salkit.systems.airborne"))  # import the library on the workers
            sweep(sc, {"receiver.noise.signal_photons": "1,2"}, metrics=sf.metrics, client=client)  # warm the workers
            t0 = time.perf_counter()
            d = sweep(sc, vary, metrics=sf.metrics, client=client)
            wall = time.perf_counter() - t0
        out[f"sweep_dask_{w}_workers_s"] = wall
        runs = float(np.nansum(d["run_seconds"].values))
        out[f"sweep_dask_{w}_overhead_per_point"] = (wall * w - runs) / runs
        out[f"sweep_dask_{w}_same_numbers"] = int(np.array_equal(d["image_snr"].values, ref))
    out["sweep_speedup_2_over_1_workers"] = out["sweep_dask_1_workers_s"] / out["sweep_dask_2_workers_s"]
    return out


if __name__ == "__main__":
    import runner
    runner.main(["sweep"])
