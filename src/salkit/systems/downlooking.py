"""Seeds 000/003: self-interferometric down-looking SAL, from the fields to the contour map.

``run`` returns ``raw_point.nc`` (the balanced-detector current of the point-target run),
``image_point.nc`` (eq-19 image, foundation image format: ``azimuth`` = along track, ``range`` =
cross track, m on the target), ``image_point_forward.nc``, ``image_scene.nc``, ``terrain.nc``, the
metrics and the figures' data; the report layer writes them with ``report.html``.
"""
from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from ..focus.downlooking import DLImages, focus_downlooking, image_dataset
from ..errors import ScenarioError
from ..geometry.downlooking import DLDesign, design
from ..metrics import measure
from ..params.scenario import dump_scenario
from ..simulate.downlooking import (DLScatterers, Disturbances, fast_time, make_scatterers, no_disturbance,
                                    raw_dataset, simulate_current, track_positions)
from .result import Progress, RunResult
from ..simulate.scene import extended_scatterers
from ..interferometry import carrier_phase, recover_height, terrain_height, terrain_scatterers
from ..atmosphere.screens import phase_screens
from ..constants import SPEED_OF_LIGHT
from ..params.scenario import parse_scenario
from ..focus import focus
from ..simulate import simulate
from ..interferometry import fringe_period, interferogram


# --------------------------------------------------------------------------- helpers
def image_position_theory(scat: DLScatterers, d: DLDesign, focal_transmit: float) -> np.ndarray:
    """Image position (along, cross) of each scatterer, m, by eq 20 with its own magnification:
    xi = 2 (x_p + M_p S_b) v_x / (M_p lambda f_x) maps to x = M_ref f_t d_x / d_z.

    Parameters
    ----------
    scat : DLScatterers
    d : DLDesign
    focal_transmit : float
        m.

    Returns
    -------
    float64 (N, 2)
        m.
    """
    x_img = d.magnification * focal_transmit * scat.d_x / scat.d_z
    return np.stack([scat.y, x_img], axis=1)


def _point_metrics(ds: xr.Dataset, prefix: str = "") -> dict:
    m = measure(ds)
    return {f"{prefix}{k}": v for k, v in m.items() if isinstance(v, (int, float)) and not k.startswith("_")}


# --------------------------------------------------------------------------- experiments
def point_run(sc, d: DLDesign, exp, rng, dist: Disturbances | None = None, points=None,
              order: str | None = None, half_window: float = 0.6):
    """Simulate and focus the scenario's point targets at the down-looking geometry.

    Returns (scatterers, Y, current, images, truth).

    Parameters
    ----------
    sc : DownlookingScenario
    d : DLDesign
    exp : DownlookingExperiment
    rng : numpy.random.Generator
    dist : Disturbances, optional
    points : sequence of PointTarget, optional
    order : str, optional
    half_window : float
        Half-size of the image window, m.

    Returns
    -------
    tuple
    """
    pts = points if points is not None else sc.scene.points
    ground = np.array([[p.x, p.y, p.z] for p in pts], np.float64).reshape(-1, 3)
    amp = np.array([p.amplitude for p in pts], np.float64)  # field reflectivity |rho|; the image shows |rho|^2
    ph = np.array([p.phase for p in pts], np.float64)
    scat = make_scatterers(ground, amp, ph, exp.track.range, exp.track.look_angle_deg)
    Y = track_positions(exp, d, float(ground[:, 0].min()), float(ground[:, 0].max()))
    dist = dist or no_disturbance(Y.size)
    cur = simulate_current(scat, exp, d, Y, dist, rng, force_fields=True)
    truth = image_position_theory(scat, d, exp.optics.focal_transmit)
    c = truth[0]
    imgs = focus_downlooking(cur, Y, d, exp, y_range=(c[0] - half_window, c[0] + half_window),
                             x_range=(c[1] - half_window, c[1] + half_window), order=order)
    return scat, Y, cur, imgs, truth


