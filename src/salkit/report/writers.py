"""Figures and report.html of each workflow, drawn from its :class:`RunResult` after the work."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .. import plot
from .. import tolerances as tol
from ..geometry.orbit import max_squint_for, resolution_vs_squint
from ..metrics.pointtarget import cut_curves
from ..papers import published
from ..units import FLAGS, NOT_MEASUREMENTS
from ..plot import downlooking as dlplot
from ..systems.result import RunResult
from .contexts import downlooking_context, table3_cells
from .judge import comparison_rows
from .pages import render


def write_airborne(result: RunResult, out: Path, page: dict | None = None) -> None:
    """Figures (image, cuts, autofocus history, raw data) and report.html of a plain run or of an
    outside file focused.

    Parameters
    ----------
    result : RunResult
    out : Path
    page : dict, optional
        Command line and index link (:func:`salkit.report.render`).
    """
    image = result.datasets["image.nc"]
    fig, metrics = result.figures, result.metrics
    details = fig["details"]
    truth = None
    if "target_azimuth" in image:
        truth = np.stack([image["target_azimuth"].values, image["target_range"].values], axis=1)
    alg = image.attrs.get("algorithm")
    step = plot.preview_step(image["image"].shape)
    every = f", each pixel shown the brightest of {step} x {step}" if step > 1 else ""
    figs = [("Focused image (dB)", "image.png",
             f"{alg} image, dB, azimuth and range in m, true target positions marked{every}")]
    plot.image_db(image, out / "image.png", title=f"{result.name}: {alg} image", truth=truth)
    if "_cut_range" in details:
        pos = image["collection_position"].values if "collection_position" in image else None
        plot.cuts(cut_curves(details, image.attrs, positions=pos), metrics, out / "cuts.png")
        figs.append(("Cuts through the brightest target against theory", "cuts.png",
                     "Range and azimuth cuts through the brightest target, dB, against the theoretical response"))
    if fig.get("autofocus") is not None:
        res = fig["autofocus"]
        plot.autofocus_history(res, out / "autofocus.png", title=getattr(res, "title", "autofocus"))
        figs.append(("Autofocus history", "autofocus.png", "Estimated phase error and image sharpness per autofocus iteration"))
    if fig.get("model_view") is not None:
        plot.model_view_figure(fig["model_view"], out / "model.png", title=f"{result.name}: the model seen from the sensor")
        figs.insert(0, ("The 3-D model seen from the sensor", "model.png",
                        "The scene's objects seen from the aperture centre, surfaces shaded by their Lambertian "
                        "brightness, the parts hidden from the sensor (shadowed) in red"))
    raw = fig.get("raw")
    if raw is not None and "fast_time" in raw:
        plot.raw_phase_history(raw, out / "raw.png")
        figs.append(("Raw dechirped data", "raw.png", "Magnitude of the raw dechirped data, slow time (s) against fast time (us)"))
    timings = fig.get("timings", {})
    render(out, "report.html", result, page, algorithm=alg, window=image.attrs.get("window"),
           t_simulate=timings.get("simulate_s", 0.0), t_focus=timings.get("focus_s", 0.0),
           figures=[{"title": t, "file": f, "alt": a} for t, f, a in figs], rows=comparison_rows(metrics))


WRITERS = {"airborne": write_airborne}


def write_turbulence(result: RunResult, out: Path, page: dict | None = None) -> None:
    """Figures 1-8 of seed 004 and its report.html.

    Parameters
    ----------
    result : RunResult
    out : Path
    page : dict, optional
        Command line and index link (:func:`salkit.report.render`).
    """
    f = result.figures
    plot.screens_figure(f["path"], out / "screens.png")
    sf = f["structure_function"]
    plot.structure_function_figure(sf["r"], sf["d"], sf["e"], sf["theory"], out / "structure_function.png",
                                   title=sf["title"])
    plot.ipr_classes_figure(f["cuts"], out / "ipr_classes.png")
    if f.get("wave_optics_cuts"):
        plot.ipr_classes_figure(f["wave_optics_cuts"], out / "ipr_classes_wave_optics.png")
    plot.image_grid_figure(f["i_images"], out / "i_target.png")
    worst = f["worst"]
    notes = {"focused, no PGA": f"entropy {result.metrics[f'{worst}_i_entropy']:.3f}"}
    for label in f["steps"]:  # "N iterations (ran K)"
        e = result.metrics.get(f"{worst}_i_pga{label.split()[0]}_entropy")
        if e is not None:
            notes[label] = f"entropy {e:.3f}"
    plot.pga_steps_figure(f["i_images"][worst][0], f["steps"], out / "pga_iterations.png", title=worst, notes=notes)
    render(out, "turbulence.html", result, page, rows=f["rows"], irw_pslr=tol.IRW_MEANINGFUL_PSLR_DB,
           wave_optics=bool(f.get("wave_optics_cuts")))


WRITERS["turbulence_pga"] = write_turbulence


def write_chirp(result: RunResult, out: Path, page: dict | None = None) -> None:
    """Heat maps of Tables 2 and 3, the range profiles, and report.html of seed 002.

    Parameters
    ----------
    result : RunResult
    out : Path
    page : dict, optional
        Command line and index link (:func:`salkit.report.render`).
    """
    sweeps = result.figures["sweeps"]
    for label, (rows_, cols_, grids, irws) in sweeps.items():
        plot.sweep_heatmaps(rows_, cols_, grids, irws, out / f"{label}.png",
                            ("d_rlo (m)", "d_r (m)") if label == "table2" else
                            ("R2 (cubic term 1/R2, no unit)", "R1 (quadratic term 1/R1, no unit)"))
    plot.range_profiles_figure(result.datasets["profiles.nc"], out / "profiles.png")
    render(out, "chirp.html", result, page, table1=result.figures["table1"], paper=published()["seed002"]["table1"],
           cells=table3_cells(sweeps["table3"]))


WRITERS["nonlinear_chirp"] = write_chirp


def write_spaceborne(result: RunResult, out: Path, page: dict | None = None) -> None:
    """Figures 5-10 of seed 001 and its report.html.

    Parameters
    ----------
    result : RunResult
    out : Path
    page : dict, optional
        Command line and index link (:func:`salkit.report.render`).
    """
    f = result.figures
    q = np.linspace(-20, 20, 201)
    plot.resolution_squint_figure(f["squints"], f["measured"], q, resolution_vs_squint(f["wavelength"], f["L0"],
                                  f["sub_length"], q), max_squint_for(1.1), out / "resolution_squint.png")
    plot.spaceborne_figures(f["truth"], f["fig7"], f["single"], f["stack"], f["counts"], f["curve"], f["snr_theory"],
                            f["az"], f["rg"], out)
    if "trajectory" in f:
        plot.trajectory_figure(f["trajectory"], out / "trajectory.png")
    if "coherent" in f:
        plot.coherent_stack_figure(f["coherent"]["image"], f["stack"], f["az"], f["rg"], f["coherent"]["resolution"],
                                   out / "coherent.png")
    if f.get("model_view") is not None:
        plot.model_view_figure(f["model_view"], out / "model.png", title=f"{result.name}: the model seen from the sensor")
    render(out, "spaceborne.html", result, page, coherent=f.get("coherent", {}).get("resolution"),
           model=f.get("model_view") is not None,
           trajectory=f.get("trajectory"), processings={"true": "true positions (BP)", "tangent": "tangent line",
                                                        "line": "seed's straight line"},
           grid_dx=float(f["az"][1] - f["az"][0]))


WRITERS["spaceborne_geo"] = write_spaceborne


def write_downlooking(result: RunResult, out: Path, page: dict | None = None) -> None:
    """Figures and report.html of seeds 000/003.

    Parameters
    ----------
    result : RunResult
    out : Path
    page : dict, optional
        Command line and index link (:func:`salkit.report.render`).
    """
    f, m = result.figures, result.metrics
    if "point_details" in f:
        ds_pt = result.datasets["image_point.nc"]
        plot.image_db(ds_pt, out / "image_point.png", title="point target, eq-19 image (forward + backward)",
                      truth=f["truth"])
        plot.cuts(cut_curves(f["point_details"], ds_pt.attrs), m, out / "cuts_point.png")
        dlplot.raw_current(f["current"], f["Y"], f["fast_time"], out / "raw_point.png")
    if "scene" in f:
        dlplot.scene_figure(*f["scene"], f["design"], out / "scene.png")
    if "terrain" in f:
        dlplot.terrain_figures(f["terrain"], f["design"], f["experiment"], out)
    if "disturbance_images" in f:
        dlplot.disturbance_figure(f["disturbance_images"], out / "disturbance.png")
    render(out, "downlooking.html", result, page, paper=published()["seed000"],
           **downlooking_context(result.name, result.description, m, f["design"], f["disturbance_rows"],
                                 result.scenario_text))


WRITERS["downlooking"] = write_downlooking


#: Most metrics a sweep's page draws (the ones asked for, else those with a theory first).
SWEEP_FIGURES = 12
#: Most points the page's table lists (sweep.csv holds them all).
SWEEP_TABLE_ROWS = 200


def write_sweep(result: RunResult, out: Path, page: dict | None = None) -> None:
    """A sweep's figures (each metric against the first varied field, median and 5-95 % band, one
    line per value of the second, theory dashed) and its report.html.

    Parameters
    ----------
    result : RunResult
        From :func:`salkit.systems.study.as_result`.
    out : Path
    page : dict, optional
        Command line and index link (:func:`salkit.report.render`).
    """
    ds = result.datasets["sweep.nc"]
    sweep = json.loads(ds.attrs["sweep"])
    axes = sweep["axes"]
    if "point" in ds.dims:  # zipped: draw against the first field's values
        ds = ds.swap_dims({"point": axes[0]["field"]})
    names = [n for n in result.figures["metrics"] if (not sweep["metrics"] or n in sweep["metrics"])
             and n not in FLAGS and n not in NOT_MEASUREMENTS]  # yes/no flags are not drawn as metrics
    names = sorted(names, key=lambda n: plot.metric_theory(ds, n) is None)[:SWEEP_FIGURES]
    figs = []
    for n in names:
        if np.isfinite(ds[n].values).any():
            plot.sweep_figure(ds, n, out / f"sweep_{n}.png")
            figs.append({"file": f"sweep_{n}.png", "title": n,
                         "alt": f"{n} against {axes[0]['field']}, median over the realisations with the 5-95 % band"})
    status = ds["status"].values.ravel()
    problems = sorted({s for s in status if s != "ok"})
    unmeasured = []
    if "unmeasured" in ds:  # one line per reason, with the points it holds at
        um, points = ds["unmeasured"], {}
        for idx in np.ndindex(um.shape):
            if str(um.values[idx]):
                where = ", ".join(f"{d} = {ds[d].values[i]:g}" if np.issubdtype(ds[d].dtype, np.number)
                                  else f"{d} = {ds[d].values[i]}" for d, i in zip(um.dims, idx))
                points.setdefault(str(um.values[idx]), []).append(where)
        for why, at in points.items():
            more = f" and {len(at) - 3} more" if len(at) > 3 else ""
            unmeasured.append(f"{why} (at {len(at)} point{'s' if len(at) > 1 else ''}: {'; '.join(at[:3])}{more})")
    lines = result.tables["sweep.csv"].splitlines()
    header, rows = lines[0].split(","), [ln.split(",") for ln in lines[1:SWEEP_TABLE_ROWS + 1]]
    render(out, "sweep.html", result, page, axes=axes, zipped=sweep["zip"], realisations=sweep["realisations"],
           figs=figs, problems=problems, n_bad=int((status != "ok").sum()), header=header, unmeasured=unmeasured,
           rows=[[c.strip('"') for c in r] for r in rows], more=max(0, len(lines) - 1 - SWEEP_TABLE_ROWS))


WRITERS["sweep"] = write_sweep
