"""The foundation workflow: simulate -> focus -> (autofocus) -> measure, for one scenario or one
outside file. It returns a :class:`~salkit.systems.result.RunResult`; the report layer
(:func:`salkit.report.write_run`) writes ``raw.nc``, ``image.nc``, ``metrics.json``,
``scenario.yaml``, the figures and ``report.html`` after it.
"""
from __future__ import annotations

import functools
import time

import numpy as np
import xarray as xr

from ..errors import ScenarioError
from ..focus import focus, focus_to_file, image_fits
from ..geometry.collection import build_collection
from ..geometry.sampling import check_sampling, n_fast_samples, resolution_theory
from ..metrics.table import warn_undeclared
from ..metrics import brightest_window, measure, snr_against_truth
from ..params.models import Processing, Scenario
from ..params.scenario import dump_scenario, stored_scenario
from ..constants import SPEED_OF_LIGHT
from ..simulate.views import model_view
from ..simulate.linewidth import expected_peak_power_loss, phase_noise_variance
from ..simulate import simulate
from .result import Progress, RunResult, flat_numbers, stage
from ..geometry.collection import equalisation_efficiency
from ..simulate import signal_scale
from ..autofocus import autofocus, history_metrics
from ..autofocus import pulse_focus
from ..atmosphere.beam import layered_r0_spherical
from ..atmosphere.path import aperture_strehl, path_layers
from ..signals.windows import Window


def analyse_image(image: xr.Dataset, scenario: Scenario | None, moments: dict | None = None) -> tuple[dict, dict]:
    """Metrics (flat numbers) and plotting details of a focused image.

    Parameters
    ----------
    image : xarray.Dataset
    scenario : Scenario or None
        For the true reflectivity phase of the brightest target.
    moments : dict, optional
        Intensity moments of the whole image when ``image`` is its window around the brightest
        pixel (:func:`salkit.metrics.brightest_window`).

    Returns
    -------
    (dict, dict)
        Flat metrics, and :func:`salkit.metrics.measure` details.
    """
    points = scenario.scene.points if scenario is not None else ()
    phases = [t.phase for t in points] if points else None
    details = measure(image, reflectivity_phase=phases, details=True, moments=moments)
    if points and "target_index" in details:
        details["target_amplitude"] = points[details["target_index"]].amplitude
    return flat_numbers(details), details


def noise_metrics(scenario: Scenario, col, raw: xr.Dataset, image: xr.Dataset, details: dict) -> dict:
    """Photon-noise figures against the model, using the noise-free image of the same scene.

    Theory: a unit-reflectance cell on the beam axis has image CNR eta*N_s*eff (eff the beam
    equalisation efficiency), so the noise power per pixel is s^2 / (eta*N_s*eff) with s the
    per-sample signal scale. Measured noise is |noisy - clean|^2 within +-15 resolution cells of
    the brightest target (where the whole aperture contributes).

    Parameters
    ----------
    scenario : Scenario
    col : Collection
    raw, image : xarray.Dataset
    details : dict
        :func:`analyse_image` details.

    Returns
    -------
    dict
    """

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


def turbulence_metrics(scenario: Scenario, col, image: xr.Dataset, peak: float) -> dict:
    """What turbulence did to a point-target image, against the same scenario without it (noise
    off, no autofocus; one more simulation and image formation): the intensity at the target over
    the turbulence-free one (``strehl_at_target``) against its r0-based expectation
    (:func:`salkit.atmosphere.path.aperture_strehl`, for phase screens), the final peak over the
    turbulence-free peak (``peak_ratio``), and the path's two-way spherical-wave Fried parameter.

    Parameters
    ----------
    scenario : Scenario
        With an atmosphere and point targets only.
    col : Collection
    image : xarray.Dataset
        The image through turbulence before autofocus.
    peak : float
        The final image's peak amplitude (after autofocus, if any).

    Returns
    -------
    dict
    """
    atm, p = scenario.atmosphere, scenario.processing
    nz = scenario.receiver.noise
    vac = scenario.model_copy(update={"atmosphere": None, "receiver": scenario.receiver.model_copy(
        update={"noise": nz.model_copy(update={"enabled": False})})})
    ref = focus(simulate(vac), p, scenario=vac)["image"].values
    at = np.unravel_index(np.argmax(np.abs(ref)), ref.shape)  # the target's pixel
    R = float(np.linalg.norm(col.center_position))
    z, r0 = path_layers(atm.cn2, R, scenario.waveform.wavelength, atm.layers)
    u0 = col.center_position / R
    m = {"strehl_at_target": float(np.abs(image["image"].values[at]) ** 2 / np.abs(ref[at]) ** 2),
         "peak_ratio": float(peak / np.abs(ref).max()),
         "r0_two_way_m": layered_r0_spherical(r0, z, R) * 2 ** (-6 / 5)}
    if atm.model == "phase_screen":  # wave optics adds amplitude scintillation: no closed form here
        w = Window(p.window, p.taylor_nbar, p.taylor_sll)(col.n_pulses)
        m["strehl_at_target_theory"] = aperture_strehl(z, r0, R, col.positions, w, u0, atm.outer_scale,
                                                       atm.inner_scale)
    return m


