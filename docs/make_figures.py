"""``make docs-figures``: run every example, copy the figures into docs/images and rewrite the
README's generated blocks (captions with their numbers, the files each example writes, the table
of formers) from that run, and docs/metrics.md's table of metrics from the declarations. ``--results DIR`` reuses a finished ``make demo`` folder instead of running again."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--results", default=None, help="an existing make demo folder (default: run into results/)")
    args = ap.parse_args(argv)
    from salkit.io.writing import write_text_atomic
    from salkit.report.docs import blocks, copy_figures, fill
    results = Path(args.results) if args.results else ROOT / "results"
    if args.results is None:
        from salkit.cli.demo import main as demo
        if demo(["--out", str(results)]) != 0:
            return 2
    for p in copy_figures(results, ROOT / "docs" / "images"):
        print(f"wrote {p.relative_to(ROOT)}")
    readme = ROOT / "README.md"
    write_text_atomic(readme, fill(readme.read_text(), blocks(results)))
    print(f"rewrote the generated blocks of {readme.relative_to(ROOT)}")
    from salkit.report.docs import declared_blocks
    table = ROOT / "docs" / "metrics.md"
    write_text_atomic(table, fill(table.read_text(), declared_blocks()))
    print(f"rewrote the generated blocks of {table.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
