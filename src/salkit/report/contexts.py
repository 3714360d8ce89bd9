"""Template variables of the seed systems' report pages: Table 3 of seed 002 cell by cell, the
down-looking page of seeds 000/003."""
from __future__ import annotations

from .. import tolerances as tol
from ..papers import published


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