def extended_run(sc, d: DLDesign, exp, rng, order: str | None = None):
    """The scenario's extended scene (flat, down-looking): images in both processing orders.

    Parameters
    ----------
    sc : DownlookingScenario
    d : DLDesign
    exp : DownlookingExperiment
    rng : numpy.random.Generator
    order : str, optional

    Returns
    -------
    (DLScatterers, DLImages, DLImages)
    """
    ext = sc.scene.extended
    pos, amp = extended_scatterers(ext, d.resolution_x * d.resolution_y, rng)
    # foundation scene frame: x along track, y across track (ground), z up
    scat = make_scatterers(pos, np.abs(amp), np.angle(amp), exp.track.range, exp.track.look_angle_deg)
    Y = track_positions(exp, d, -0.5 * ext.extent[0], 0.5 * ext.extent[0])
    cur = simulate_current(scat, exp, d, Y, None, rng)
    half_y, half_x = 0.5 * ext.extent[0] + 0.1, 0.5 * ext.extent[1] + 0.1
    imgs = focus_downlooking(cur, Y, d, exp, y_range=(-half_y, half_y), x_range=(-half_x, half_x),
                             order="focus_then_add")
    paper = focus_downlooking(cur, Y, d, exp, y_range=(-half_y, half_y), x_range=(-half_x, half_x),
                              order="paper")
    return scat, imgs, paper


def terrain_run(exp, d: DLDesign, rng):
    """Oblique observation of the 3-D terrain; interferogram, unwrapping, height and what it shows.

    Returns a dict of arrays and numbers.

    Parameters
    ----------
    exp : DownlookingExperiment
    d : DLDesign
    rng : numpy.random.Generator

    Returns
    -------
    dict
    """
    ter = exp.terrain
    look = exp.terrain_look_angle_deg
    th = math.radians(look)
    cell = d.resolution_y * d.resolution_x / max(math.cos(th), 1e-6)
    pos, amp = terrain_scatterers(ter, cell, rng)
    scat = make_scatterers(pos, np.abs(amp), np.angle(amp), exp.track.range, look)
    Y = track_positions(exp, d, -0.5 * ter.extent[0], 0.5 * ter.extent[0])
    cur = simulate_current(scat, exp, d, Y, None, rng)
    truth_img = image_position_theory(scat, d, exp.optics.focal_transmit)
    xr_ = (float(truth_img[:, 1].min()), float(truth_img[:, 1].max()))
    half_y = 0.5 * ter.extent[0]
    imgs = focus_downlooking(cur, Y, d, exp, y_range=(-half_y, half_y), x_range=xr_, order="focus_then_add")
    hr = recover_height(imgs.forward, imgs.backward, imgs.y, imgs.x, d.magnification, exp.optics.bias_common,
                        d.fringe_period_x, look, exp.unwrap, d.resolution_x, truth_img, scat.ground[:, 2])
    # what the paper's Fig. 2 pictures: the flat fringe phase painted onto the terrain, in ground
    # coordinates (a second, nadir-looking camera would see this; the SAL cannot)
    gx = np.linspace(-0.5 * ter.extent[0], 0.5 * ter.extent[0], 160)
    gy = np.linspace(-0.5 * ter.extent[1], 0.5 * ter.extent[1], 160)
    GX, GY = np.meshgrid(gx, gy, indexing="ij")
    GZ = terrain_height(ter, GX, GY)
    pts = np.stack([GX.ravel(), GY.ravel(), GZ.ravel()], axis=1)
    flat = np.stack([GX.ravel(), GY.ravel(), np.zeros(GX.size)], axis=1)
    s_t = make_scatterers(pts, np.ones(len(pts)), np.zeros(len(pts)), exp.track.range, look)
    s_f = make_scatterers(flat, np.ones(len(pts)), np.zeros(len(pts)), exp.track.range, look)
    xi_t = image_position_theory(s_t, d, exp.optics.focal_transmit)[:, 1]
    xi_f = image_position_theory(s_f, d, exp.optics.focal_transmit)[:, 1]
    ground_fringe = (carrier_phase(xi_t, d.magnification, exp.optics.bias_common, d.fringe_period_x)
                     - carrier_phase(xi_f, d.magnification, exp.optics.bias_common, d.fringe_period_x)).reshape(GX.shape)
    return {**hr, "images": imgs, "ground_x": gx, "ground_y": gy, "ground_z": GZ, "ground_fringe": ground_fringe,
            "metrics": {"terrain_look_angle_deg": look, "terrain_height_max_m": float(np.nanmax(GZ)),
                        **hr["metrics"],
                        "terrain_ground_fringe_phase_rms_rad": float(np.std(ground_fringe)),
                        "terrain_ground_fringe_phase_span_rad": float(np.ptp(ground_fringe)),
                        "terrain_scatterers": scat.count}}