def linewidth_metrics(scenario: Scenario, col, image: xr.Dataset) -> dict:
    """What the laser's phase noise did to a point-target image, against the same scenario with a
    perfectly coherent laser (noise off; one more simulation and image formation): the intensity at
    the target over the coherent one (``peak_power_loss``) against exp(-sigma^2), sigma^2 = 2 pi
    linewidth |tau - tau_LO| at the scene centre, with the pedestal the noise leaves
    (:func:`salkit.simulate.linewidth.expected_peak_power_loss`; :mod:`salkit.simulate.linewidth`).

    Parameters
    ----------
    scenario : Scenario
        With ``waveform.linewidth`` > 0 and point targets only.
    col : Collection
    image : xarray.Dataset
        The image before autofocus.

    Returns
    -------
    dict
    """
    nz = scenario.receiver.noise
    coherent = scenario.model_copy(update={
        "waveform": scenario.waveform.model_copy(update={"linewidth": 0.0}),
        "receiver": scenario.receiver.model_copy(update={"noise": nz.model_copy(update={"enabled": False})})})
    ref = focus(simulate(coherent), scenario.processing, scenario=coherent)["image"].values
    at = np.unravel_index(np.argmax(np.abs(ref)), ref.shape)  # the target's pixel
    mid = col.n_pulses // 2
    tau = 2.0 * float(np.linalg.norm(col.center_position)) / SPEED_OF_LIGHT
    lo = scenario.receiver.lo_delay
    tau_lo = 2.0 * float(col.reference_range[mid]) / SPEED_OF_LIGHT if lo is None else lo
    wf, rx, p = scenario.waveform, scenario.receiver, scenario.processing
    win = Window(p.window, p.taylor_nbar, p.taylor_sll)
    n = max(1, min(n_fast_samples(scenario, col), int(round(wf.pulse_width * rx.adc_rate))))  # samples with the echo
    return {"peak_power_loss": float(np.abs(image["image"].values[at]) ** 2 / np.abs(ref[at]) ** 2),
            "peak_power_loss_theory": expected_peak_power_loss(wf.linewidth, tau - tau_lo, 1.0 / rx.adc_rate, win(n),
                                                               win(col.n_pulses)),
            "phase_noise_variance_theory": phase_noise_variance(wf.linewidth, tau - tau_lo)}


def autofocus_image(image: xr.Dataset, scenario: Scenario | None, method: str | None = None,
                   kernel: str | None = None, max_iter: int | None = None):
    """Autofocus a formed image; its metrics before, and the history.

    Parameters
    ----------
    image : xarray.Dataset
    scenario : Scenario or None
        For the defaults of ``method``, ``kernel`` and ``max_iter`` (its processing block).
    method : {"pga", "min-entropy"}, optional
    kernel : {"pd", "lumv", "ev"}, optional
    max_iter : int, optional

    Returns
    -------
    (xarray.Dataset, AutofocusResult, dict)
        The focused image, the result with its history, and ``before_autofocus_*`` metrics.
    """

    p = scenario.processing if scenario is not None else None
    method = method or p.autofocus
    kernel = kernel or (p.autofocus_kernel if p else "lumv")
    max_iter = max_iter or (p.autofocus_max_iter if p else 30)
    before, _ = analyse_image(image, scenario)
    af, res = autofocus(image, method, kernel=kernel, max_iter=max_iter)
    m = {f"before_autofocus_{k}": v for k, v in before.items()
         if k.startswith(("irw_", "pslr_", "islr_", "entropy", "contrast", "peak_"))}
    m.update(history_metrics(res))
    res.title = f"{method} ({kernel})"
    return af, res, m


