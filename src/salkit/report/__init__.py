"""The report layer: after a workflow has computed, it writes every file of the run (datasets,
tables, figures, ``metrics.json``, ``scenario.yaml``) and lays out ``report.html``.

:func:`write_run` takes a :class:`~salkit.systems.result.RunResult`; :func:`run_scenario`
runs a scenario's workflow and writes it.
"""
from __future__ import annotations

import re
from datetime import datetime, timezone
from functools import lru_cache
from pathlib import Path

from jinja2 import Environment, PackageLoader, select_autoescape

from .. import __version__
from .. import tolerances as tol
from ..io.datasets import write_dataset, write_json_atomic, write_text_atomic
from ..io.runfolder import is_staging
from ..papers import published
from ..systems import run_workflow
from ..systems.result import Progress, RunResult
from ..params.scenario import dump_scenario
from ..units import display

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
                  page_warnings=list(page.get("warnings", ())), files=[])
    common.update(context)
    tpl = environment().get_template(template)
    html = tpl.render(**common)
    figures = dict(re.findall(r'<img src="([^"]+)" alt="([^"]*)"', html))
    common["files"] = file_rows(out_dir, result, figures)
    return write_text_atomic(Path(out_dir) / "report.html", tpl.render(**common))


def write_run(result: RunResult, out_dir: str | Path, *, command: str | None = None,
              index: str | None = None) -> dict:
    """Write everything a workflow computed into ``out_dir``: ``scenario.yaml``, the datasets
    (NetCDF) and tables (CSV), ``metrics.json``, the figures and ``report.html``, each atomically.

    Parameters
    ----------
    result : RunResult
    out_dir : path
    command : str, optional
        The command line shown on the report (default: the Python API).
    index : str, optional
        Relative link from the report to an index page of several runs.

    Returns
    -------
    dict
        The metrics written.
    """
    from .writers import WRITERS

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out / "scenario.yaml", result.scenario_text)
    for name, ds in result.datasets.items():
        write_dataset(ds, out / name)
    for name, text in result.tables.items():
        write_text_atomic(out / name, text)
    write_json_atomic(out / "metrics.json", result.metrics)
    WRITERS[result.system](result, out, {"command": command, "index": index})
    return result.metrics


def run_scenario(scenario, out_dir: str | Path, progress: Progress = None, *, command: str | None = None,
                 index: str | None = None) -> dict:
    """Run a scenario's workflow (:func:`salkit.systems.run_workflow`) and write it into
    ``out_dir`` (:func:`write_run`).

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
    out_dir : path
        Also the place of a workflow's checkpoints (the space-borne ``stack.zarr``).
    progress : callable, optional
        ``progress(stage, done, total)``.
    command, index : str, optional
        As :func:`write_run`.

    Returns
    -------
    dict
        The metrics.
    """
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    write_text_atomic(Path(out_dir) / "scenario.yaml", dump_scenario(scenario))  # what is running, first
    return write_run(run_workflow(scenario, out_dir, progress), out_dir, command=command, index=index)


def _fmt(v, unit_scale=1.0, digits=4):
    if v is None:
        return "-"
    try:
        return f"{float(v) * unit_scale:.{digits}g}"
    except (TypeError, ValueError):
        return str(v)


