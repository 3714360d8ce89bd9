"""The index page of several runs (``results/index.html`` of ``make demo``): one card per run with
its headline figures of merit against theory or the paper, a pass/fail colour, a thumbnail, the
run time and a link to its report."""
from __future__ import annotations

from pathlib import Path

from .. import __version__
from .. import tolerances as tol
from ..io.datasets import write_text_atomic
from ..units import display
from . import environment

#: The figure shown on each kind of run's card, first found wins.
THUMBNAILS = ("image.png", "i_target.png", "stack.png", "table3.png", "image_point.png", "scene.png")


def _ratio_item(label: str, m: dict, key: str, ref: str, tolerance: float, what: str = "theory") -> dict | None:
    if key not in m or ref not in m or not m[ref]:
        return None
    r = m[key] / m[ref]
    return {"label": label, "measured": " ".join(display(key, m[key])).strip(),
            "reference": f"{what} {' '.join(display(ref, m[ref])).strip()}", "delta": f"ratio {r:.3f}",
            "ok": abs(r - 1) <= tolerance}


def headline(metrics: dict) -> list[dict]:
    """The headline figures of merit of a run, each against theory (or the paper), with whether it
    is within the test suite's tolerance (:mod:`salkit.tolerances`).

    Parameters
    ----------
    metrics : dict
        A run's ``metrics.json``.

    Returns
    -------
    list of dict
        ``label``, ``measured``, ``reference``, ``delta`` and ``ok`` (True, False, or None for a
        figure without a pass/fail rule).

    Examples
    --------
    >>> [h["ok"] for h in headline({"irw_range_m": 0.0179, "irw_range_theory_m": 0.0178})]
    [True]
    """
    m, items = metrics, []
    if "snr_stack" in m:  # space-borne GEO stack (seed 001)
        single = _ratio_item("single sub-image SNR", m, "snr_single", "snr_single_theory", tol.SNR_RATIO,
                             "eq 15 (uniform area)")
        if single is not None:  # eq 15 holds for a uniform area; the satellite's edges lower it (docs/spaceborne.md)
            single["ok"] = None
        items.append(single)
        if m.get("snr_single") and m.get("stack_count"):
            gain, want = m["snr_stack"] / m["snr_single"], m["stack_count"] ** 0.5
            items.append({"label": f"stack gain, {m['stack_count']} sub-images", "measured": f"{gain:.3g}",
                          "reference": f"sqrt(P) {want:.3g}", "delta": f"ratio {gain / want:.3f}",
                          "ok": abs(gain / want - 1) <= tol.SNR_RATIO})
        coh = sorted(int(k.split("_")[3]) for k in m if k.startswith("coherent_irw_azimuth_") and "theory" not in k)
        if coh:
            items.append(_ratio_item(f"coherent stack IRW, P = {coh[-1]}", m, f"coherent_irw_azimuth_{coh[-1]}_m",
                                     f"coherent_irw_azimuth_{coh[-1]}_theory_m", tol.IRW_RATIO,
                                     "0.886 lambda L0/(2 P L_sa)"))
    elif "A_resample_irw_m" in m:  # nonlinear chirp (seed 002)
        items += [_ratio_item("point A range IRW, resampling", m, "A_resample_irw_m", "A_ideal_irw_m",
                              tol.CHIRP_IRW_OF_IDEAL, "ideal chirp"),
                  _ratio_item("point A range IRW, paper's method", m, "A_paper_irw_m", "A_ideal_irw_m",
                              tol.CHIRP_IRW_OF_IDEAL, "ideal chirp")]
    elif "fringe_period_theory_m" in m:  # down-looking 3-D (seeds 000, 003)
        items += [_ratio_item("fringe period", m, "fringe_period_m", "fringe_period_theory_m", tol.FRINGE_PERIOD_RATIO,
                              "eq 25"),
                  _ratio_item("IRW across track", m, "irw_range_m", "irw_range_theory_m", tol.IRW_RATIO)]
    elif "medium_irw_azimuth_m" in m:  # turbulence (seed 004)
        items += [_ratio_item("turbulence-free azimuth IRW", m, "none_irw_azimuth_m", "none_irw_azimuth_theory_m",
                              tol.IRW_RATIO)]
        if "medium_pga_peak_ratio" in m:
            items.append({"label": "medium class peak, before / after PGA",
                          "measured": f"{m['medium_peak_ratio']:.2f} / {m['medium_pga_peak_ratio']:.2f}",
                          "reference": "turbulence-free 1", "delta": "", "ok": None})
    else:  # a plain scenario or an outside file
        items += [_ratio_item("range IRW", m, "irw_range_m", "irw_range_theory_m", tol.IRW_RATIO),
                  _ratio_item("azimuth IRW", m, "irw_azimuth_m", "irw_azimuth_theory_m", tol.IRW_RATIO)]
        if "pslr_range_db" in m and "pslr_range_theory_db" in m:
            d = m["pslr_range_db"] - m["pslr_range_theory_db"]
            clutter = "image_snr" in m or bool(m.get("extended_scene"))
            items.append({"label": "range PSLR" + (" (target in a scene)" if clutter else ""),
                          "measured": f"{m['pslr_range_db']:.2f} dB",
                          "reference": f"theory {m['pslr_range_theory_db']:.2f} dB", "delta": f"{d:+.2f} dB",
                          "ok": None if clutter else abs(d) <= tol.PSLR_DB})
    return [i for i in items if i is not None]


def passed(items: list[dict]) -> bool | None:
    """Whether every headline with a rule passed (None when none has one).

    Parameters
    ----------
    items : list of dict
        From :func:`headline`.

    Returns
    -------
    bool or None
    """
    rules = [i["ok"] for i in items if i["ok"] is not None]
    return all(rules) if rules else None


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
        thumb = next((f"{r['name']}/{t}" for t in THUMBNAILS if (out / r["name"] / t).is_file()), None)
        cards.append({**r, "items": items, "ok": passed(items), "thumb": thumb})
    html = environment().get_template("index.html").render(cards=cards, version=__version__,
                                                           n_ok=sum(c["ok"] is True for c in cards),
                                                           n_bad=sum(c["ok"] is False for c in cards))
    return write_text_atomic(out / "index.html", html)
