"""``make demo``: run every shipped example and sweep (``examples/sweeps/``) and leave their reports
under ``results/``.

Examples that are long at full scale run a documented smaller configuration here (``DEMO_SETS``);
the full one stays one command away: ``salkit run examples/NAME.yaml --out DIR``.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from ..errors import SalkitError
from ..io.runfolder import RunFolder

# name -> overrides applied in the demo only (none needed yet: every example runs in seconds)
DEMO_SETS: dict[str, list[str]] = {
    # the full collection is 11,288 sub-images; the demo stacks the 64 nearest closest approach, in
    # this process: a local cluster's start (about 8 s on 2 cores) takes longer than these stacks
    "spaceborne_geo": ["stack.max_subimages=64", "stack.workers=0"],
    "satellite_geo": ["stack.max_subimages=16", "stack.workers=0"],
}
#: sweep name -> realisations in the demo (the full study stays one command away:
#: ``salkit sweep examples/sweeps/NAME.yaml --out DIR``, on a local Dask cluster). The demo runs
#: its sweeps in this process: on a small machine a cluster's start costs more than it saves here.
DEMO_SWEEP_REALISATIONS: dict[str, int] = {"turbulence_cn2": 4, "geo_snr_vs_photons": 2}


def main(argv=None) -> int:
    """Run every shipped example into ``--out`` (default results/) and write an index page.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0, or 2 for bad input.
    """
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="results")
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--sweep-realisations", type=int, default=None,
                    help="realisations of every shipped sweep (default: DEMO_SWEEP_REALISATIONS, else the file's)")
    args = ap.parse_args(argv)
    from ..params import load_scenario
    from ..report import run_scenario
    from ..report.index import write_index
    from ..report.sweeps import CHECKPOINT, run_sweep
    from ..systems.study import prepare
    from ..studies.spec import resolve_request
    from .app import _Bar, show_warning
    from .options import _examples_dir, print_headline
    import warnings
    warnings.showwarning = show_warning

    out = Path(args.out)

    def example(f: Path):
        sets = DEMO_SETS.get(f.stem, [])
        sc = load_scenario(f, sets)
        command = " ".join(["salkit run", f"examples/{f.name}", "--out", str(out / f.stem), *(f"--set {x}" for x in sets)])
        with RunFolder(out / f.stem, overwrite=True, keep_on_failure=("stack.zarr",)) as tmp, _Bar() as bar:
            return sc.description, run_scenario(sc, tmp, progress=bar, command=command, index="../index.html")

    def study(f: Path):
        request = resolve_request(f, realisations=args.sweep_realisations or DEMO_SWEEP_REALISATIONS.get(f.stem))
        sc, plan, invalid = prepare(request)
        command = " ".join(["salkit sweep", f"examples/sweeps/{f.name}", "--out", str(out / f"sweep_{f.stem}"), "--workers 0"]
                           + ([f"--realisations {request.realisations}"]
                              if args.sweep_realisations or f.stem in DEMO_SWEEP_REALISATIONS else []))
        with RunFolder(out / f"sweep_{f.stem}", overwrite=True, keep_on_failure=(CHECKPOINT,)) as tmp, _Bar() as bar:
            return request.description, run_sweep(sc, plan, invalid, tmp, workers=0, progress=bar,
                                                   name=request.name, description=request.description or None,
                                                   index="../index.html", command=command)

    jobs = [(f.stem, f, example) for f in sorted(_examples_dir().glob("*.yaml"))]
    jobs += [(f"sweep_{f.stem}", f, study) for f in sorted((_examples_dir() / "sweeps").glob("*.yaml"))]
    runs = []
    for name, f, job in jobs:
        if args.only and name not in args.only:
            continue
        print(f"== {name}", flush=True)
        t0 = time.perf_counter()
        try:
            description, m = job(f)
        except SalkitError as e:
            print(f"error: {e}", file=sys.stderr)
            return 2
        dt = time.perf_counter() - t0
        runs.append({"name": name, "description": description, "seconds": dt, "metrics": m})
        print(f"   {dt:.1f} s", flush=True)
        print_headline(m)
    write_index(out, runs)
    print(f"reports: {out / 'index.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
