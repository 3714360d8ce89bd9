"""The HTML report: a thin layer that lays out figures, metrics and the scenario."""
from __future__ import annotations

from pathlib import Path

from jinja2 import Environment, PackageLoader, select_autoescape

from ..io.datasets import write_text_atomic


def _fmt(v, unit_scale=1.0, digits=4):
    if v is None:
        return "-"
    try:
        return f"{float(v) * unit_scale:.{digits}g}"
    except (TypeError, ValueError):
        return str(v)


def comparison_rows(m: dict) -> list[dict]:
    """Measured-vs-theory rows with the acceptance tolerances of the test suite."""
    rows = []
    for ax in ("range", "azimuth"):
        irw, th = m.get(f"irw_{ax}_m"), m.get(f"irw_{ax}_theory_m")
        if irw is not None and th:
            r = irw / th
            rows.append(dict(name=f"IRW {ax} (cm)", measured=_fmt(irw, 100), theory=_fmt(th, 100),
                             delta=f"{r:.4f}", ok=abs(r - 1) <= 0.03, tol="ratio 1 +- 0.03"))
        p, pt = m.get(f"pslr_{ax}_db"), m.get(f"pslr_{ax}_theory_db")
        if p is not None and pt is not None:
            rows.append(dict(name=f"PSLR {ax} (dB)", measured=_fmt(p), theory=_fmt(pt),
                             delta=f"{p - pt:+.3f}", ok=abs(p - pt) <= 0.3, tol="+- 0.3 dB"))
        i, it = m.get(f"islr_{ax}_db"), m.get(f"islr_{ax}_theory_db")
        if i is not None and it is not None:
            rows.append(dict(name=f"ISLR {ax} (dB)", measured=_fmt(i), theory=_fmt(it),
                             delta=f"{i - it:+.3f}", ok=abs(i - it) <= 1.0, tol="+- 1 dB"))
        off = m.get(f"peak_offset_{ax}_m")
        res = m.get(f"resolution_{ax}_theory_m")
        if off is not None and res:
            rows.append(dict(name=f"peak offset {ax} (cells)", measured=_fmt(off / res), theory="0",
                             delta=f"{off / res:+.4f}", ok=abs(off / res) <= 0.1, tol="+- 0.1 cell"))
    pe = m.get("peak_phase_error_rad")
    if pe is not None:
        rows.append(dict(name="peak phase error (rad)", measured=_fmt(pe), theory="0", delta=f"{pe:+.4f}",
                         ok=abs(pe) <= 0.05, tol="+- 0.05 rad"))
    if "cnr_peak" in m:
        r = m["cnr_peak"] / m["cnr_peak_theory"]
        rows.append(dict(name="brightest target CNR", measured=_fmt(m["cnr_peak"]), theory=_fmt(m["cnr_peak_theory"]),
                         delta=f"{r:.3f}", ok=abs(r - 1) <= 0.15, tol="ratio 1 +- 0.15 (one realisation)"))
    if "image_snr" in m:
        r = m["image_snr"] / m["image_snr_theory"]
        rows.append(dict(name="speckle image SNR", measured=_fmt(m["image_snr"]),
                         theory=_fmt(m["image_snr_theory"]), delta=f"{r:.3f}", ok=abs(r - 1) <= 0.1,
                         tol="ratio 1 +- 0.1"))
    return rows


def write_report(out_dir: str | Path, context: dict) -> Path:
    """Render ``report.html`` into ``out_dir`` (atomically) from a context dict."""
    env = Environment(loader=PackageLoader("salkit", "report/templates"),
                      autoescape=select_autoescape(["html"]))
    html = env.get_template("report.html").render(**context)
    return write_text_atomic(Path(out_dir) / "report.html", html)


def write_turbulence_report(out_dir, scenario, rows, metrics) -> Path:
    """report.html of the seed 004 experiment."""
    from ..params.scenario import dump_scenario
    env = Environment(loader=PackageLoader("salkit", "report/templates"), autoescape=select_autoescape(["html"]))
    html = env.get_template("turbulence.html").render(name=scenario.name, description=scenario.description,
                                                      rows=rows, metrics=metrics, scenario=dump_scenario(scenario))
    return write_text_atomic(Path(out_dir) / "report.html", html)


PAPER_TABLE1 = {"A": (4.2846, 1.1685, 3.667), "B": (3.1, 1.558, 1.9375), "C": (3.1, 1.558, 1.9375)}


def write_chirp_report(out_dir, scenario, table1, sweeps, metrics) -> Path:
    """report.html of the seed 002 experiment."""
    from ..params.scenario import dump_scenario
    env = Environment(loader=PackageLoader("salkit", "report/templates"), autoescape=select_autoescape(["html"]))
    html = env.get_template("chirp.html").render(name=scenario.name, description=scenario.description,
                                                 table1=table1, paper=PAPER_TABLE1, metrics=metrics,
                                                 scenario=dump_scenario(scenario))
    return write_text_atomic(Path(out_dir) / "report.html", html)
