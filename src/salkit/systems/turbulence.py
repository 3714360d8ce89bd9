"""Seed 004: SAL through atmospheric turbulence, polar format imaging, phase gradient autofocus.

For each turbulence class (Cn^2) a point target and an "I" made of point targets are simulated
through the same frozen 50-layer path (screens of one seed, scaled by r0), focused with PFA and
autofocused with PGA. Outputs: image_<class>.nc and image_<class>_pga.nc (point target),
metrics.json with <class>_ and <class>_pga_ prefixes, figures for the seed's figures 1-8, and
report.html.
"""
from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np

from ..atmosphere import (phase_screens, r0_from_cn2, structure_function, structure_function_estimate,
                          turbulence_class)
from ..autofocus import autofocus, history_metrics
from ..focus import focus
from ..geometry.collection import build_collection
from ..geometry.sampling import check_sampling
from ..io.datasets import write_dataset, write_json_atomic, write_text_atomic
from ..metrics import measure
from ..params.models import Atmosphere, PointTarget, Scenario, Scene
from ..params.scenario import dump_scenario
from ..simulate import simulate, turbulent_path
from ..simulate.scene import pattern_mask

KEYS = ("irw_azimuth_m", "irw_range_m", "pslr_azimuth_db", "islr_azimuth_db", "peak_amplitude",
        "peak_offset_azimuth_m", "entropy", "contrast")


def _with(scenario: Scenario, cn2: float, points) -> Scenario:
    atm = scenario.atmosphere or Atmosphere(cn2=1e-15)
    atm = atm.model_copy(update={"cn2": cn2}) if cn2 > 0 else None
    return scenario.model_copy(update={"atmosphere": atm, "experiment": None,
                                       "scene": Scene(points=tuple(points))})


def i_target_points(extent, spacing, seed: int = 0):
    """Point targets on the seed's "I" pattern (ground coordinates), with seeded Rayleigh amplitudes
    (mean power 1) and uniform random phases. Equal-amplitude lattices put several identical
    scatterers in every range line, the case phase gradient autofocus cannot handle (no dominant
    scatterer); real multi-point targets are not like that."""
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


