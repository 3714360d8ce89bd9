"""Space-borne SAL of a GEO target (seed 001): squinted sub-apertures, incoherent or coherent stacking.

The sub-images and the stacks are :mod:`salkit.stack`; this workflow composes them into the
seed's figures 5-10: geometry, a photon-limited single sub-image against eq 15, the stack on Dask
(checkpointed in ``stack.zarr`` in the run folder) and its SNR against sqrt(P) x eq 15, the
resolution against squint (eq 12), and sub-images before and after geometric correction. With
``stack.mode = coherent`` it also forms the phase-aligned complex sum (:func:`coherent_part`).
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import zarr
from scipy.ndimage import binary_erosion, gaussian_filter

from ..focus import focus
from ..geometry.collection import build_collection, grid_axes, plane_from
from ..geometry.orbit import (collection_span, max_squint_for, n_subimages, relative_speed, resolution_vs_squint,
                              subaperture_length)
from ..geometry.sampling import check_sampling, n_fast_samples, resolution_theory
from ..io.datasets import make_image_dataset
from ..metrics import measure, split_snr, stack_snr
from ..metrics.pointtarget import ipr_1d
from ..params.models import Scenario
from ..params.scenario import dump_scenario, parse_scenario
from ..resources import check_memory
from ..simulate import signal_scale, simulate
from ..simulate.views import model_view
from ..simulate.scene import pattern_mask
from ..stack import (coherent_resolution, coherent_stack, geo_base, nearest_squints, point_target, run_stack,
                     stack_memory_estimate, subimage, uncorrect)
from ..studies.engine import execute, require_ok
from ..studies.plan import check_points, make_plan
from ..studies.spec import Axis
from .result import Progress, RunResult, stage
from .study import run_point


def collection_metrics(scenario: Scenario) -> tuple[dict, list]:
    """The collection of the experiment (eqs 1-4): relative speed, closest distance, span,
    sub-aperture length and count; and the squints (deg) of the sub-apertures to stack.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (dict, list of float)
    """
    exp = scenario.experiment
    L0 = exp.r2 - exp.r1
    D = collection_span(L0, exp.squint_max_deg)
    L = subaperture_length(scenario.waveform.wavelength, L0, exp.resolution)
    P_all = n_subimages(D, L)
    count = min(P_all, scenario.stack.max_subimages or P_all)
    return ({"relative_speed_m_s": relative_speed(exp.r1, exp.r2), "closest_distance_m": L0, "collection_span_m": D,
             "subaperture_length_m": L, "subimages_in_collection": P_all, "stack_count": count},
            nearest_squints(count, L, L0))


def truth_image(base: Scenario, az: np.ndarray, rg: np.ndarray) -> np.ndarray:
    """The target's reflectivity on the image grid (its extended pattern).

    Parameters
    ----------
    base : Scenario
    az, rg : float64
        m.

    Returns
    -------
    float ndarray
    """
    ext = base.scene.extended
    if ext is None:
        return np.zeros((az.size, rg.size))
    A_, R_ = np.meshgrid(az, rg, indexing="ij")
    return pattern_mask(ext.pattern, A_ / ext.extent[0], R_ / ext.extent[1]) * ext.amplitude


def stack_curve(inten: np.ndarray, mask: np.ndarray, noise_power: float, snr_single: float) -> tuple[dict, list, list]:
    """SNR of the stack of the first c sub-images for c on a log scale up to all of them (eq 16).

    Parameters
    ----------
    inten : float (K, nx, ny)
    mask : bool (nx, ny)
    noise_power : float
    snr_single : float

    Returns
    -------
    (dict, list of int, list of float)
    """
    count = len(inten)
    counts = sorted({int(c) for c in np.unique(np.round(np.geomspace(2, count, 12)))}) if count >= 2 else [1]
    curve = [split_snr(inten[:c], mask, noise_power) if c >= 2 else snr_single for c in counts]
    return {f"snr_stack_{c}": v for c, v in zip(counts, curve)}, counts, curve


def squint_sweep(scenario: Scenario, squints, runner, metrics=()):
    """A sub-aperture scenario swept over its squint through the study engine, in this process:
    each squint is :func:`salkit.stack.subaperture` of ``scenario`` (noise seed 0).

    Parameters
    ----------
    scenario : Scenario
        One sub-aperture (experiment block removed).
    squints : sequence of float
        deg.
    runner : callable
        The point function (:func:`salkit.systems.study.run_point` or :func:`trajectory_point`).
    metrics : sequence of str
        Metrics to keep (empty: all).

    Returns
    -------
    (xarray.Dataset, dict)
        The sweep (``platform.squint_deg``, ``realisation``), and each squint's payload by index.
    """
    base = scenario.model_copy(update={"seed": 0})
    axis = Axis("platform.squint_deg", tuple(float(q) for q in squints), "list", ",".join(f"{q:g}" for q in squints))
    plan = make_plan(base, [axis], metrics=metrics)
    payloads = {}
    ds = execute(plan, check_points(plan), runner, collect=payloads)
    require_ok(ds, "squint sweep")
    return ds, {i: payloads[(i, 0)] for i in range(plan.n_points)}


def resolution_against_squint(base: Scenario, sub_length: float) -> tuple[dict, list, list]:
    """Along-track resolution measured on a point target at several squints, against eq 12: a
    sweep of the sub-aperture's squint through the study engine (:func:`squint_sweep`).

    Parameters
    ----------
    base : Scenario
    sub_length : float
        m.

    Returns
    -------
    (dict, list of float, list of float)
        Metrics, squints (deg), measured resolutions (m).
    """
    L0 = base.platform.standoff
    sq_meas = [0.0, 2.5, 5.0, 7.5, 10.0, round(max_squint_for(1.1), 2)]
    ds, _ = squint_sweep(point_target(base), sq_meas, run_point, metrics=("irw_azimuth_m",))
    meas, m = [float(v) for v in ds["irw_azimuth_m"].isel(realisation=0).values / 0.886], {}
    for q, v in zip(sq_meas, meas):
        m[f"resolution_azimuth_squint_{q:g}_m"] = v
        m[f"resolution_azimuth_squint_{q:g}_theory_m"] = float(resolution_vs_squint(
            base.waveform.wavelength, L0, sub_length, q))
    m["max_squint_within_1p1_deg"] = max_squint_for(1.1)
    return m, sq_meas, meas


def coherent_part(base: Scenario, store: Path, count: int, mask: np.ndarray, snr_incoherent: float) -> tuple[dict, dict]:
    """The coherent stack: the stored complex sub-images summed with phase alignment
    (:func:`salkit.stack.coherent_stack`), its one-look SNR on the uniform region, and the
    resolution of coherent stacks of 1, 2, 4, ... sub-apertures on a point target against the
    combined aperture's theory (:func:`salkit.stack.coherent_resolution`).

    Parameters
    ----------
    base : Scenario
    store : Path
        The stack's Zarr store, with ``image`` (complex sub-images).
    count : int
    mask : bool (nx, ny)
        Uniform region of the target.
    snr_incoherent : float
        The incoherent stack's SNR, for the ratio.

    Returns
    -------
    (dict, dict)
        Metrics and figure data (``image``, ``resolution``).
    """
    images = zarr.open_group(str(store), mode="r")["image"]
    acc, offsets = coherent_stack(np.asarray(images[i]) for i in range(count))
    inten = np.abs(acc[mask]) ** 2
    snr = float(inten.mean() / inten.std()) if inten.size > 1 else float("nan")
    counts = [int(2 ** k) for k in range(int(math.log2(min(count, 64))) + 1)]
    res = coherent_resolution(base, counts)
    m = {"stack_coherent": 1, "snr_stack_coherent": snr, "snr_stack_coherent_over_incoherent": snr / snr_incoherent,
         "coherent_phase_offsets_std_rad": float(np.std(offsets))}
    for P, irw, th in zip(res["counts"], res["irw_m"], res["irw_theory_m"]):
        m[f"coherent_irw_azimuth_{P}_m"], m[f"coherent_irw_azimuth_{P}_theory_m"] = irw, th
    return m, {"image": acc.astype(np.complex64), "resolution": res}


#: Processings compared on the true relative orbit (platform.trajectory keplerian).
TRAJECTORY_PROCESSINGS = ("true", "tangent", "line")


def _focus_with(raw, sc: Scenario, positions: np.ndarray):
    """Focus ``raw`` as if the antenna had been at ``positions`` (what a processor assumes)."""
    r = raw.copy(deep=True)
    r["position"].values[:] = positions
    r["velocity"].values[:] = np.gradient(positions, r["slow_time"].values, axis=0)
    return focus(r, sc.processing, scenario=sc)


#: What :func:`trajectory_point` measures of each processing.
TRAJECTORY_QUANTITIES = ("irw_azimuth_m", "irw_azimuth_theory_m", "pslr_azimuth_db", "peak_ratio",
                         "peak_offset_azimuth_m", "peak_phase_rad")


def trajectory_point(data: dict, metrics=(), keep_images: bool = False) -> dict:
    """One squint of the trajectory study, as a sweep point: a noise-free point target simulated
    on the true relative orbit, focused with the true positions, the tangent line and the seed's
    straight line at V (:func:`trajectory_study`).

    Parameters
    ----------
    data : dict
        The sub-aperture (keplerian trajectory, one point target) as plain data.
    metrics, keep_images
        Unused.

    Returns
    -------
    dict
        A sweep record: metrics ``<processing>_<quantity>`` (:data:`TRAJECTORY_QUANTITIES`, the
        peak ratio against the true processing's), and as ``payload`` each processing's image
        intensity, for the stack.
    """
    t0 = time.perf_counter()
    sk = parse_scenario(data)
    sl = sk.model_copy(update={"platform": sk.platform.model_copy(update={"trajectory": "straight", "orbit": None})})
    raw = simulate(sk)
    true_pos = raw["position"].values
    mid = len(true_pos) // 2
    vel = np.gradient(true_pos, raw["slow_time"].values, axis=0)[mid]
    tangent = true_pos[mid] + np.outer(raw["slow_time"].values - raw["slow_time"].values[mid], vel)
    images = {"true": focus(raw, sk.processing, scenario=sk), "tangent": _focus_with(raw, sk, tangent),
              "line": _focus_with(raw, sl, build_collection(sl).positions)}
    out, payload, ref = {}, {}, None
    for k, img in images.items():
        a = img["image"].values
        payload[k] = np.abs(a) ** 2
        mm = measure(img)
        ref = mm["peak_amplitude"] if ref is None else ref
        vals = {**{q: mm[q] for q in TRAJECTORY_QUANTITIES if q != "peak_ratio"}, "peak_ratio": mm["peak_amplitude"] / ref}
        out.update({f"{k}_{q}": float(vals[q]) for q in TRAJECTORY_QUANTITIES})
    return {"status": "ok", "metrics": out, "seconds": time.perf_counter() - t0, "payload": payload}


def trajectory_study(base: Scenario, squints, grid=None) -> tuple[dict, dict]:
    """A noise-free point target simulated on the true relative orbit at each squint (a squint sweep
    through the study engine, :func:`trajectory_point` at each), focused three ways: with the true positions (BP), with the straight line tangent to the true path at the
    sub-aperture's centre, and with the seed's straight line at V; and the incoherent stack of
    each over the squints.

    Parameters
    ----------
    base : Scenario
        One sub-aperture on the keplerian trajectory (:func:`salkit.stack.geo_base`).
    squints : sequence of float
        deg.
    grid : Grid, optional
        Image grid (default: 8 mm along track, fine enough for either attitude's resolution).

    Returns
    -------
    (dict, dict)
        Metrics (``trajectory_<processing>_<quantity>_squint_<q>``, ``trajectory_stack_<processing>_*``)
        and figure data (per processing: IRW, PSLR and peak ratio against squint).
    """
    g = grid or base.processing.grid.model_copy(update={"nx": 160, "ny": 48, "dx": 0.008, "dy": 0.03})
    ds, payloads = squint_sweep(point_target(base, g), squints, trajectory_point)
    m, fig, stacks = {}, {k: {"irw": [], "pslr": [], "peak": []} for k in TRAJECTORY_PROCESSINGS}, {}
    for i, q in enumerate(squints):
        for k in TRAJECTORY_PROCESSINGS:
            for name in TRAJECTORY_QUANTITIES:
                m[f"trajectory_{k}_{name}_squint_{q:g}"] = float(ds[f"{k}_{name}"].values[i, 0])
            fig[k]["irw"].append(float(ds[f"{k}_irw_azimuth_m"].values[i, 0]))
            fig[k]["pslr"].append(float(ds[f"{k}_pslr_azimuth_db"].values[i, 0]))
            fig[k]["peak"].append(float(ds[f"{k}_peak_ratio"].values[i, 0]))
            stacks[k] = payloads[i][k] + stacks.get(k, 0.0)
    ref = stacks["true"].max()
    for k, s in stacks.items():
        i = np.unravel_index(np.argmax(s), s.shape)
        cut = np.sqrt(s[:, i[1]])
        m[f"trajectory_stack_{k}_peak_ratio"] = float(s.max() / ref)
        m[f"trajectory_stack_{k}_irw_azimuth_m"] = float(ipr_1d(cut, g.dx, g.dx * 2)["irw"])
    fig["squints"] = [float(q) for q in squints]
    return m, fig


def run(scenario: Scenario, out_dir, progress: Progress = None) -> RunResult:
    """Run the seed 001 experiment: sub-images, a photon-limited single image, the stack.

    Parameters
    ----------
    scenario : Scenario
        With ``experiment.kind = spaceborne_geo``.
    out_dir : path
        The run folder: the stack's checkpoint ``stack.zarr`` lives there (a killed run resumes).
    progress : callable, optional
        ``progress(stage, done, total)``, in sub-images.

    Returns
    -------
    RunResult
    """
    t0, exp, base = time.perf_counter(), scenario.experiment, geo_base(scenario)
    col = build_collection(base)
    check_sampling(base, col)
    metrics, squints = collection_metrics(scenario)
    check_memory(*stack_memory_estimate(base, len(squints), scenario.stack.workers),
                 "reduce stack.max_subimages, stack.workers or the grid")
    g, nz = base.processing.grid, base.receiver.noise
    az, rg = grid_axes(g)
    truth = truth_image(base, az, rg)
    i0 = int(np.argmin(np.abs(squints)))  # one photon-limited sub-image at closest approach, and its twin
    single, clean = subimage(base, squints[i0], i0, noise=True), subimage(base, squints[i0], i0, noise=False)
    if truth.max() == 0 and base.scene.objects:  # a 3-D model: where its noise-free sub-image is (smoothed)
        truth = gaussian_filter(np.abs(clean) ** 2, 3.0)
        truth /= truth.max()
    mask = binary_erosion(truth > 0.5 * truth.max(), iterations=2) if truth.max() > 0 else np.ones(truth.shape, bool)
    n_th = signal_scale(base, col, n_fast_samples(base, col)) ** 2 / nz.cnr if nz.enabled else 0.0
    metrics.update(snr_single=stack_snr(np.abs(single) ** 2, np.abs(clean) ** 2, mask), snr_single_theory=nz.snr_theory)
    store = Path(out_dir) / "stack.zarr"
    coherent = scenario.stack.mode == "coherent"
    stacked, computed = run_stack(base, squints, store, scheduler=scenario.stack.scheduler, keep_complex=coherent,
                                  workers=scenario.stack.workers, progress=stage(progress, "sub-images"))
    inten = np.asarray(zarr.open_group(str(store), mode="r")["intensity"][:])
    metrics["snr_stack"] = split_snr(inten, mask, n_th) if len(squints) >= 2 else metrics["snr_single"]
    metrics["snr_stack_theory"] = math.sqrt(len(squints)) * nz.snr_theory
    m, counts, curve = stack_curve(inten, mask, n_th, metrics["snr_single"])
    metrics.update(m)
    fig7 = {q: (uncorrect(im, az, rg, q), np.abs(im)) for q in (0.0, exp.squint_max_deg, -exp.squint_max_deg)
            for im in [subimage(base, q, 0, noise=False)]}  # before and after geometric correction
    sub_len = col.n_pulses * base.platform.speed / base.waveform.prf
    m, sq_meas, meas = resolution_against_squint(base, sub_len)
    metrics.update(m, run_s=time.perf_counter() - t0, computed_subimages=computed)
    plane = plane_from(col.track, col.center_position, g.plane)
    at = {"algorithm": "bp", "wavelength": base.waveform.wavelength, "phase_reference": "aperture_centre",
          "aperture_center": col.center_position, "carrier_frequency": base.waveform.carrier_frequency}
    data = {name: make_image_dataset(np.asarray(img).astype(np.complex64), az, rg, plane, {**at, "content": what})
            for name, img, what in (("truth.nc", truth, "truth"), ("image_single.nc", single, "single photon-limited "
                                    "sub-image"), ("image_stack.nc", np.sqrt(stacked), f"incoherent stack of "
                                    f"{len(squints)} sub-images (amplitude)"))}
    figures = {"truth": truth, "fig7": fig7, "single": np.abs(single), "stack": np.sqrt(stacked), "counts": counts,
               "curve": curve, "snr_theory": nz.snr_theory, "az": az, "rg": rg, "squints": sq_meas, "measured": meas,
               "L0": exp.r2 - exp.r1, "sub_length": sub_len, "wavelength": base.waveform.wavelength}
    if base.scene.objects:  # the model as the closest-approach sub-aperture sees it, shadowed parts marked
        res = resolution_theory(base, col)
        figures["model_view"] = model_view(base.scene.objects, col.center_position,
                                           min(res["azimuth"], res["slant_range"]) / 2)
        metrics["stack_model_3d"] = 1
    if coherent:
        m, figures["coherent"] = coherent_part(base, store, len(squints), mask, metrics["snr_stack"])
        metrics.update(m)
        data["image_stack_coherent.nc"] = make_image_dataset(figures["coherent"]["image"], az, rg, plane, {
            **at, "content": f"coherent stack of {len(squints)} sub-images (phase-aligned complex sum)"})
    if base.platform.trajectory == "keplerian":
        m, figures["trajectory"] = trajectory_study(base, (-exp.squint_max_deg, 0.0, exp.squint_max_deg / 2,
                                                           exp.squint_max_deg))
        metrics.update(m, trajectory_keplerian=1, trajectory_earth_pointing=int(exp.target_attitude == "earth_pointing"))
    return RunResult("spaceborne_geo", scenario.name, scenario.description, dump_scenario(scenario), metrics, data,
                     figures=figures)
