"""The foundation system: simulate -> focus -> measure -> figures -> report, for one scenario.

Every file in the output folder is written atomically; ``raw.nc``, ``image.nc``,
``metrics.json``, ``scenario.yaml``, the PNG figures and ``report.html``.
"""
from __future__ import annotations

import time
from pathlib import Path
from typing import Callable, Optional

import numpy as np
import xarray as xr

from .. import __version__
from ..focus import focus, grid_of
from ..geometry.collection import build_collection
from ..geometry.sampling import check_sampling
from ..io.datasets import write_dataset, write_json_atomic, write_text_atomic
from ..metrics import measure, snr_against_truth
from ..metrics.pointtarget import cut_curves
from ..params.models import Processing, Scenario
from ..params.scenario import dump_scenario, stored_scenario
from ..simulate import simulate

Progress = Optional[Callable[[str, int, int], None]]


def _flat_numbers(d: dict) -> dict:
    out = {}
    for k, v in d.items():
        if k.startswith("_"):
            continue
        if isinstance(v, (bool, np.bool_)):
            out[k] = int(v)
        elif isinstance(v, (int, float, np.integer, np.floating)):
            out[k] = float(v) if isinstance(v, (float, np.floating)) else int(v)
    return out


def run_memory_estimate(scenario: Scenario) -> tuple[float, str]:
    """Peak memory of :func:`run`: the larger of simulating and of focusing while the raw signal is
    held (:func:`salkit.simulate.memory_estimate`, :func:`salkit.focus.memory_estimate`), bytes.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (float, str)
    """
    from ..focus import memory_estimate as focus_estimate
    from ..simulate import memory_estimate as simulate_estimate, signal_shape

    sim, _ = simulate_estimate(scenario)
    P, N = signal_shape(scenario)
    g = scenario.processing.grid
    foc, _ = focus_estimate(P, N, g.nx, g.ny, scenario.processing.algorithm, raw=True)
    return max(sim, foc + 8.0 * P * N), (f"simulating and focusing {P} pulses x {N} samples "
                                         f"({8.0 * P * N / 2 ** 30:.3g} GiB of signal) onto {g.nx} x {g.ny} pixels")


def analyse_image(image: xr.Dataset, scenario: Scenario | None) -> tuple[dict, dict]:
    """Metrics (flat numbers) and plotting details of a focused image."""
    details = measure(image, details=True)
    if scenario is not None and scenario.scene.points and "target_index" in details:
        t = scenario.scene.points[details["target_index"]]
        details = measure(image, reflectivity_phase=t.phase, details=True)
        details["target_amplitude"] = t.amplitude
    return _flat_numbers(details), details


def noise_metrics(scenario: Scenario, col, raw: xr.Dataset, image: xr.Dataset, details: dict) -> dict:
    """Photon-noise figures against the model, using the noise-free image of the same scene.

    Theory: a unit-reflectance cell on the beam axis has image CNR eta*N_s*eff (eff the beam
    equalisation efficiency), so the noise power per pixel is s^2 / (eta*N_s*eff) with s the
    per-sample signal scale. Measured noise is |noisy - clean|^2 within +-15 resolution cells of
    the brightest target (where the whole aperture contributes).
    """
    from ..geometry.collection import equalisation_efficiency
    from ..simulate import signal_scale

    nz = scenario.receiver.noise
    clean = simulate(scenario, noise=False)
    truth_img = focus(clean, scenario.processing, scenario=scenario)["image"].values
    img = image["image"].values
    s = signal_scale(scenario, col, raw.sizes["fast_time"])
    eff = equalisation_efficiency(scenario, col)
    n_th = s ** 2 / (nz.cnr * eff)
    az, rg = image["azimuth"].values, image["range"].values
    i0 = int(np.argmin(np.abs(az - details["peak_azimuth_m"])))
    j0 = int(np.argmin(np.abs(rg - details["peak_range_m"])))
    hx = max(int(15 * image.attrs["resolution_azimuth"] / (az[1] - az[0])), 4)
    hy = max(int(15 * image.attrs["resolution_range"] / (rg[1] - rg[0])), 4)
    win = (slice(max(i0 - hx, 0), i0 + hx + 1), slice(max(j0 - hy, 0), j0 + hy + 1))
    npow = float(np.mean(np.abs(img[win] - truth_img[win]) ** 2))
    peak = float(np.abs(truth_img).max() ** 2)
    out = {"noise_power": npow, "noise_power_theory": n_th, "equalisation_efficiency": eff,
           "image_cnr_theory": nz.cnr * eff, "cnr_peak": peak / npow, "cnr_peak_theory": peak / n_th}
    ext = scenario.scene.extended
    if ext is not None and ext.speckle and ext.kind == "pattern" and ext.pattern == "uniform":
        res_a, res_r = image.attrs["resolution_azimuth"], image.attrs["resolution_range"]
        A, Rg = np.meshgrid(az, rg, indexing="ij")
        plane_y = Rg  # ground extent mapped conservatively: stay 3 cells inside both edges
        mask = (np.abs(A) < ext.extent[0] / 2 - 3 * res_a) & (np.abs(plane_y) < ext.extent[1] / 2 * 0.7 - 3 * res_r)
        for t in scenario.scene.points:  # keep clear of point targets
            mask &= np.hypot((A - t.x) / res_a, (Rg - t.y) / res_r) > 8
        if mask.sum() > 50:
            S = float(np.mean(np.abs(truth_img[mask]) ** 2))
            out["image_snr"] = snr_against_truth(img, truth_img, mask)
            out["image_snr_theory"] = S / (S + n_th)
            out["image_snr_mean_cell_cnr"] = S / n_th
    return out