def run(scenario: Scenario, out_dir=None, progress: Progress = None) -> RunResult:
    """Simulate, focus, autofocus (if asked) and measure one scenario.

    Parameters
    ----------
    scenario : Scenario
    out_dir : path, optional
        Unused (this workflow keeps no checkpoint).
    progress : callable, optional
        ``progress(stage, done, total)``.

    Returns
    -------
    RunResult
        ``raw.nc``, ``image.nc`` (and ``image_focus.nc``, the image before autofocus), the
        metrics against theory, and what the figures need.
    """
    col = build_collection(scenario)
    samp = check_sampling(scenario, col)  # before any work
    p = scenario.processing
    t0 = time.perf_counter()
    raw = simulate(scenario, progress=stage(progress, "pulses simulated"))
    t_sim, t0 = time.perf_counter() - t0, time.perf_counter()
    data = {"raw.nc": raw}
    image, af_metrics, af_res = focus_and_autofocus(raw, scenario, data, p, progress=progress)
    t_focus = time.perf_counter() - t0
    metrics, details = analyse_image(image, scenario)
    metrics.update(af_metrics)
    metrics.update({f"sampling_{k}": v for k, v in samp.as_dict().items()})
    metrics.update({"n_pulses": raw.sizes["slow_time"], "n_samples": raw.sizes["fast_time"],
                    "simulate_s": t_sim, "focus_s": t_focus,
                    "extended_scene": int(scenario.scene.extended is not None or bool(scenario.scene.objects))})  # in clutter
    if scenario.receiver.noise.enabled:
        metrics.update(noise_metrics(scenario, col, raw, image, details))
    if scenario.atmosphere is not None and scenario.scene.extended is None:
        metrics.update(turbulence_metrics(scenario, col, data.get("image_focus.nc", image), metrics["peak_amplitude"]))
    if scenario.waveform.linewidth > 0 and scenario.scene.extended is None and not scenario.scene.objects:
        metrics.update(linewidth_metrics(scenario, col, data.get("image_focus.nc", image)))
    view = None
    if scenario.scene.objects:  # the model as the sensor sees it, shadowed parts marked
        res = resolution_theory(scenario, col)
        view = model_view(scenario.scene.objects, col.center_position, min(res["azimuth"], res["slant_range"]) / 2)
        metrics["object_samples_hidden_fraction"] = float(np.mean(view["state"] == 1) / max(np.mean(view["state"] < 2), 1e-12))
    return RunResult("airborne", scenario.name, scenario.description, dump_scenario(scenario), metrics, data,
                     figures={"details": details, "autofocus": af_res, "raw": raw, "model_view": view,
                              "timings": {"simulate_s": t_sim, "focus_s": t_focus}})


def focus_and_autofocus(raw: xr.Dataset, scenario: Scenario | None, data: dict, processing: Processing | None = None,
                        progress: Progress = None, autofocus: str | None = None, kernel: str | None = None,
                        **options):
    """Focus ``raw`` and autofocus the way ``autofocus`` (default: the scenario's) says: ``pulse``
    corrects the phase history before focusing, ``pga``/``min-entropy`` the formed image. The
    image before autofocus goes into ``data["image_focus.nc"]``, the final one into
    ``data["image.nc"]``.

    Parameters
    ----------
    raw : xarray.Dataset
    scenario : Scenario or None
    data : dict
        File name -> dataset, filled in.
    processing : Processing, optional
    progress : callable, optional
        ``progress(stage, done, total)``.
    autofocus, kernel : str, optional
    **options
        ``algorithm``, ``window_name``, ``grid``, ``plane`` for :func:`salkit.focus.focus`.

    Returns
    -------
    (xarray.Dataset, dict, AutofocusResult or None)
    """
    method = autofocus or (scenario.processing.autofocus if scenario is not None else "none")
    af_metrics, af_res = {}, None
    proc = processing or (scenario.processing if scenario is not None else None)
    alg = options.get("algorithm") or (proc.algorithm if proc is not None else "bp")
    unit = "levels merged" if alg == "ffbp" else "pulses focused"  # ffbp reports its levels
    if method == "pulse":  # the phase history is corrected on the pixels of the first image, then refocused
        form = functools.partial(focus, processing=processing, scenario=scenario, **options)
        image, data["image_focus.nc"], af_metrics = pulse_focus(
            raw, form, proc.chirp_correction if proc is not None else "none", progress=stage(progress, unit),
            phase_noise_correction=proc.phase_noise_correction if proc is not None else "none")
    else:
        image = focus(raw, processing, scenario=scenario, progress=stage(progress, unit), **options)
    if method not in ("none", "pulse"):
        data["image_focus.nc"] = image
        image, af_res, af_metrics = autofocus_image(image, scenario, method, kernel)
    data["image.nc"] = image
    return image, af_metrics, af_res


