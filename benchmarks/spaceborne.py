"""spaceborne: GEO sub-images per second in-process and through Dask with 1 and 2 workers (64 sub-
images, cluster start included).

``make bench NAME=spaceborne`` (or ``python benchmarks/spaceborne.py``) runs it alone.
"""
from __future__ import annotations

import time
from pathlib import Path


def bench_spaceborne(n=64):
    """Space-borne sub-images per second: in-process, and through Dask with 1 and 2 workers."""
    import shutil
    import tempfile

    from salkit.params import load_scenario
    from salkit.stack import geo_base, nearest_squints, run_stack, subimage
    ex = Path(__file__).resolve().parents[1] / "examples" / "spaceborne_geo.yaml"
    base = geo_base(load_scenario(ex))
    sq = nearest_squints(n, 3.1, 2e5)
    subimage(base, 0.0, 0)
    t0 = time.perf_counter()
    for i, q in enumerate(sq[:16]):
        subimage(base, q, i)
    out = {"geo_subimages_per_s_in_process": 16 / (time.perf_counter() - t0)}
    for w in (1, 2):
        d = tempfile.mkdtemp()
        try:
            t0 = time.perf_counter()
            run_stack(base, sq, Path(d) / "s.zarr", workers=w)
            out[f"geo_subimages_per_s_dask_{w}_workers"] = n / (time.perf_counter() - t0)
        finally:
            shutil.rmtree(d, ignore_errors=True)
    out["geo_dask_speedup_2_over_1"] = out["geo_subimages_per_s_dask_2_workers"] / out["geo_subimages_per_s_dask_1_workers"]
    out["geo_full_collection_minutes_at_2_workers"] = 11288 / out["geo_subimages_per_s_dask_2_workers"] / 60
    return out


if __name__ == "__main__":
    import runner
    runner.main(["spaceborne"])
