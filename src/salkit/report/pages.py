"""The pages of a run: the Jinja environment of the templates, the Files section (what each file
holds, its size), the metrics table with units, and :func:`render`, which lays out ``report.html``."""
from __future__ import annotations

import re
from datetime import datetime, timezone
from functools import lru_cache
from pathlib import Path

from jinja2 import Environment, PackageLoader, select_autoescape

from .. import __version__
from ..io.writing import write_text_atomic
from ..io.runfolder import is_staging
from ..systems.result import RunResult
from ..units import display
from .judge import VERDICTS, headline, verdict

#: What the files every run may write hold (datasets, tables and figures describe themselves).
FILE_NOTES = {
    "scenario.yaml": "the resolved scenario, every default filled in: salkit run scenario.yaml repeats the run",
    "metrics.json": "every figure of merit, full precision, SI units named in each key",
    "manifest.json": "size and SHA-256 of every file, written when the run completed (salkit verify)",
    "report.html": "this page",
    "stack.zarr": "checkpoint of the sub-image stack (Zarr), kept so that an interrupted run resumes",
}


#: Default command shown on a page written from Python rather than the command line.
API_COMMAND = "Python API (salkit.report.write_run)"


@lru_cache(maxsize=1)
def environment() -> Environment:
    """The Jinja environment of the report templates (one for every report).

    Returns
    -------
    jinja2.Environment
    """
    env = Environment(loader=PackageLoader("salkit", "report/templates"), autoescape=select_autoescape(["html"]))
    env.filters["q"] = lambda v, name="", digits=4: " ".join(x for x in display(name, v, digits) if x)
    env.globals["zip"] = zip
    return env


def human_size(n: int) -> str:
    """A byte count as B, kB, MB or GB (powers of 1000).

    Parameters
    ----------
    n : int
        Bytes.

    Returns
    -------
    str

    Examples
    --------
    >>> human_size(512), human_size(2_345_678)
    ('512 B', '2.3 MB')
    """
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= scale:
            return f"{n / scale:.1f} {unit}"
    return f"{n} B"


def describe_dataset(ds) -> str:
    """One line on what a dataset holds: each variable's type and dimensions with sizes.

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    str
    """
    parts = []
    for k, v in list(ds.data_vars.items())[:6]:
        dims = " x ".join(f"{d} {ds.sizes[d]}" for d in v.dims)
        parts.append(f"{k} ({v.dtype}{', ' + dims if dims else ''})")
    more = f" and {len(ds.data_vars) - 6} more" if len(ds.data_vars) > 6 else ""
    return "NetCDF: " + "; ".join(parts) + more + "; coordinates in m and s, parameters as attributes"


def _size(p: Path) -> int:
    if p.is_dir():
        return sum(f.stat().st_size for f in p.rglob("*") if f.is_file())
    return p.stat().st_size


def file_rows(out_dir: str | Path, result: RunResult, figures: dict) -> list[dict]:
    """The Files section of a report: every file of the run folder with its size and what it
    holds, the report itself and, in a run folder being staged, the manifest written after it.

    Parameters
    ----------
    out_dir : path
    result : RunResult
    figures : dict
        Figure file -> its caption (the alt text of the page's images).

    Returns
    -------
    list of dict
        ``name``, ``link`` (folders end in /), ``size``, ``what``.
    """
    out = Path(out_dir)
    rows = []
    names = {p.name: p for p in out.iterdir() if not p.name.startswith(".")}
    later = {"report.html"} | ({"manifest.json"} if is_staging(out) else set())  # written after this page
    for name in sorted(set(names) | later):
        p = names.get(name)
        if name in result.datasets:
            what = describe_dataset(result.datasets[name])
        elif name in result.tables:
            cols = result.tables[name].splitlines()[0].split(",") if result.tables[name] else []
            what = "table (CSV): " + ", ".join(cols[:8]) + (", ..." if len(cols) > 8 else "")
        elif name in figures:
            what = "figure: " + figures[name]
        else:
            what = FILE_NOTES.get(name, "")
        link = name + "/" if p is not None and p.is_dir() else name
        rows.append({"name": name, "link": link, "size": human_size(_size(p)) if p is not None else "-",
                     "what": what})
    return rows


def metric_rows(metrics: dict) -> list[tuple[str, str, str]]:
    """The metrics as (name, value, unit), rounded to 4 significant digits, lengths in a unit
    that keeps them between 1 and 1000 (:func:`salkit.units.display`).

    Parameters
    ----------
    metrics : dict

    Returns
    -------
    list of tuple
    """
    return [(k, *display(k, v)) for k, v in metrics.items()]


def render(out_dir: str | Path, template: str, result: RunResult, page: dict | None = None, **context) -> Path:
    """Render ``template`` (which extends ``base.html``) into ``out_dir/report.html``, atomically,
    with what every page shows: version, command line, metrics with units, the Files section and
    the resolved scenario.

    Parameters
    ----------
    out_dir : path
    template : str
        A file of ``salkit/report/templates``.
    result : RunResult
    page : dict, optional
        ``command`` (the command line that made the run), ``index`` (relative link to the index
        page, if there is one), ``warnings`` (to show at the top).
    **context
        The template's own variables.

    Returns
    -------
    Path
    """
    page = page or {}
    common = dict(name=result.name, description=result.description, version=__version__,
                  command=page.get("command") or API_COMMAND, index=page.get("index"),
                  created=datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                  metric_rows=metric_rows(result.metrics), scenario=result.scenario_text, metrics=result.metrics,
                  page_warnings=list(page.get("warnings", ())), files=[],
                  headline=[{**i, "verdict": verdict(i["ok"])} for i in headline(result.metrics)],
                  verdicts=list(VERDICTS.values()))
    common.update(context)
    tpl = environment().get_template(template)
    html = tpl.render(**common)
    figures = dict(re.findall(r'<img src="([^"]+)" alt="([^"]*)"', html))
    common["files"] = file_rows(out_dir, result, figures)
    return write_text_atomic(Path(out_dir) / "report.html", tpl.render(**common))
