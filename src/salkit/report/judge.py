"""Measured against theory, judged in one place: the ratio and difference rules with the test
suite's tolerances (:mod:`salkit.tolerances`), used by the report's comparison table
(:func:`comparison_rows`), by the index page's and the sweep's headline figures (:func:`headline`) and
by the command line, with one vocabulary of verdicts (:data:`VERDICTS`)."""
from __future__ import annotations

from .. import tolerances as tol
from ..units import display


#: Every verdict a figure, a table row or a card can have, one vocabulary for the command line, the
#: report, the index card and the sweep card: the CSS class, the word printed beside the figure, the
#: colour and the legend's words. ``None`` is a figure no theory predicts here; it always carries the
#: reason (``why``).
VERDICTS = {
    True: {"css": "pass", "word": "ok", "colour": "green", "legend": "within the test suite's tolerance"},
    False: {"css": "fail", "word": "outside tolerance", "colour": "red", "legend": "outside the test suite's tolerance"},
    None: {"css": "na", "word": "not judged", "colour": "grey",
           "legend": "no theory predicts this figure here (the reason is given beside it)"},
}

#: Why a target's sidelobes in a scene are not judged.
CLUTTER_WHY = ("the target sits in a speckled scene: the highest level within +-10 cells of it is the scene's "
               "speckle, not the target's sidelobe, so a point target's PSLR and ISLR theory does not apply")


def verdict(ok: bool | None) -> dict:
    """The words and colours of a verdict (:data:`VERDICTS`).

    Parameters
    ----------
    ok : bool or None

    Returns
    -------
    dict

    Examples
    --------
    >>> verdict(None)["word"]
    'not judged'
    """
    return VERDICTS[None if ok is None else bool(ok)]


#: Metric name prefixes of a sweep judged against their theory at the worst point, and the tolerance
#: of |median / theory - 1| (the same as a single run's).
SWEEP_RULES = {"irw_": tol.IRW_RATIO, "image_snr": tol.SNR_RATIO, "snr_": tol.SNR_RATIO}


#: Why an IRW is not judged in a scene without point targets.
NO_TARGET_WHY = ("no point target in the scene: the brightest pixel is the scene's speckle, whose width is not the "
                 "system's IRW")


def no_target(m: dict) -> bool:
    """Whether a run measured a speckled scene without point targets (its IRWs are a speckle's).

    Parameters
    ----------
    m : dict
        Metrics.

    Returns
    -------
    bool
    """
    return bool(m.get("extended_scene")) and "target_index" not in m


def in_clutter(m: dict) -> bool:
    """Whether the measured target sits in a scene (speckle or other scatterers): its sidelobes then
    hold the scene as well as the response, and PSLR and ISLR have no pass/fail rule.

    Parameters
    ----------
    m : dict
        Metrics.

    Returns
    -------
    bool
    """
    return "image_snr" in m or bool(m.get("extended_scene"))


def ratio_rule(measured: float, theory: float, tolerance: float) -> tuple[float, bool]:
    """A figure judged by its ratio to theory: ``|measured / theory - 1| <= tolerance``.

    Parameters
    ----------
    measured, theory : float
        In the same unit; ``theory`` non-zero.
    tolerance : float
        Dimensionless.

    Returns
    -------
    (float, bool)
        The ratio and whether it passes.

    Examples
    --------
    >>> ratio_rule(0.0179, 0.0178, 0.05)
    (1.0056179775280898, True)
    """
    r = measured / theory
    return r, abs(r - 1) <= tolerance


def difference_rule(measured: float, theory: float, tolerance: float, applies: bool = True) -> tuple[float, bool | None]:
    """A figure judged by its difference from theory (dB, cells, rad): ``|measured - theory| <= tolerance``.

    Parameters
    ----------
    measured, theory : float
        In the same unit.
    tolerance : float
        In that unit.
    applies : bool
        False where no rule applies (sidelobes of a target in a scene): the verdict is None.

    Returns
    -------
    (float, bool or None)
        The difference and the verdict.
    """
    d = measured - theory
    return d, (abs(d) <= tolerance if applies else None)