def make_disturbances(exp, d: DLDesign, Y: np.ndarray, which: str, rng_seed: int) -> Disturbances:
    """Sampled disturbances for one case of the immunity experiment.

    ``which``: "common" (vibration, jitter, shared path screen), "transmitter" (turbulent layer at the
    transmit pupil) or "differential" (polarisation-dependent phase).

    Parameters
    ----------
    exp : DownlookingExperiment
    d : DLDesign
    Y : float64 (n_scans,)
        m.
    which : {"common", "transmitter", "differential"}
    rng_seed : int

    Returns
    -------
    Disturbances
    """
    ds = exp.disturbance
    base = no_disturbance(Y.size)
    rng = np.random.default_rng(rng_seed)
    n_t = d.samples
    kw = dict(vibration=base.vibration, jitter=base.jitter, path_screen=base.path_screen, path_dx=1.0,
              tx_screen=base.tx_screen, tx_dx=1.0, tx_shift=0.0, differential=base.differential)
    if which == "common":
        if ds.vibration is not None:
            kw["vibration"] = ds.vibration.values(Y.size)
        if ds.jitter_rms > 0:
            kw["jitter"] = ds.jitter_rms * rng.standard_normal((Y.size, n_t))
        if ds.path_r0 is not None:
            span = float(np.ptp(Y)) + d.spot_x + 1.0
            dx = 0.01
            n = int(2 ** math.ceil(math.log2(span / dx)))
            kw["path_screen"] = phase_screens(n, dx, ds.path_r0, seed=rng_seed)[0]
            kw["path_dx"] = dx
    elif which == "transmitter":
        if ds.transmitter_r0 is None:
            raise ValueError("disturbance.transmitter_r0 is not set")
        span = d.transmit_pupil_diameter + ds.transmitter_screen_shift * Y.size + 0.2
        dx = 0.002
        n = int(2 ** math.ceil(math.log2(span / dx)))
        kw["tx_screen"] = phase_screens(n, dx, ds.transmitter_r0, seed=rng_seed)[0]
        kw["tx_dx"] = dx
        kw["tx_shift"] = ds.transmitter_screen_shift
    elif which == "differential":
        kw["differential"] = ds.differential_rms * rng.standard_normal(Y.size)
    else:
        raise ValueError(which)
    return Disturbances(**kw)


def side_looking_scenario(exp, d: DLDesign, phase_error=None):
    """A foundation side-looking spotlight SAL of comparable resolution (first null equal to the DL-SAL's)
    at the same wavelength and range, with the same per-pulse phase disturbance.

    Parameters
    ----------
    exp : DownlookingExperiment
    d : DLDesign
    phase_error : PhaseError, optional

    Returns
    -------
    Scenario
    """
    lam, R = d.wavelength, d.range
    res = d.resolution_x
    L = lam * R / (2 * res)
    data = {
        "name": "side_looking_comparison",
        "waveform": {"wavelength": lam, "bandwidth": SPEED_OF_LIGHT / (2 * res), "pulse_width": 10e-6, "prf": 2560.0},
        "platform": {"mode": "spotlight", "speed": 1.0, "altitude": 0.0, "standoff": R,
                     "real_aperture": 0.02, "aperture_length": L},
        "scene": {"points": [{"x": 0.0, "y": 0.0}]},
        "receiver": {"adc_rate": 8e6},
        "processing": {"algorithm": "bp", "grid": {"nx": 96, "ny": 96, "dx": res / 3, "dy": res / 3}},
    }
    if phase_error is not None:
        data["platform"]["phase_error"] = phase_error.model_dump()
    return parse_scenario(data)