def run(scenario: Scenario, out_dir, progress=None) -> dict:
    """Run the seed 004 experiment; returns the metrics written to metrics.json."""
    from .. import plot
    exp = scenario.experiment
    out = Path(out_dir)
    col = build_collection(scenario)
    check_sampling(scenario, col)
    out.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out / "scenario.yaml", dump_scenario(scenario))
    lam = scenario.waveform.wavelength
    R = float(np.linalg.norm(col.center_position))
    atm = scenario.atmosphere or Atmosphere(cn2=1e-14)
    metrics: dict = {}
    t0 = time.perf_counter()
    # figures 1-2: one layer and the sum of all layers (medium class), path r0
    cn2_fig = exp.classes.get("medium", max(exp.classes.values()))
    path = turbulent_path(_with(scenario, cn2_fig, scenario.scene.points), col)
    plot.screens_figure(path, out / "screens.png")
    for name, cn2 in exp.classes.items():
        if cn2 > 0:
            metrics[f"{name}_cn2"] = cn2
            metrics[f"{name}_r0_plane_m"] = float(r0_from_cn2(cn2, R, lam))
            metrics[f"{name}_r0_spherical_m"] = float(r0_from_cn2(cn2, R, lam, "spherical"))
            metrics[f"{name}_r0_two_way_m"] = float(r0_from_cn2(cn2, R, lam, "spherical")) * 2 ** (-6 / 5)
    # figure 3: ensemble structure function of screens against theory
    r0_layer = float(path.r0[0])
    scr = phase_screens(exp.ensemble_n, atm.screen_dx, r0_layer, count=exp.ensemble_screens, seed=scenario.seed)
    r, d, e = structure_function_estimate(scr, atm.screen_dx)
    th = structure_function(r, r0_layer)
    metrics["screens_sf_max_deviation_2px_to_N4"] = float(np.max(np.abs(d[1:] / th[1:] - 1)))
    metrics["screens_sf_ratio_at_N4"] = float(d[-1] / th[-1])
    plot.structure_function_figure(r, d, e, th, out / "structure_function.png",
                                   title=f"{exp.ensemble_screens} screens, r0 = {r0_layer:.3g} m")
    # figures 4-8: point and I targets per class, before and after PGA
    i_pts = i_target_points(exp.i_target_extent, exp.i_target_spacing, scenario.seed)
    cuts, i_images, rows = {}, {}, []
    p = scenario.processing
    n_cls = len(exp.classes)
    with warnings.catch_warnings():  # the replica warning was given once above
        warnings.filterwarnings("ignore", message="processing.grid spans")
        for ci, (name, cn2) in enumerate(exp.classes.items()):
            if progress:
                progress("classes", ci, n_cls)
            sc_pt = _with(scenario, cn2, scenario.scene.points)
            img = focus(simulate(sc_pt), sc_pt.processing, scenario=sc_pt)
            write_dataset(img, out / f"image_{name}.nc")
            af, res = autofocus(img, "pga", kernel=p.autofocus_kernel, max_iter=p.autofocus_max_iter)
            write_dataset(af, out / f"image_{name}_pga.nc")
            m0, m1 = measure(img, details=True), measure(af, details=True)
            for k in KEYS:
                metrics[f"{name}_{k}"] = float(m0[k])
                metrics[f"{name}_pga_{k}"] = float(m1[k])
            metrics[f"{name}_irw_azimuth_theory_m"] = float(m0["irw_azimuth_theory_m"])
            metrics.update(history_metrics(res, prefix=f"{name}_pga"))
            cuts[name] = (m0, m1)
            sc_i = _with(scenario, cn2, i_pts)
            img_i = focus(simulate(sc_i), sc_i.processing, scenario=sc_i)
            af_i, _ = autofocus(img_i, "pga", kernel=p.autofocus_kernel, max_iter=p.autofocus_max_iter)
            i_images[name] = (img_i, af_i)
            metrics[f"{name}_i_entropy"] = float(measure(img_i)["entropy"])
            metrics[f"{name}_i_pga_entropy"] = float(measure(af_i)["entropy"])
            rows.append({"name": name, "cn2": cn2, "class": turbulence_class(cn2) if cn2 > 0 else "none",
                         **{k: metrics[f"{name}_{k}"] for k in KEYS}, **{f"pga_{k}": metrics[f"{name}_pga_{k}"] for k in KEYS},
                         "iterations": len(res.history) - 1, "i_entropy": metrics[f"{name}_i_entropy"],
                         "i_pga_entropy": metrics[f"{name}_i_pga_entropy"]})
        if progress:
            progress("classes", n_cls, n_cls)
    plot.ipr_classes_figure(cuts, out / "ipr_classes.png")
    plot.image_grid_figure(i_images, out / "i_target.png")
    # PGA after 5, 10, 20 iterations (capped) on the strongest class with turbulence
    worst = max(exp.classes, key=exp.classes.get)
    steps = {}
    for n_it in exp.pga_iterations:
        a, r_ = autofocus(i_images[worst][0], "pga", kernel=p.autofocus_kernel, max_iter=n_it)
        steps[f"{n_it} iterations (ran {len(r_.history) - 1})"] = a
        metrics[f"{worst}_i_pga{n_it}_entropy"] = float(measure(a)["entropy"])
    plot.pga_steps_figure(i_images[worst][0], steps, out / "pga_iterations.png", title=worst)
    metrics["run_s"] = time.perf_counter() - t0
    write_json_atomic(out / "metrics.json", metrics)
    from ..report import write_turbulence_report
    write_turbulence_report(out, scenario, rows, metrics)
    return metrics