def comparison_rows(m: dict) -> list[dict]:
    """Measured-vs-theory rows with the acceptance tolerances of the test suite.

    Parameters
    ----------
    m : dict
        Metrics.

    Returns
    -------
    list of dict
        ``name``, ``measured``, ``theory``, ``delta``, ``ok`` (None where no rule applies: sidelobes
        of a target in speckle), ``tol`` (:mod:`salkit.tolerances`).
    """
    rows = []
    clutter = "image_snr" in m or bool(m.get("extended_scene"))  # sidelobes hold the scene, not only the response
    for ax in ("range", "azimuth"):
        irw, th = m.get(f"irw_{ax}_m"), m.get(f"irw_{ax}_theory_m")
        if irw is not None and th:
            r = irw / th
            rows.append(dict(name=f"IRW {ax} (cm)", measured=_fmt(irw, 100), theory=_fmt(th, 100),
                             delta=f"{r:.4f}", ok=abs(r - 1) <= tol.IRW_RATIO, tol=f"ratio 1 +- {tol.IRW_RATIO:g}"))
        p, pt = m.get(f"pslr_{ax}_db"), m.get(f"pslr_{ax}_theory_db")
        if p is not None and pt is not None:
            rows.append(dict(name=f"PSLR {ax} (dB)", measured=_fmt(p), theory=_fmt(pt), delta=f"{p - pt:+.3f}",
                             ok=None if clutter else abs(p - pt) <= tol.PSLR_DB,
                             tol="not tested: the scene around the target" if clutter else f"+- {tol.PSLR_DB:g} dB"))
        i, it = m.get(f"islr_{ax}_db"), m.get(f"islr_{ax}_theory_db")
        if i is not None and it is not None:
            rows.append(dict(name=f"ISLR {ax} (dB)", measured=_fmt(i), theory=_fmt(it), delta=f"{i - it:+.3f}",
                             ok=None if clutter else abs(i - it) <= tol.ISLR_DB,
                             tol="not tested: the scene around the target" if clutter else f"+- {tol.ISLR_DB:g} dB"))
        off = m.get(f"peak_offset_{ax}_m")
        res = m.get(f"resolution_{ax}_theory_m")
        if off is not None and res:
            rows.append(dict(name=f"peak offset {ax} (cells)", measured=_fmt(off / res), theory="0",
                             delta=f"{off / res:+.4f}", ok=abs(off / res) <= tol.PEAK_OFFSET_CELLS,
                             tol=f"+- {tol.PEAK_OFFSET_CELLS:g} cell"))
    pe = m.get("peak_phase_error_rad")
    if pe is not None:
        rows.append(dict(name="peak phase error (rad)", measured=_fmt(pe), theory="0", delta=f"{pe:+.4f}",
                         ok=abs(pe) <= tol.PEAK_PHASE_RAD, tol=f"+- {tol.PEAK_PHASE_RAD:g} rad"))
    if "cnr_peak" in m:
        r = m["cnr_peak"] / m["cnr_peak_theory"]
        rows.append(dict(name="brightest target CNR", measured=_fmt(m["cnr_peak"]), theory=_fmt(m["cnr_peak_theory"]),
                         delta=f"{r:.3f}", ok=abs(r - 1) <= tol.CNR_RATIO,
                         tol=f"ratio 1 +- {tol.CNR_RATIO:g} (one realisation)"))
    if "image_snr" in m:
        r = m["image_snr"] / m["image_snr_theory"]
        rows.append(dict(name="speckle image SNR", measured=_fmt(m["image_snr"]),
                         theory=_fmt(m["image_snr_theory"]), delta=f"{r:.3f}", ok=abs(r - 1) <= tol.SNR_RATIO,
                         tol=f"ratio 1 +- {tol.SNR_RATIO:g}"))
    return rows


def table3_cells(sweep) -> list[dict]:
    """Cell-by-cell comparison on Table 3: the paper's published ratio (fails below 1.5) beside
    salkit's reproduction of the paper's method and salkit's corrections (succeed when the range
    IRW is within 5 % of the ideal chirp's).

    Parameters
    ----------
    sweep : tuple
        (rows R2, columns R1, ratio grids, IRW grids) of :func:`salkit.systems.chirp.sweep`.

    Returns
    -------
    list of dict
    """
    rows_, cols_, grids, irws = sweep
    table3 = published()["seed002"]["table3"]
    out = []
    for i, r2 in enumerate(rows_):
        for j, r1 in enumerate(cols_):
            pub = table3["rows"].get(int(r2), None)
            pub_v = pub[table3["r1"].index(int(r1))] if pub is not None and int(r1) in table3["r1"] else None
            ideal = irws["ideal"][i, j]
            cell = {"r2": r2, "r1": r1, "published": pub_v,
                    "published_ok": None if pub_v is None else pub_v >= table3["failure_below"]}
            for m in ("paper", "deskew", "resample"):
                ratio = irws[m][i, j] / ideal
                cell[f"{m}_ratio"] = float(grids[m][i, j])
                cell[f"{m}_irw_over_ideal"] = float(ratio)
                cell[f"{m}_ok"] = bool(abs(ratio - 1) <= tol.CHIRP_IRW_OF_IDEAL)
            out.append(cell)
    return out




def downlooking_context(name, description, metrics, design, dist_rows, scenario_text) -> dict:
    """Template variables of the seed 000 report.

    Parameters
    ----------
    name, description : str
    metrics : dict
    design : DLDesign
    dist_rows : dict
    scenario_text : str

    Returns
    -------
    dict
    """
    point_rows = [(k, t) for k, t in (
        ("irw_range_m", "irw_range_theory_m"), ("irw_azimuth_m", "irw_azimuth_theory_m"),
        ("forward_irw_range_m", "irw_range_theory_m"), ("forward_irw_azimuth_m", "irw_azimuth_theory_m"),
        ("pslr_range_db", "pslr_range_theory_db"), ("pslr_azimuth_db", "pslr_azimuth_theory_db"),
        ("peak_offset_range_m", "peak_offset_range_theory_m"), ("peak_offset_azimuth_m", "peak_offset_azimuth_theory_m"),
        ("fringe_modulation_point", "fringe_modulation_point_theory"), ("fringe_period_m", "fringe_period_theory_m"))
        if k in metrics]
    rows = {k: {"label": v.get("label", k.replace("_", " ")), **v} for k, v in dist_rows.items()}
    return dict(name=name, description=description, m=metrics, d=design, warnings=design.warnings,
                point_rows=point_rows, dist_rows=rows, scenario=scenario_text)