def disturbance_experiment(sc, exp, d: DLDesign, progress: Progress = None) -> dict:
    """The immunity experiment: DL-SAL under common-mode and non-common-mode disturbances, and a
    side-looking SAL of comparable resolution under the same vibration.

    Parameters
    ----------
    sc : DownlookingScenario
    exp : DownlookingExperiment
    d : DLDesign
    progress : callable, optional

    Returns
    -------
    dict
        ``cases`` (metrics by case) and ``images``.
    """
    pts = sc.scene.points[:1]
    rng = np.random.default_rng(sc.seed + 101)
    _, Y, _, clean, truth = point_run(sc, d, exp, rng, points=pts, half_window=0.3)
    ref = clean.combined
    pk = float(np.abs(ref).max())
    out = {"cases": {}}
    cases = [("common", "common mode: vibration + jitter + shared path turbulence")]
    if exp.disturbance.transmitter_r0 is not None:
        cases.append(("transmitter", f"turbulent layer at the transmit pupil, r0 = {exp.disturbance.transmitter_r0:g} m"))
    if exp.disturbance.differential_rms > 0:
        cases.append(("differential", f"polarisation-dependent phase, {exp.disturbance.differential_rms:g} rad RMS"))
    images = {"DL-SAL, no disturbance": (clean, ref)}
    base_m = _dl_case_metrics(clean, d, exp, truth)
    out["cases"]["none"] = base_m
    for i, (key, label) in enumerate(cases):
        if progress:
            progress("cases of disturbance", i, len(cases))
        dist = make_disturbances(exp, d, Y, key, exp.disturbance.seed + i)
        _, _, _, imgs, _ = point_run(sc, d, exp, np.random.default_rng(sc.seed + 101), dist=dist, points=pts,
                                     half_window=0.3)
        m = _dl_case_metrics(imgs, d, exp, truth)
        m["max_change_over_peak"] = float(np.abs(imgs.combined - ref).max() / pk)
        m["peak_ratio"] = m["peak_amplitude"] / base_m["peak_amplitude"]
        m["label"] = label
        out["cases"][key] = m
        images[f"DL-SAL, {label}"] = (imgs, imgs.combined)
    # side-looking SAL with the same vibration (the jitter as well, as white per-pulse phase)
    if exp.side_looking_comparison and exp.disturbance.vibration is not None:
        for name, pe in (("side_clean", None), ("side_vibration", exp.disturbance.vibration)):
            ssc = side_looking_scenario(exp, d, pe)
            raw = simulate(ssc, noise=False)
            img = focus(raw, ssc.processing, scenario=ssc)
            mm = measure(img)
            out["cases"][name] = {k: mm[k] for k in ("irw_range_m", "irw_azimuth_m", "pslr_range_db",
                                                     "pslr_azimuth_db", "peak_amplitude", "entropy")}
            images["side-looking SAL, " + ("no disturbance" if pe is None else "same vibration")] = (img, None)
        sl0, sl1 = out["cases"]["side_clean"], out["cases"]["side_vibration"]
        sl1["peak_ratio"] = sl1["peak_amplitude"] / sl0["peak_amplitude"]
    if progress:
        progress("cases of disturbance", len(cases), len(cases))
    out["images"] = images
    return out