def _fmt(v, unit_scale=1.0, digits=4):
    """A number for a table cell: ``digits`` significant figures after scaling, '-' for None."""
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
    clutter = in_clutter(m)
    scene_note = "not judged"
    for ax in ("range", "azimuth"):
        irw, th = m.get(f"irw_{ax}_m"), m.get(f"irw_{ax}_theory_m")
        if irw is not None and th:
            r, ok = ratio_rule(irw, th, tol.IRW_RATIO)
            rows.append(dict(name=f"IRW {ax} (cm)", measured=_fmt(irw, 100), theory=_fmt(th, 100),
                             delta=f"{r:.4f}", ok=None if no_target(m) else ok,
                             tol=f"{scene_note}: {NO_TARGET_WHY}" if no_target(m) else f"ratio 1 +- {tol.IRW_RATIO:g}"))
        for what, tolerance in (("pslr", tol.PSLR_DB), ("islr", tol.ISLR_DB)):
            v, vt = m.get(f"{what}_{ax}_db"), m.get(f"{what}_{ax}_theory_db")
            if v is not None and vt is not None:
                d, ok = difference_rule(v, vt, tolerance, applies=not clutter)
                rows.append(dict(name=f"{what.upper()} {ax} (dB)", measured=_fmt(v), theory=_fmt(vt),
                                 delta=f"{d:+.3f}", ok=ok, tol=f"{scene_note}: {CLUTTER_WHY}" if clutter
                                 else f"+- {tolerance:g} dB"))
        off = m.get(f"peak_offset_{ax}_m")
        res = m.get(f"resolution_{ax}_theory_m")
        if off is not None and res:
            d, ok = difference_rule(off / res, 0.0, tol.PEAK_OFFSET_CELLS)
            rows.append(dict(name=f"peak offset {ax} (cells)", measured=_fmt(off / res), theory="0",
                             delta=f"{d:+.4f}", ok=ok, tol=f"+- {tol.PEAK_OFFSET_CELLS:g} cell"))
    pe = m.get("peak_phase_error_rad")
    if pe is not None:
        d, ok = difference_rule(pe, 0.0, tol.PEAK_PHASE_RAD)
        rows.append(dict(name="peak phase error (rad)", measured=_fmt(pe), theory="0", delta=f"{d:+.4f}",
                         ok=ok, tol=f"+- {tol.PEAK_PHASE_RAD:g} rad"))
    if "cnr_peak" in m:
        r, ok = ratio_rule(m["cnr_peak"], m["cnr_peak_theory"], tol.CNR_RATIO)
        rows.append(dict(name="brightest target CNR", measured=_fmt(m["cnr_peak"]), theory=_fmt(m["cnr_peak_theory"]),
                         delta=f"{r:.3f}", ok=ok, tol=f"ratio 1 +- {tol.CNR_RATIO:g} (one realisation)"))
    if "strehl_at_target_theory" in m:  # one draw of a random quantity: its ensemble mean is what theory gives
        rows.append(dict(name="intensity at target / turbulence-free", measured=_fmt(m["strehl_at_target"]),
                         theory=_fmt(m["strehl_at_target_theory"]),
                         delta=f"{m['strehl_at_target'] / m['strehl_at_target_theory']:.3f}", ok=None,
                         tol="not judged: one realisation of the screens (the theory is the ensemble mean; "
                             "salkit sweep --realisations N)"))
    if "peak_power_loss_theory" in m:  # one draw of the laser's phase noise, as above
        rows.append(dict(name="intensity at target / coherent laser", measured=_fmt(m["peak_power_loss"]),
                         theory=_fmt(m["peak_power_loss_theory"]),
                         delta=f"{m['peak_power_loss'] / m['peak_power_loss_theory']:.3f}", ok=None,
                         tol="not judged: one realisation of the phase noise (the theory, exp(-sigma^2), is the "
                             "ensemble mean; salkit sweep --realisations N)"))
    if "image_snr" in m:
        r, ok = ratio_rule(m["image_snr"], m["image_snr_theory"], tol.SNR_RATIO)
        rows.append(dict(name="speckle image SNR", measured=_fmt(m["image_snr"]),
                         theory=_fmt(m["image_snr_theory"]), delta=f"{r:.3f}", ok=ok,
                         tol=f"ratio 1 +- {tol.SNR_RATIO:g}"))
    return rows


