"""The index page of several runs (``results/index.html`` of ``make demo``): one card per run with
its headline figures of merit against theory or the paper, a pass/fail colour, a thumbnail, the
run time and a link to its report."""
from __future__ import annotations

from pathlib import Path

from .. import __version__
from ..io.writing import write_text_atomic
from .judge import VERDICTS, headline, passed, verdict
from .pages import environment

#: The figure shown on each kind of run's card, first found wins.
THUMBNAILS = ("image.png", "i_target.png", "stack.png", "table3.png", "image_point.png", "scene.png")

__all__ = ["THUMBNAILS", "headline", "passed", "write_index"]


def write_index(out_dir: str | Path, runs: list[dict]) -> Path:
    """Write ``out_dir/index.html``: a card per run.

    Parameters
    ----------
    out_dir : path
        The folder holding one sub-folder per run.
    runs : list of dict
        ``name`` (the sub-folder), ``description``, ``seconds`` (run time) and ``metrics``.

    Returns
    -------
    Path
    """
    out = Path(out_dir)
    cards = []
    for r in runs:
        items = headline(r["metrics"])
        found = [t for t in THUMBNAILS if (out / r["name"] / t).is_file()]
        found += sorted(p.name for p in (out / r["name"]).glob("sweep_*.png"))  # a sweep's first figure
        thumb = f"{r['name']}/{found[0]}" if found else None
        for i in items:
            i["verdict"] = verdict(i["ok"])
        ok = passed(items)
        cards.append({**r, "items": items, "ok": ok, "verdict": verdict(ok), "thumb": thumb})
    counts = [(VERDICTS[k], [c["name"] for c in cards if c["ok"] is k]) for k in (True, False, None)]
    html = environment().get_template("index.html").render(cards=cards, version=__version__, counts=counts,
                                                           verdicts=list(VERDICTS.values()))
    return write_text_atomic(out / "index.html", html)