def _dl_case_metrics(imgs: DLImages, d: DLDesign, exp, truth) -> dict:
    ds = image_dataset(imgs.combined, imgs, d, exp, exp.track.look_angle_deg, "combined", truth[:1])
    m = measure(ds)
    i, j = np.unravel_index(int(np.argmax(np.abs(imgs.forward))), imgs.forward.shape)
    fringe_phase = float(np.angle(imgs.forward[i, j] * np.conj(imgs.backward[i, j])))
    keys = ("irw_range_m", "irw_azimuth_m", "pslr_range_db", "pslr_azimuth_db", "peak_amplitude",
            "peak_offset_range_m", "peak_offset_azimuth_m", "entropy")
    out = {k: float(m[k]) for k in keys if k in m}
    out["fringe_phase_rad"] = fringe_phase
    return out


# --------------------------------------------------------------------------- the run
def point_case(scenario, d: DLDesign, rng) -> tuple[dict, dict, dict]:
    """The point target: raw current, eq-19 and forward-only images, their metrics against theory
    and the fringe modulation of a point (with the paper's processing order beside it).

    Parameters
    ----------
    scenario : DownlookingScenario
    d : DLDesign
    rng : numpy.random.Generator

    Returns
    -------
    (dict, dict, dict)
        Metrics, datasets (by file name) and figure data.
    """
    exp, text = scenario.experiment, dump_scenario(scenario)
    if not scenario.scene.points:
        raise ScenarioError("scene.points", [], "the down-looking experiment needs at least one point target")
    scat, Y, cur, imgs, truth = point_run(scenario, d, exp, rng)
    ds_pt = image_dataset(imgs.combined, imgs, d, exp, exp.track.look_angle_deg, "combined eq 19", truth, text)
    ds_fw = image_dataset(imgs.forward, imgs, d, exp, exp.track.look_angle_deg, "forward scans only", truth, text)
    m_pt = measure(ds_pt, details=True)
    metrics = {k: v for k, v in m_pt.items() if not k.startswith("_") and isinstance(v, (int, float))}
    m_fw = _point_metrics(ds_fw, "forward_")
    metrics.update({k: v for k, v in m_fw.items() if k.startswith(("forward_irw", "forward_pslr", "forward_islr",
                                                                     "forward_peak_offset"))})
    alpha = 2 * math.pi * (truth[0, 1] + d.magnification * exp.optics.bias_common) / d.fringe_period_x
    metrics["fringe_modulation_point"] = float(m_pt["peak_amplitude"] / max(m_fw["forward_peak_amplitude"], 1e-30) / 2)
    metrics["fringe_modulation_point_theory"] = abs(math.cos(alpha))
    paper = focus_downlooking(cur, Y, d, exp, y_range=(imgs.y[0], imgs.y[-1]), x_range=(imgs.x[0], imgs.x[-1]),
                              order="paper")
    metrics["fringe_modulation_point_paper_order"] = float(np.abs(paper.combined).max()
                                                           / max(np.abs(imgs.forward).max(), 1e-30) / 2)
    t = fast_time(d, exp.scan.duration)
    return (metrics, {"raw_point.nc": raw_dataset(cur, Y, t, d, text), "image_point.nc": ds_pt,
                      "image_point_forward.nc": ds_fw},
            {"point_details": m_pt, "truth": truth, "current": cur, "Y": Y, "fast_time": t})


def scene_case(scenario, d: DLDesign, rng) -> tuple[dict, dict, dict]:
    """The extended scene: fringes, their period (eq 25) and the paper's processing order.

    Parameters
    ----------
    scenario : DownlookingScenario
    d : DLDesign
    rng : numpy.random.Generator

    Returns
    -------
    (dict, dict, dict)
    """
    exp = scenario.experiment
    sscat, simgs, spaper = extended_run(scenario, d, exp, rng)
    per = fringe_period(interferogram(simgs.forward.astype(np.complex128), simgs.backward.astype(np.complex128)),
                        simgs.x, factor=2.0)
    ds = image_dataset(simgs.combined, simgs, d, exp, exp.track.look_angle_deg, "combined eq 19", None,
                       dump_scenario(scenario))
    return ({"fringe_period_m": per["period_m"], "scene_scatterers": sscat.count}, {"image_scene.nc": ds},
            {"scene": (simgs, spaper)})


