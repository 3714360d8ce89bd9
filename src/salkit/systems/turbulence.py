"""Seed 004: SAL through atmospheric turbulence, polar format imaging, phase gradient autofocus.

For each turbulence class (Cn^2) a point target and an "I" made of point targets are simulated
through the same frozen 50-layer path (screens of one seed, scaled by r0), focused with PFA and
autofocused with PGA. The run returns image_<class>.nc and image_<class>_pga.nc (point target),
metrics with <class>_ and <class>_pga_ prefixes and the data of the seed's figures 1-8; the report
layer writes them.
"""
from __future__ import annotations

import functools
import time
import warnings

import numpy as np

from ..atmosphere import (phase_screens, r0_from_cn2, rytov_variance, structure_function,
                          structure_function_estimate, turbulence_class)
from ..autofocus import autofocus, history_metrics
from ..focus import focus
from ..geometry.collection import build_collection
from ..geometry.sampling import check_sampling
from ..metrics import measure
from ..params.models import Atmosphere, PointTarget, Scenario, Scene
from ..params.scenario import dump_scenario, parse_scenario
from ..simulate import screen_size, simulate, turbulent_path
from ..simulate.scene import pattern_mask
from ..studies.engine import execute, require_ok
from ..studies.plan import check_points, make_plan
from ..studies.spec import Axis
from .result import Progress, RunResult

KEYS = ("irw_azimuth_m", "irw_range_m", "pslr_azimuth_db", "islr_azimuth_db", "peak_amplitude",
        "peak_offset_azimuth_m", "entropy", "contrast")


def _with(scenario: Scenario, cn2: float, points, **atm_update) -> Scenario:
    atm = scenario.atmosphere or Atmosphere(cn2=1e-15)
    atm = atm.model_copy(update={"cn2": cn2, **atm_update}) if cn2 > 0 else None
    return scenario.model_copy(update={"atmosphere": atm, "experiment": None,
                                       "scene": Scene(points=tuple(points))})


def i_target_points(extent, spacing, seed: int = 0):
    """Point targets on the seed's "I" pattern (ground coordinates), with seeded Rayleigh amplitudes
    (mean power 1) and uniform random phases. Equal-amplitude lattices put several identical
    scatterers in every range line, the case phase gradient autofocus cannot handle (no dominant
    scatterer); real multi-point targets are not like that.

    Parameters
    ----------
    extent : (float, float)
        m.
    spacing : float
        m.
    seed : int

    Returns
    -------
    list of PointTarget
    """
    rng = np.random.default_rng(seed)
    nx = int(round(extent[0] / spacing)) + 1
    ny = int(round(extent[1] / spacing)) + 1
    x = (np.arange(nx) - (nx - 1) / 2) * spacing
    y = (np.arange(ny) - (ny - 1) / 2) * spacing
    X, Y = np.meshgrid(x, y, indexing="ij")
    m = pattern_mask("letter_I", X / extent[0], Y / extent[1]) > 0
    amp = rng.rayleigh(1 / np.sqrt(2), m.sum())
    ph = rng.uniform(-np.pi, np.pi, m.sum())
    return [PointTarget(x=float(a), y=float(b), amplitude=float(g), phase=float(f))
            for a, b, g, f in zip(X[m], Y[m], amp, ph)]


def path_metrics(scenario: Scenario, classes: dict, R: float) -> dict:
    """Fried parameters (plane, spherical, two-way) of each turbulence class over range ``R``, m.

    Parameters
    ----------
    scenario : Scenario
    classes : dict
        Name -> Cn^2, m^(-2/3).
    R : float
        m.

    Returns
    -------
    dict
    """
    lam, out = scenario.waveform.wavelength, {}
    for name, cn2 in classes.items():
        if cn2 > 0:
            out[f"{name}_cn2"] = cn2
            out[f"{name}_r0_plane_m"] = float(r0_from_cn2(cn2, R, lam))
            out[f"{name}_r0_spherical_m"] = float(r0_from_cn2(cn2, R, lam, "spherical"))
            out[f"{name}_r0_two_way_m"] = float(r0_from_cn2(cn2, R, lam, "spherical")) * 2 ** (-6 / 5)
    return out