def run_autofocus(image: xr.Dataset, scenario: Scenario | None, out: Path, method: str | None = None,
                  kernel: str | None = None, max_iter: int | None = None):
    """Autofocus an image; keep the focused one as image_focus.nc; metrics before/after and history."""
    from .. import plot
    from ..autofocus import autofocus, history_metrics

    p = scenario.processing if scenario is not None else None
    method = method or p.autofocus
    kernel = kernel or (p.autofocus_kernel if p else "lumv")
    max_iter = max_iter or (p.autofocus_max_iter if p else 30)
    write_dataset(image, out / "image_focus.nc")
    before, _ = analyse_image(image, scenario)
    af, res = autofocus(image, method, kernel=kernel, max_iter=max_iter)
    m = {f"before_autofocus_{k}": v for k, v in before.items()
         if k.startswith(("irw_", "pslr_", "islr_", "entropy", "contrast", "peak_"))}
    m.update(history_metrics(res))
    plot.autofocus_history(res, out / "autofocus.png", title=f"{method} ({kernel})")
    return af, res, m


def pulse_correct(raw: xr.Dataset, grid, chirp_correction: str = "none") -> tuple[xr.Dataset, dict]:
    """Per-pulse autofocus of ``raw`` on ``grid``: the corrected phase history and its metrics."""
    from ..autofocus import pulse_autofocus, pulse_metrics

    corrected, res = pulse_autofocus(raw, grid, chirp_correction=chirp_correction)
    m = pulse_metrics(res)
    m["autofocus_s"] = float(corrected.attrs.get("autofocus_s", 0.0))
    return corrected, m


def report_outputs(out: Path, image: xr.Dataset, metrics: dict, details: dict, scenario_text: str,
                   name: str, description: str, timings: dict, raw: xr.Dataset | None = None) -> None:
    """Write metrics.json, figures and report.html for a focused image."""
    from .. import plot
    from ..report import comparison_rows, write_report

    truth = None
    if "target_azimuth" in image:
        truth = np.stack([image["target_azimuth"].values, image["target_range"].values], axis=1)
    figs = [("Focused image (dB)", "image.png")]
    plot.image_db(image, out / "image.png", title=f"{name}: {image.attrs.get('algorithm')} image", truth=truth)
    if "_cut_range" in details:
        plot.cuts(cut_curves(details, image.attrs), metrics, out / "cuts.png")
        figs.append(("Cuts through the brightest target against theory", "cuts.png"))
    if (out / "autofocus.png").exists():
        figs.append(("Autofocus history", "autofocus.png"))
    if raw is not None and "fast_time" in raw:
        plot.raw_phase_history(raw, out / "raw.png")
        figs.append(("Raw dechirped data", "raw.png"))
    write_json_atomic(out / "metrics.json", metrics)
    files = sorted(p.name for p in out.iterdir() if not p.name.startswith("."))
    write_report(out, {
        "name": name, "description": description, "version": __version__,
        "algorithm": image.attrs.get("algorithm"), "window": image.attrs.get("window"),
        "t_simulate": timings.get("simulate_s", 0.0), "t_focus": timings.get("focus_s", 0.0),
        "figures": [{"title": t, "file": f} for t, f in figs],
        "rows": comparison_rows(metrics), "metrics": metrics, "files": files + ["report.html"],
        "scenario": scenario_text,
    })