def focus_file(raw: xr.Dataset, processing: Processing | None = None, progress: Progress = None,
               autofocus: str | None = None, kernel: str | None = None, image_file=None, **options) -> RunResult:
    """Focus an existing raw file (with the scenario it carries, if any) and measure the image.

    Parameters
    ----------
    raw : xarray.Dataset
        Raw data or a phase history (:func:`salkit.io.read_phase_data`).
    processing : Processing, optional
    progress : callable, optional
    autofocus : {"none", "pga", "min-entropy", "pulse"}, optional
    kernel : {"pd", "lumv", "ev"}, optional
    image_file : path, optional
        Where ``image.nc`` will be written: an image larger than the memory budget
        (:func:`salkit.focus.image_fits`) is formed tile by tile straight into it
        (:func:`salkit.focus.focus_to_file`), measured on the window around its brightest pixel and
        drawn from every k-th pixel; it cannot then be autofocused.
    **options
        ``algorithm``, ``window_name``, ``grid``, ``plane``, ``accuracy``, ``memory_limit``,
        ``client``, ``upsample`` for :func:`salkit.focus.focus`.

    Returns
    -------
    RunResult
    """
    scenario = stored_scenario(raw.attrs)
    if not isinstance(scenario, Scenario):
        scenario = None
    t0 = time.perf_counter()
    data: dict = {}
    if image_file is not None and not image_fits(raw, processing, grid=options.get("grid"),
                                                 algorithm=options.get("algorithm"),
                                                 memory_limit=options.get("memory_limit"),
                                                 client=options.get("client"), accuracy=options.get("accuracy"),
                                                 upsample=options.get("upsample")):
        if autofocus not in (None, "none"):
            raise ScenarioError("--autofocus", autofocus, "needs the whole image in memory; this image is larger "
                                "than the budget and is formed tile by tile into its file (raise --memory-limit)")
        image = focus_to_file(raw, image_file, processing, scenario=scenario, progress=stage(progress, "tiles formed"),
                              **options)
        data["image.nc"] = image
        t_focus = time.perf_counter() - t0
        window, moments = brightest_window(image)
        metrics, details = analyse_image(window, scenario, moments=moments)
        metrics.update(focus_s=t_focus, image_out_of_core=1)
        warn_undeclared(metrics, "focusing a file")
        return RunResult("airborne", scenario.name if scenario else "external data",
                         scenario.description if scenario else "",
                         raw.attrs.get("scenario", "# no scenario stored in the raw file\n"), metrics, data,
                         figures={"details": details, "autofocus": None, "timings": {"focus_s": t_focus}})
    image, af_metrics, af_res = focus_and_autofocus(raw, scenario, data, processing, progress, autofocus, kernel,
                                                    **options)
    t_focus = time.perf_counter() - t0
    metrics, details = analyse_image(image, scenario)
    metrics.update(af_metrics)
    metrics["focus_s"] = t_focus
    warn_undeclared(metrics, "focusing a file")
    return RunResult("airborne", scenario.name if scenario else "external data",
                     scenario.description if scenario else "",
                     raw.attrs.get("scenario", "# no scenario stored in the raw file\n"), metrics, data,
                     figures={"details": details, "autofocus": af_res, "timings": {"focus_s": t_focus}})


__all__ = ["analyse_image", "autofocus_image", "focus_and_autofocus", "focus_file", "noise_metrics",
           "run"]