def screen_statistics(scenario: Scenario, r0_layer: float) -> tuple[dict, dict]:
    """Ensemble structure function of the experiment's screens against theory (the seed's fig 3):
    its metrics and the curves.

    Parameters
    ----------
    scenario : Scenario
    r0_layer : float
        m.

    Returns
    -------
    (dict, dict)
    """
    exp, atm = scenario.experiment, scenario.atmosphere or Atmosphere(cn2=1e-14)
    scr = phase_screens(exp.ensemble_n, atm.screen_dx, r0_layer, count=exp.ensemble_screens, seed=scenario.seed)
    r, d, e = structure_function_estimate(scr, atm.screen_dx)
    th = structure_function(r, r0_layer)
    m = {"screens_sf_max_deviation_2px_to_N4": float(np.max(np.abs(d[1:] / th[1:] - 1))),
         "screens_sf_ratio_at_N4": float(d[-1] / th[-1])}
    return m, {"r": r, "d": d, "e": e, "theory": th,
               "title": f"{exp.ensemble_screens} screens, r0 = {r0_layer:.3g} m"}


def point_images(scenario: Scenario, name: str, cn2: float, **atm_update) -> tuple[dict, dict, tuple]:
    """The point target of one class focused with PFA, before and after PGA, and measured.

    Parameters
    ----------
    scenario : Scenario
    name : str
        Prefix of the metrics (``<name>_`` and ``<name>_pga_``).
    cn2 : float
        m^(-2/3).
    **atm_update
        Atmosphere fields to change (``model``, ``screen_n``).

    Returns
    -------
    (dict, dict, tuple)
        Metrics, the images (``point``, ``point_pga``) and the cuts (before, after) for the figure.
    """
    p = scenario.processing
    sc_pt = _with(scenario, cn2, scenario.scene.points, **atm_update)
    img = focus(simulate(sc_pt), sc_pt.processing, scenario=sc_pt)
    af, res = autofocus(img, "pga", kernel=p.autofocus_kernel, max_iter=p.autofocus_max_iter)
    m0, m1 = measure(img, details=True), measure(af, details=True)
    metrics = {f"{name}_{k}": float(m0[k]) for k in KEYS}
    metrics.update({f"{name}_pga_{k}": float(m1[k]) for k in KEYS})
    metrics[f"{name}_irw_azimuth_theory_m"] = float(m0["irw_azimuth_theory_m"])
    metrics.update(history_metrics(res, prefix=f"{name}_pga"))
    metrics[f"{name}_pga_iterations"] = len(res.history) - 1
    return metrics, {"point": img, "point_pga": af}, (m0, m1)


def class_images(scenario: Scenario, name: str, cn2: float, i_pts, **atm_update) -> tuple[dict, dict, dict]:
    """One turbulence class: the point target and the "I" focused with PFA, before and after PGA.

    Parameters
    ----------
    scenario : Scenario
    name : str
    cn2 : float
        m^(-2/3).
    i_pts : list of PointTarget
    **atm_update
        Atmosphere fields to change (``model``, ``screen_n``).

    Returns
    -------
    (dict, dict, dict)
        Metrics (``<class>_`` and ``<class>_pga_``), the images (by name), and the report row.
    """
    p = scenario.processing
    metrics, imgs, cuts = point_images(scenario, name, cn2, **atm_update)
    img, af = imgs["point"], imgs["point_pga"]
    sc_i = _with(scenario, cn2, i_pts, **atm_update)
    img_i = focus(simulate(sc_i), sc_i.processing, scenario=sc_i)
    af_i, _ = autofocus(img_i, "pga", kernel=p.autofocus_kernel, max_iter=p.autofocus_max_iter)
    metrics[f"{name}_i_entropy"] = float(measure(img_i)["entropy"])
    metrics[f"{name}_i_pga_entropy"] = float(measure(af_i)["entropy"])
    row = {"name": name, "cn2": cn2, "class": turbulence_class(cn2) if cn2 > 0 else "none",
           **{k: metrics[f"{name}_{k}"] for k in KEYS}, **{f"pga_{k}": metrics[f"{name}_pga_{k}"] for k in KEYS},
           "iterations": metrics[f"{name}_pga_iterations"], "i_entropy": metrics[f"{name}_i_entropy"],
           "i_pga_entropy": metrics[f"{name}_i_pga_entropy"]}
    return metrics, {"point": img, "point_pga": af, "cuts": cuts, "i": (img_i, af_i)}, row


def wave_optics_screen_n(scenario: Scenario, cn2: float, col) -> int:
    """Screen side that both models of a class share: what the wave-optics grids need.

    Parameters
    ----------
    scenario : Scenario
    cn2 : float
        m^(-2/3).
    col : Collection

    Returns
    -------
    int
    """
    return screen_size(_with(scenario, cn2, scenario.scene.points, model="wave_optics"), col)


