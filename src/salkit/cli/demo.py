"""``make demo``: run every shipped example and leave their reports under ``results/``.

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
    # the full collection is 11,288 sub-images; the demo stacks the 64 nearest closest approach
    "spaceborne_geo": ["stack.max_subimages=64"],
}


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
    args = ap.parse_args(argv)
    from ..params import load_scenario
    from ..report import run_scenario
    from ..report.index import write_index
    from .app import _Bar, show_warning
    from .options import _examples_dir, print_headline
    import warnings
    warnings.showwarning = show_warning

    out = Path(args.out)
    runs = []
    for f in sorted(_examples_dir().glob("*.yaml")):
        name = f.stem
        if args.only and name not in args.only:
            continue
        print(f"== {name}", flush=True)
        t0 = time.perf_counter()
        sets = DEMO_SETS.get(name, [])
        command = " ".join(["salkit run", f"examples/{f.name}", "--out", str(out / name),
                            *(f"--set {x}" for x in sets)])
        try:
            sc = load_scenario(f, sets)
            with RunFolder(out / name, overwrite=True, keep_on_failure=("stack.zarr",)) as tmp, _Bar() as bar:
                m = run_scenario(sc, tmp, progress=bar, command=command, index="../index.html")
        except SalkitError as e:
            print(f"error: {e}", file=sys.stderr)
            return 2
        dt = time.perf_counter() - t0
        runs.append({"name": name, "description": sc.description, "seconds": dt, "metrics": m})
        print(f"   {dt:.1f} s", flush=True)
        print_headline(m)
    write_index(out, runs)
    print(f"reports: {out / 'index.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