def run(scenario: Scenario, out_dir: str | Path, progress: Progress = None) -> dict:
    """Run a scenario end to end and write every output into ``out_dir``.

    Parameters
    ----------
    scenario : Scenario
    out_dir : str or Path
    progress : callable, optional
        ``progress(stage, done, total)``.

    Returns
    -------
    dict
        The metrics written to ``metrics.json``.
    """
    col = build_collection(scenario)
    samp = check_sampling(scenario, col)  # before any work, before anything is written
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    text = dump_scenario(scenario)
    write_text_atomic(out / "scenario.yaml", text)
    t0 = time.perf_counter()
    cb = (lambda d, n: progress("simulate", d, n)) if progress else None
    raw = simulate(scenario, progress=cb)
    t_sim = time.perf_counter() - t0
    write_dataset(raw, out / "raw.nc")
    t0 = time.perf_counter()
    cb = (lambda d, n: progress("focus", d, n)) if progress else None
    af_metrics, af_res = {}, None
    if scenario.processing.autofocus == "pulse":
        write_dataset(focus(raw, scenario.processing, scenario=scenario), out / "image_focus.nc")
        corrected, af_metrics = pulse_correct(raw, scenario.processing.grid, scenario.processing.chirp_correction)
        image = focus(corrected, scenario.processing, progress=cb)
    else:
        image = focus(raw, scenario.processing, scenario=scenario, progress=cb)
    t_focus = time.perf_counter() - t0
    if scenario.processing.autofocus not in ("none", "pulse"):
        image, af_res, af_metrics = run_autofocus(image, scenario, out)
    write_dataset(image, out / "image.nc")
    metrics, details = analyse_image(image, scenario)
    metrics.update(af_metrics)
    metrics.update({f"sampling_{k}": v for k, v in samp.as_dict().items()})
    metrics.update({"n_pulses": raw.sizes["slow_time"], "n_samples": raw.sizes["fast_time"],
                    "simulate_s": t_sim, "focus_s": t_focus})
    nz = scenario.receiver.noise
    if nz.enabled:
        metrics.update(noise_metrics(scenario, col, raw, image, details))
    report_outputs(out, image, metrics, details, text, scenario.name, scenario.description,
                   {"simulate_s": t_sim, "focus_s": t_focus}, raw)
    return metrics


def focus_file(raw: xr.Dataset, out_dir: str | Path, processing: Processing | None = None,
               algorithm: str | None = None, window_name: str | None = None, grid=None,
               progress: Progress = None, autofocus: str | None = None, kernel: str | None = None,
               plane: str | None = None) -> dict:
    """Focus an existing raw file and write image.nc, metrics.json, figures and report.html."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    scenario = stored_scenario(raw.attrs)
    if not isinstance(scenario, Scenario):
        scenario = None
    t0 = time.perf_counter()
    cb = (lambda d, n: progress("focus", d, n)) if progress else None
    af_metrics = {}
    method = autofocus or (scenario.processing.autofocus if scenario is not None else "none")
    if method == "pulse":
        before = focus(raw, processing, algorithm=algorithm, window_name=window_name, grid=grid, plane=plane)
        write_dataset(before, out / "image_focus.nc")
        cc = processing or (scenario.processing if scenario is not None else None)
        raw, af_metrics = pulse_correct(raw, grid_of(before),  # the pixels of the image
                                        cc.chirp_correction if cc is not None else "none")
    image = focus(raw, processing, algorithm=algorithm, window_name=window_name, grid=grid, plane=plane,
                  progress=cb)
    t_focus = time.perf_counter() - t0
    if method not in ("none", "pulse"):
        image, _, af_metrics = run_autofocus(image, scenario, out, method, kernel)
    write_dataset(image, out / "image.nc")
    metrics, details = analyse_image(image, scenario)
    metrics.update(af_metrics)
    metrics["focus_s"] = t_focus
    text = raw.attrs.get("scenario", "# no scenario stored in the raw file\n")
    write_text_atomic(out / "scenario.yaml", text)
    name = scenario.name if scenario else "external data"
    report_outputs(out, image, metrics, details, text, name, scenario.description if scenario else "",
                   {"focus_s": t_focus})
    return metrics


__all__ = ["analyse_image", "focus_file", "run"]