def compare_models(scenario: Scenario, name: str, cn2: float, row: dict, screen_n: int | None) -> tuple[dict, dict]:
    """The point target of one class through the same screens with wave optics: its metrics
    (``<class>_wo_``), images and cuts; ``row`` gains the ``wo_`` columns. Without turbulence the
    two models are the same simulation and the phase-screen figures are copied.

    Parameters
    ----------
    scenario : Scenario
    name : str
    cn2 : float
        m^(-2/3).
    row : dict
        The class's report row (phase-screen model), updated in place.
    screen_n : int or None
        The shared screen side (None without turbulence).

    Returns
    -------
    (dict, dict)
        Metrics and ``{"images": ..., "cuts": ...}`` (empty without turbulence).
    """
    lam = scenario.waveform.wavelength
    if cn2 > 0:
        m, imgs, cuts = point_images(scenario, f"{name}_wo", cn2, model="wave_optics", screen_n=screen_n)
        R = float(np.linalg.norm(build_collection(scenario).center_position))
        m[f"{name}_rytov_spherical"] = float(rytov_variance(cn2, R, lam, "spherical"))
        m[f"{name}_screen_n"] = screen_n
        out = {"images": imgs, "cuts": cuts}
    else:
        m = {f"{name}_wo_{k}": row[k] for k in KEYS}
        m.update({f"{name}_wo_pga_{k}": row[f"pga_{k}"] for k in KEYS})
        m[f"{name}_wo_pga_iterations"] = row["iterations"]
        m[f"{name}_rytov_spherical"] = 0.0
        out = {}
    row.update({f"wo_{k}": m[f"{name}_wo_{k}"] for k in KEYS})
    row.update({f"wo_pga_{k}": m[f"{name}_wo_pga_{k}"] for k in KEYS})
    row["wo_iterations"] = m[f"{name}_wo_pga_iterations"]
    row["rytov_spherical"] = m[f"{name}_rytov_spherical"]
    return m, out


def pga_steps(scenario: Scenario, image, worst: str) -> tuple[dict, dict]:
    """PGA stopped after each of the experiment's iteration counts, on one image: entropies and
    the images.

    Parameters
    ----------
    scenario : Scenario
    image : xarray.Dataset
    worst : str

    Returns
    -------
    (dict, dict)
    """
    p, steps, m = scenario.processing, {}, {}
    for n_it in scenario.experiment.pga_iterations:
        a, r_ = autofocus(image, "pga", kernel=p.autofocus_kernel, max_iter=n_it)
        steps[f"{n_it} iterations (ran {len(r_.history) - 1})"] = a
        m[f"{worst}_i_pga{n_it}_entropy"] = float(measure(a)["entropy"])
    return m, steps


#: The prefix :func:`class_point` gives its metrics; :func:`named` replaces it by the class's name.
CLASS = "class"


def class_point(data: dict, metrics=(), keep_images: bool = False, *, i_pts=(), wave: bool = False) -> dict:
    """One turbulence class as a sweep point (:func:`class_sweep`): the point target and the "I"
    through the scenario's Cn2 (none when the atmosphere is absent), PFA, PGA; with ``wave`` the
    point target through the same screens by wave optics too.

    Parameters
    ----------
    data : dict
        The seed 004 scenario as plain data, its ``atmosphere.cn2`` the class's.
    metrics, keep_images
        Unused (every metric is kept).
    i_pts : sequence of PointTarget
        The "I" target.
    wave : bool
        Compare with wave optics (the experiment's atmosphere model is ``wave_optics``).

    Returns
    -------
    dict
        A sweep record: metrics ``class_*`` (:func:`class_images`, :func:`compare_models`), and as
        ``payload`` the images, the cuts, the report row and the wave-optics images.
    """
    t0 = time.perf_counter()
    sc = parse_scenario(data)
    cn2 = float(sc.atmosphere.cn2) if sc.atmosphere is not None else 0.0
    shared = {"model": "phase_screen", "screen_n": wave_optics_screen_n(sc, cn2, build_collection(sc))} \
        if wave and cn2 > 0 else {}
    with warnings.catch_warnings():  # the replica warning was given once by the experiment
        warnings.filterwarnings("ignore", message="processing.grid spans")
        m, imgs, row = class_images(sc, CLASS, cn2, list(i_pts), **shared)
        wo = {}
        if wave:
            mw, wo = compare_models(sc, CLASS, cn2, row, shared.get("screen_n"))
            m.update(mw)
    return {"status": "ok", "metrics": {k: float(v) for k, v in m.items()}, "seconds": time.perf_counter() - t0,
            "payload": {"metrics": m, "images": imgs, "row": row, "wave_optics": wo}}