def terrain_case(scenario, d: DLDesign, rng) -> tuple[dict, dict, dict]:
    """The oblique view of the 3-D terrain: images, interferogram and height (:func:`terrain_run`).

    Parameters
    ----------
    scenario : DownlookingScenario
    d : DLDesign
    rng : numpy.random.Generator

    Returns
    -------
    (dict, dict, dict)
    """
    exp = scenario.experiment
    ter = terrain_run(exp, d, rng)
    timgs = ter["images"]
    tds = image_dataset(timgs.combined, timgs, d, exp, exp.terrain_look_angle_deg, "terrain, combined eq 19",
                        None, dump_scenario(scenario))
    tds["interferogram"] = (("azimuth", "range"), ter["ifg"].astype(np.complex64))
    tds["height_recovered"] = (("azimuth", "range"), ter["h_rec"].astype(np.float32), {"units": "m"})
    tds["height_true"] = (("azimuth", "range"), ter["h_true"].astype(np.float32), {"units": "m"})
    return ter["metrics"], {"terrain.nc": tds}, {"terrain": ter}


def disturbance_case(scenario, d: DLDesign, progress: Progress = None) -> tuple[dict, dict, dict]:
    """The disturbance experiment (:func:`disturbance_experiment`): metrics of every case.

    Parameters
    ----------
    scenario : DownlookingScenario
    d : DLDesign
    progress : callable, optional

    Returns
    -------
    (dict, dict, dict)
    """
    dres = disturbance_experiment(scenario, scenario.experiment, d, progress)
    metrics = {f"disturbance_{case}_{k}": v for case, mm in dres["cases"].items() for k, v in mm.items()
               if isinstance(v, (int, float))}
    return metrics, {}, {"disturbance_images": dres["images"], "disturbance_rows": dres["cases"]}


def run(scenario, out_dir=None, progress: Progress = None) -> RunResult:
    """Run the seed 000 experiment: point target, extended scene, 3-D terrain, disturbances.

    Parameters
    ----------
    scenario : DownlookingScenario
    out_dir : path, optional
        Unused.
    progress : callable(stage, done, total), optional

    Returns
    -------
    RunResult
    """
    t_all, exp = time.perf_counter(), scenario.experiment
    d = design(exp)
    metrics: dict = {f"design_{k}": v for k, v in d.as_dict().items()}
    metrics["design_warnings"] = len(d.warnings)
    metrics["fringe_period_m"] = float("nan")  # a point's fringe belongs to its position: needs a scene
    metrics["fringe_period_theory_m"] = d.fringe_period_x
    rng = np.random.default_rng(scenario.seed)
    data, figures = {}, {"design": d, "experiment": exp, "disturbance_rows": {}}
    cases = [("point target", "point_s", lambda: point_case(scenario, d, rng)),
             ("extended scene", "scene_s", (lambda: scene_case(scenario, d, rng)) if scenario.scene.extended else None),
             ("3-D terrain", "terrain_s", (lambda: terrain_case(scenario, d, rng)) if exp.terrain else None),
             ("disturbances", "disturbance_s",
              (lambda: disturbance_case(scenario, d, progress)) if exp.disturbance.active else None)]
    for i, (label, key, case) in enumerate(cases):
        if progress:
            progress("cases", i, len(cases))
        if case is None:
            continue
        t0 = time.perf_counter()
        m, ds, fig = case()
        metrics.update(m)
        metrics[f"time_{key}"] = time.perf_counter() - t0
        data.update(ds)
        figures.update(fig)
    if progress:
        progress("cases", len(cases), len(cases))
    metrics["time_total_s"] = time.perf_counter() - t_all
    return RunResult("downlooking", scenario.name, scenario.description, dump_scenario(scenario), metrics, data,
                     figures=figures)