def _ratio_item(label: str, m: dict, key: str, ref: str, tolerance: float, what: str = "theory") -> dict | None:
    """A headline judged by :func:`ratio_rule` (None when the metrics lack it)."""
    if key not in m or ref not in m or not m[ref]:
        return None
    r, ok = ratio_rule(m[key], m[ref], tolerance)
    return {"label": label, "measured": " ".join(display(key, m[key])).strip(),
            "reference": f"{what} {' '.join(display(ref, m[ref])).strip()}", "delta": f"ratio {r:.3f}", "ok": ok}


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
        figure no theory predicts here, which then has ``why``). A target in a scene has no PSLR
        headline (:data:`CLUTTER_WHY`); the report's table keeps it, not judged, with the reason.

    Examples
    --------
    >>> [h["ok"] for h in headline({"irw_range_m": 0.0179, "irw_range_theory_m": 0.0178})]
    [True]
    """
    m, items = metrics, []
    if "sweep_points" in m:  # a design study: how many points ran, each metric's worst point against theory
        n_real = m["sweep_realisations"]
        reals = f"{n_real} realisation{'s' if n_real != 1 else ''}"
        items.append({"label": "points run", "measured": f"{m['sweep_points_ok']} of {m['sweep_points']}",
                      "reference": f"x {reals}", "delta": "",
                      "ok": m["sweep_points_ok"] == m["sweep_points"] - m.get("sweep_points_invalid", 0)})
        for k in sorted(k for k in m if k.endswith("_over_theory_max_deviation")):
            name = k[: -len("_over_theory_max_deviation")]
            stat = m.get(f"{name}_theory_statistic", "median")
            rule = SWEEP_RULES.get(next((p for p in SWEEP_RULES if name.startswith(p)), ""), None)
            item = {"label": f"{name}, worst point", "measured": f"{100 * m[k]:.2f} % from theory",
                    "reference": f"{stat} of {reals} against theory's {stat}", "delta": ""}
            se = m.get(f"{name}_over_theory_max_deviation_se")
            if stat == "mean" and se is not None and n_real > 1:  # a Monte Carlo mean: within 3 standard errors
                item["delta"] = f"3 s.e. {300 * se:.1f} %"
                item["ok"] = m[k] <= 3 * se
            elif m.get("sweep_perturbed"):
                item["ok"], item["why"] = None, ("turbulence or a phase error perturbs the image; this theory is "
                                                 "the unperturbed limit")
            elif rule is None:
                item["ok"], item["why"] = None, "no tolerance is set for this figure in a sweep"
            else:
                item["ok"] = m[k] <= rule
            items.append(item)
        for k in sorted(k for k in m if k.endswith("_minus_theory_max_db")):
            name = k[: -len("_minus_theory_max_db")]
            tolerance = tol.PSLR_DB if name.startswith("pslr") else (tol.ISLR_DB if name.startswith("islr") else None)
            item = {"label": f"{name}, worst point", "measured": f"{m[k]:.2f} dB from theory",
                    "reference": f"median of {reals} against theory", "delta": ""}
            if tolerance is None:
                item["ok"], item["why"] = None, "no tolerance is set for this figure in a sweep"
            elif m.get("sweep_perturbed"):
                item["ok"], item["why"] = None, ("turbulence or a phase error perturbs the image; this theory is "
                                                 "the unperturbed limit")
            elif m.get("sweep_in_clutter"):
                item["ok"], item["why"] = None, CLUTTER_WHY
            else:
                item["ok"] = m[k] <= tolerance
            items.append(item)
        return items
    if "snr_stack" in m:  # space-borne GEO stack (seed 001)
        single = _ratio_item("single sub-image SNR", m, "snr_single", "snr_single_theory", tol.SNR_RATIO,
                             "eq 15 (uniform area)")
        if single is not None:  # eq 15 holds for a uniform area; the satellite's edges lower it (docs/spaceborne.md)
            single["ok"], single["why"] = None, ("eq 15 is for a uniform area of unit reflectance; a 3-D model's faces "
                                                 "pile into the image cells (more photons a cell)"
                                                 if m.get("stack_model_3d") else
                                                 "eq 15 holds for a uniform area; the satellite's edges lower it")
        items.append(single)
        if m.get("snr_single") and m.get("stack_count"):
            gain, want = m["snr_stack"] / m["snr_single"], m["stack_count"] ** 0.5
            r, ok = ratio_rule(gain, want, tol.SNR_RATIO)
            items.append({"label": f"stack gain, {m['stack_count']} sub-images", "measured": f"{gain:.3g}",
                          "reference": f"sqrt(P) {want:.3g}", "delta": f"ratio {r:.3f}", "ok": ok})
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
                          "reference": "turbulence-free 1", "delta": "", "ok": None,
                          "why": "one realisation of the screens; theory gives ensemble figures (salkit sweep)"})
    else:  # a plain scenario or an outside file
        irws = [_ratio_item("range IRW", m, "irw_range_m", "irw_range_theory_m", tol.IRW_RATIO),
                _ratio_item("azimuth IRW", m, "irw_azimuth_m", "irw_azimuth_theory_m", tol.IRW_RATIO)]
        if no_target(m):
            for i in irws:
                if i is not None:
                    i["ok"], i["why"] = None, NO_TARGET_WHY
        items += irws
        if "pslr_range_db" in m and "pslr_range_theory_db" in m and not in_clutter(m):  # judge what theory predicts
            d, ok = difference_rule(m["pslr_range_db"], m["pslr_range_theory_db"], tol.PSLR_DB)
            items.append({"label": "range PSLR", "measured": f"{m['pslr_range_db']:.2f} dB",
                          "reference": f"theory {m['pslr_range_theory_db']:.2f} dB", "delta": f"{d:+.2f} dB",
                          "ok": ok})
    items = [i for i in items if i is not None]
    for i in items:
        i["ok"] = None if i["ok"] is None else bool(i["ok"])  # numpy's bools too: one vocabulary
        if i["ok"] is None:
            i.setdefault("why", "no pass/fail rule for this figure")
    return items


def not_within(cards: list[dict]) -> list[str]:
    """Names of the cards that are not within tolerance (outside, or with nothing judged).

    Parameters
    ----------
    cards : list of dict
        ``name`` and ``ok`` (:func:`passed`).

    Returns
    -------
    list of str
    """
    return [c["name"] for c in cards if c["ok"] is not True]


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