def class_sweep(scenario: Scenario, i_pts, wave: bool, progress: Progress = None):
    """The experiment's turbulence classes as a sweep of ``atmosphere.cn2`` through the study
    engine (:func:`class_point` at each distinct value, in this process).

    Parameters
    ----------
    scenario : Scenario
        With ``experiment.kind = turbulence_pga``.
    i_pts : sequence of PointTarget
    wave : bool
    progress : callable, optional
        ``progress(stage, done, total)``, in classes.

    Returns
    -------
    (xarray.Dataset, list)
        The sweep (``class_*`` metrics against ``atmosphere.cn2``) and each value's payload.
    """
    values = tuple(dict.fromkeys(float(c) for c in scenario.experiment.classes.values()))
    base = scenario if scenario.atmosphere is not None else scenario.model_copy(update={"atmosphere": Atmosphere(cn2=1e-15)})
    axis = Axis("atmosphere.cn2", values, "list", ",".join(f"{v:g}" for v in values))
    plan = make_plan(base, [axis])
    payloads = {}
    tick = (lambda d, n: progress("classes of turbulence", d, n)) if progress else None
    ds = execute(plan, check_points(plan), functools.partial(class_point, i_pts=tuple(i_pts), wave=wave),
                 progress=tick, collect=payloads)
    require_ok(ds, "turbulence classes")
    return ds, [payloads[(i, 0)] for i in range(plan.n_points)]


def named(payload: dict, name: str) -> tuple[dict, dict, dict, dict]:
    """A class point's payload under the class's name: metrics ``<name>_*``, images, report row and
    wave-optics images.

    Parameters
    ----------
    payload : dict
        From :func:`class_point`.
    name : str

    Returns
    -------
    (dict, dict, dict, dict)
    """
    m = {f"{name}{k[len(CLASS):]}": v for k, v in payload["metrics"].items()}
    return m, payload["images"], {**payload["row"], "name": name}, payload["wave_optics"]


def run(scenario: Scenario, out_dir=None, progress: Progress = None) -> RunResult:
    """Run the seed 004 experiment (figures 1-8 of the seed).

    Parameters
    ----------
    scenario : Scenario
        With ``experiment.kind = turbulence_pga``.
    out_dir : path, optional
        Unused.
    progress : callable, optional
        ``progress(stage, done, total)``, in turbulence classes.

    Returns
    -------
    RunResult
    """
    exp, t0 = scenario.experiment, time.perf_counter()
    col = build_collection(scenario)
    check_sampling(scenario, col)
    R = float(np.linalg.norm(col.center_position))
    cn2_fig = exp.classes.get("medium", max(exp.classes.values()))
    path = turbulent_path(_with(scenario, cn2_fig, scenario.scene.points), col)  # figures 1-2
    metrics = path_metrics(scenario, exp.classes, R)
    sf_metrics, sf_curves = screen_statistics(scenario, float(path.r0[0]))
    metrics.update(sf_metrics)
    i_pts = i_target_points(exp.i_target_extent, exp.i_target_spacing, scenario.seed)
    data, cuts, i_images, rows, wo_cuts = {}, {}, {}, [], {}
    wave = scenario.atmosphere is not None and scenario.atmosphere.model == "wave_optics"
    ds, points = class_sweep(scenario, i_pts, wave, progress)
    data["classes.nc"] = ds
    values = list(ds["atmosphere.cn2"].values)
    for name, cn2 in exp.classes.items():
        m, imgs, row, wo = named(points[values.index(cn2)], name)
        metrics.update(m)
        rows.append(row)
        data[f"image_{name}.nc"], data[f"image_{name}_pga.nc"] = imgs["point"], imgs["point_pga"]
        cuts[name], i_images[name] = imgs["cuts"], imgs["i"]
        if wave:
            wo_cuts[name] = wo.get("cuts", imgs["cuts"])
            if wo:
                data[f"image_{name}_wave_optics.nc"] = wo["images"]["point"]
                data[f"image_{name}_wave_optics_pga.nc"] = wo["images"]["point_pga"]
    ref = min(rows, key=lambda r: r["cn2"])["peak_amplitude"]  # the weakest class, turbulence-free if present
    for r in rows:  # peak over the reference peak: the damage where a broken peak makes IRW meaningless
        for pre in ("", "wo_") if wave else ("",):
            for stage in ("", "pga_"):
                key = f"{pre}{stage}peak_ratio"
                r[key] = metrics[f"{r['name']}_{key}"] = r[f"{pre}{stage}peak_amplitude"] / ref
    worst = max(exp.classes, key=exp.classes.get)
    m, steps = pga_steps(scenario, i_images[worst][0], worst)
    metrics.update(m)
    metrics["run_s"] = time.perf_counter() - t0
    return RunResult("turbulence_pga", scenario.name, scenario.description, dump_scenario(scenario), metrics, data,
                     figures={"path": path, "structure_function": sf_curves, "cuts": cuts, "i_images": i_images,
                              "worst": worst, "steps": steps, "rows": rows, "wave_optics_cuts": wo_cuts})
