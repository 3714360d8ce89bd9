"""Space-borne SAL of a GEO target (seed 001): squinted sub-apertures and incoherent stacking.

Sub-aperture p of the collection is centred at along-track offset u_p = L0 tan(theta_p) on the
straight-line model (or the true relative trajectory), has length L_sa and forms one sub-image
by backprojection onto the common target-frame grid: exact for any squint, so the sub-image is
already geometrically corrected (eq 11 maps the squinted slant frame to this one). Each
sub-aperture has its own photon noise; the scene's scatterers are the same physical target, so
its speckle decorrelates between sub-apertures through the change of aspect alone.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..focus import focus
from ..params.models import Scenario
from ..simulate import simulate


def squint_of(index: int, count: int, squint_max_deg: float) -> float:
    """Squint (deg) of sub-aperture ``index`` of ``count`` spread evenly over +-squint_max."""
    if count == 1:
        return 0.0
    return -squint_max_deg + 2 * squint_max_deg * (index + 0.5) / count


def subaperture(base: Scenario, squint_deg: float, noise_seed: int) -> Scenario:
    """The scenario of one sub-aperture: same target and grid, its squint, its own noise seed."""
    p = base.platform.model_copy(update={"squint_deg": squint_deg})
    return base.model_copy(update={"platform": p, "seed": noise_seed})


def subimage(base: Scenario, squint_deg: float, noise_seed: int, noise: bool = True) -> np.ndarray:
    """Complex sub-image on the common target grid. The scene (speckle) uses ``base.seed``; the
    photon noise uses ``noise_seed``."""
    sc = subaperture(base, squint_deg, base.seed)
    rng = np.random.default_rng(base.seed)  # the scene (speckle) draws first: the same target every time
    raw = simulate(sc, noise=False, rng=rng)
    if noise and base.receiver.noise.enabled:
        from ..simulate import photon_noise
        sig = raw["signal"].values.copy()
        photon_noise(sig, base.receiver.noise, np.random.default_rng(10_000_019 + noise_seed))
        raw["signal"].values[...] = sig
    return focus(raw, sc.processing, scenario=sc)["image"].values


def stack(base: Scenario, count: int, squint_max_deg: float, noise: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Incoherent stack (mean intensity) of ``count`` sub-images, and the first sub-image."""
    acc = None
    first = None
    for i in range(count):
        img = subimage(base, squint_of(i, count, squint_max_deg), i, noise)
        first = img if first is None else first
        acc = np.abs(img) ** 2 if acc is None else acc + np.abs(img) ** 2
    return acc / count, first


def split_snr(intensities: np.ndarray, mask: np.ndarray, noise_power: float) -> float:
    """SNR of the mean of independent intensity images: (mean - noise power) over the standard
    deviation of the random part, estimated from two independent half-stacks (odd and even):
    std((A - B)/2). The target's deterministic intensity pattern (edges, structure, sidelobes)
    cancels in A - B, so only speckle and noise are counted, as in eqs 14-16."""
    A = intensities[0::2].mean(axis=0)
    B = intensities[1::2].mean(axis=0)
    full = intensities.mean(axis=0)
    rand = float(np.std((A - B)[mask])) / 2 * math.sqrt(
        4 * len(intensities[0::2]) * len(intensities[1::2]) / len(intensities) ** 2)
    return float((full[mask].mean() - noise_power) / rand)


def coherent_stack(images, align: bool = True):
    """Coherent sum of complex sub-images on the common grid, with phase alignment.

    Backprojection keeps absolute phase, so sub-images of one phase-coherent collection add in
    phase and their sum is the image of the combined (longer) aperture: finer along-track
    resolution, not lower speckle. Real collections drift in phase between sub-apertures (laser
    phase, residual motion), so each sub-image's constant offset is estimated against the running
    sum, arg sum(img conj(acc)), and removed before it is added.

    Returns
    -------
    (sum, offsets) : complex ndarray, and the removed phase of each sub-image (rad)
    """
    acc = None
    offsets = []
    for img in images:
        if acc is None:
            acc = np.asarray(img, dtype=np.complex128).copy()
            offsets.append(0.0)
            continue
        phi = float(np.angle(np.vdot(acc, img))) if align else 0.0  # vdot conjugates acc
        acc += img * np.exp(-1j * phi)
        offsets.append(phi)
    return acc, np.asarray(offsets)


def stack_snr(stacked_intensity: np.ndarray, clean_intensity: np.ndarray, mask: np.ndarray) -> float:
    """SNR of a (stacked) intensity image against the truth: mean signal intensity / std."""
    return float(clean_intensity[mask].mean() / stacked_intensity[mask].std())




def _subimage_chunk_task(base_dict: dict, indices: list, squints: list, noise: bool):
    """Dask task: the intensities of a chunk of sub-images (top level, so workers can import it).

    Chunks amortise the per-task costs (scheduling, parsing the scenario) that otherwise take twice
    the compute of a sub-image."""
    from ..params.scenario import parse_scenario
    base = parse_scenario(base_dict)
    out = np.stack([np.abs(subimage(base, q, i, noise)) ** 2 for i, q in zip(indices, squints)])
    return list(indices), out.astype(np.float32)


def stack_memory_estimate(base: Scenario, count: int, workers: int) -> tuple[float, str]:
    """Peak memory of stacking ``count`` sub-images of ``base`` with ``workers`` local workers, bytes:
    one sub-image simulated and focused per worker and in this process, plus the (count, nx, ny)
    float32 intensity stack read back for the SNR curves.

    Parameters
    ----------
    base : Scenario
        One sub-image's scenario.
    count : int
    workers : int

    Returns
    -------
    (float, str)
    """
    from .airborne import run_memory_estimate
    one, _ = run_memory_estimate(base)
    g = base.processing.grid
    stack_bytes = 4.0 * count * g.nx * g.ny
    return (workers + 1) * one + 2 * stack_bytes, (f"stacking {count} sub-images of {g.nx} x {g.ny} pixels on "
                                                   f"{workers} worker(s)")


def run_stack(base: Scenario, squints, store, scheduler: str | None = None,
              workers: int = 2, noise: bool = True, progress=None, stop_after: int | None = None,
              chunk: int | None = None):
    """Stack ``count`` sub-images as Dask tasks, checkpointed in a Zarr store.

    Parameters
    ----------
    base : Scenario
    squints : sequence of float
        Squint (deg) of each sub-aperture.
    store : str or Path
        Zarr store: ``intensity`` (count, nx, ny) float32, one chunk per sub-image, and ``done``
        (count,) flags written after each chunk. A run that is killed resumes from the flags and
        recomputes nothing already stored.
    scheduler : str, optional
        Address of an existing Dask scheduler; default: a local cluster of ``workers`` processes.
    progress : callable, optional
        ``progress(done, total)``.
    stop_after : int, optional
        Stop (raise KeyboardInterrupt) after this many new sub-images: simulates a killed run.
    chunk : int, optional
        Sub-images per Dask task (default: up to 64, at least 4 tasks per worker).

    Returns
    -------
    (stack, computed)
        The mean intensity over all stored sub-images and how many this call computed.
    """
    import zarr
    from dask.distributed import Client, LocalCluster, as_completed

    from ..errors import SalkitError
    from ..params.scenario import dump_scenario

    cluster = None
    try:  # connect first: an unreachable scheduler writes nothing
        if scheduler:
            client = Client(scheduler, timeout="5s")
        else:
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            client = Client(cluster)
    except (OSError, TimeoutError) as err:
        from ..errors import EnvironmentProblem
        raise EnvironmentProblem(f"--scheduler {scheduler}: no Dask scheduler answers there "
                                 f"({type(err).__name__})") from None
    try:
        squints = [float(q) for q in squints]
        count = len(squints)
        g = base.processing.grid
        root = zarr.open_group(str(store), mode="a")
        text = dump_scenario(base)
        if "intensity" in root:
            if root.attrs.get("scenario") != text or root.attrs.get("squints") != squints:
                raise SalkitError(f"{store}: the checkpoint belongs to another run (scenario or count differs)")
        else:
            root.create_array("intensity", shape=(count, g.nx, g.ny), chunks=(1, g.nx, g.ny), dtype="float32")
            root.create_array("done", shape=(count,), chunks=(count,), dtype="bool", fill_value=False)
            root.attrs.update({"scenario": text, "count": count, "squints": squints})
        done = np.asarray(root["done"][:])
        todo = [i for i in range(count) if not done[i]]
        computed = 0
        bd = base.model_dump(mode="json")
        size = int(chunk or max(1, min(64, len(todo) // (4 * max(workers, 1)))))
        chunks = [todo[a:a + size] for a in range(0, len(todo), size)]
        futures = [client.submit(_subimage_chunk_task, bd, ch, [squints[i] for i in ch], noise, pure=False)
                   for ch in chunks]
        for fut in as_completed(futures):
            idx, inten = fut.result()
            for i, im in zip(idx, inten):
                root["intensity"][i] = im
            done[idx] = True
            root["done"][:] = done  # flags after the data: a killed run recomputes only unflagged ones
            computed += len(idx)
            if progress:
                progress(int(done.sum()), count)
            if stop_after is not None and computed >= stop_after:
                for f in futures:
                    f.cancel()
                raise KeyboardInterrupt("stopped on request")
        stack_ = np.asarray(root["intensity"][:]).mean(axis=0)
        return stack_, computed
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def geo_base(scenario: Scenario) -> Scenario:
    """The sub-aperture scenario implied by the experiment: straight-line pass at V and L0, one
    sub-aperture L_sa long, spotlight on the target, no experiment block."""
    from ..geometry.orbit import relative_speed, subaperture_length
    exp = scenario.experiment
    L0 = exp.r2 - exp.r1
    V = relative_speed(exp.r1, exp.r2)
    L = subaperture_length(scenario.waveform.wavelength, L0, exp.resolution)
    p = scenario.platform.model_copy(update={"mode": "spotlight", "speed": V, "standoff": L0, "altitude": 0.0,
                                             "aperture_length": L, "squint_deg": 0.0, "positions": None})
    return scenario.model_copy(update={"platform": p, "experiment": None})


def nearest_squints(count: int, sub_length: float, closest: float) -> list[float]:
    """Squints (deg) of the ``count`` consecutive sub-apertures nearest closest approach."""
    k = np.arange(count) - (count - 1) / 2
    return [float(v) for v in np.degrees(np.arctan(k * sub_length / closest))]


def uncorrect(img: np.ndarray, az: np.ndarray, rg: np.ndarray, squint_deg: float) -> np.ndarray:
    """|image| resampled into the squinted frame of eq 11 (X = -x0 - z0 tan th, Y = z0 cos th +
    x0 sin th): the sub-image as a squinted processor delivers it, before geometric correction."""
    from scipy.ndimage import map_coordinates
    th = math.radians(squint_deg)
    X, Y = np.meshgrid(-az, rg, indexing="ij")
    # invert eq 11 for (x0, z0)
    A = np.array([[-1.0, -math.tan(th)], [math.sin(th), math.cos(th)]])
    inv = np.linalg.inv(A)
    x0 = inv[0, 0] * X + inv[0, 1] * Y
    z0 = inv[1, 0] * X + inv[1, 1] * Y
    ia = (x0 - az[0]) / (az[1] - az[0])
    ir = (z0 - rg[0]) / (rg[1] - rg[0])
    return map_coordinates(np.abs(img), [ia, ir], order=1, cval=0.0)


def run(scenario: Scenario, out_dir, progress=None) -> dict:
    """Run the seed 001 experiment: sub-images, photon-limited single image, stack, report."""
    import time

    from .. import plot
    from ..geometry.collection import build_collection, grid_axes, plane_from
    from ..geometry.orbit import collection_span, n_subimages, relative_speed, subaperture_length
    from ..geometry.sampling import check_sampling
    from ..resources import check_memory
    from ..io.datasets import make_image_dataset, write_dataset, write_json_atomic, write_text_atomic
    from ..params.scenario import dump_scenario
    from ..simulate import signal_scale
    from ..simulate.scene import pattern_mask
    from ..geometry.sampling import n_fast_samples

    t0 = time.perf_counter()
    exp = scenario.experiment
    base = geo_base(scenario)
    col = build_collection(base)
    check_sampling(base, col)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out / "scenario.yaml", dump_scenario(scenario))
    L0 = exp.r2 - exp.r1
    V = relative_speed(exp.r1, exp.r2)
    D = collection_span(L0, exp.squint_max_deg)
    L = subaperture_length(scenario.waveform.wavelength, L0, exp.resolution)
    P_all = n_subimages(D, L)
    count = min(P_all, scenario.stack.max_subimages or P_all)
    squints = nearest_squints(count, L, L0)
    check_memory(*stack_memory_estimate(base, count, scenario.stack.workers),
                 "reduce stack.max_subimages, stack.workers or the grid")
    metrics = {"relative_speed_m_s": V, "closest_distance_m": L0, "collection_span_m": D,
               "subaperture_length_m": L, "subimages_in_collection": P_all, "stack_count": count}
    g = base.processing.grid
    az, rg = grid_axes(g)
    plane = plane_from(col.track, col.center_position, g.plane)
    attrs = {"algorithm": "bp", "wavelength": base.waveform.wavelength, "phase_reference": "aperture_centre",
             "aperture_center": col.center_position, "carrier_frequency": base.waveform.carrier_frequency}
    # truth: the target reflectivity on the image grid
    ext = base.scene.extended
    truth = np.zeros((g.nx, g.ny))
    if ext is not None:
        A_, R_ = np.meshgrid(az, rg, indexing="ij")
        truth = pattern_mask(ext.pattern, A_ / ext.extent[0], R_ / ext.extent[1]) * ext.amplitude
    write_dataset(make_image_dataset(truth.astype(np.complex64), az, rg, plane, {**attrs, "content": "truth"}),
                  out / "truth.nc")
    # one photon-limited sub-image at closest approach, and its noise-free twin
    i0 = int(np.argmin(np.abs(squints)))
    single = subimage(base, squints[i0], i0, noise=True)
    clean = subimage(base, squints[i0], i0, noise=False)
    write_dataset(make_image_dataset(single, az, rg, plane, {**attrs, "content": "single photon-limited sub-image"}),
                  out / "image_single.nc")
    from scipy.ndimage import binary_erosion
    mask = binary_erosion(truth > 0.5 * truth.max(), iterations=2) if truth.max() > 0 else np.ones(truth.shape, bool)
    nz = base.receiver.noise
    s = signal_scale(base, col, n_fast_samples(base, col))
    n_th = s ** 2 / nz.cnr if nz.enabled else 0.0
    metrics["snr_single"] = stack_snr(np.abs(single) ** 2, np.abs(clean) ** 2, mask)
    metrics["snr_single_theory"] = nz.snr_theory
    # the stack, on Dask, checkpointed
    st = scenario.stack
    cb = (lambda d, n: progress("sub-images", d, n)) if progress else None
    stacked, computed = run_stack(base, squints, out / "stack.zarr", scheduler=st.scheduler, workers=st.workers,
                                  progress=cb)
    import zarr
    inten = np.asarray(zarr.open_group(str(out / "stack.zarr"), mode="r")["intensity"][:])
    metrics["snr_stack"] = split_snr(inten, mask, n_th) if count >= 2 else metrics["snr_single"]
    metrics["snr_stack_theory"] = math.sqrt(count) * nz.snr_theory
    counts = sorted({int(c) for c in np.unique(np.round(np.geomspace(2, count, 12)))}) if count >= 2 else [1]
    curve = []
    for c in counts:
        curve.append(split_snr(inten[:c], mask, n_th) if c >= 2 else metrics["snr_single"])
        metrics[f"snr_stack_{c}"] = curve[-1]
    write_dataset(make_image_dataset(np.sqrt(stacked).astype(np.complex64), az, rg, plane,
                                     {**attrs, "content": f"incoherent stack of {count} sub-images (amplitude)"}),
                  out / "image_stack.nc")
    # figure 7: sub-images at 0 and +-squint_max (high SNR), before and after geometric correction
    fig7 = {}
    for q in (0.0, exp.squint_max_deg, -exp.squint_max_deg):
        im = subimage(base, q, 0, noise=False)
        fig7[q] = (uncorrect(im, az, rg, q), np.abs(im))
    # fig 5: along-track resolution against squint, measured on a point target, against eq 12
    from ..geometry.orbit import max_squint_for, resolution_vs_squint
    from ..metrics import measure
    from ..params.models import PointTarget, Scene
    pt = base.model_copy(update={"scene": Scene(points=(PointTarget(),)),
                                 "receiver": base.receiver.model_copy(update={"noise": nz.model_copy(
                                     update={"enabled": False})})})
    sq_meas = [0.0, 2.5, 5.0, 7.5, 10.0, round(max_squint_for(1.1), 2)]
    meas = []
    for q in sq_meas:
        ptq = subaperture(pt, q, 0)
        m = measure(focus(simulate(ptq), ptq.processing, scenario=ptq))
        meas.append(m["irw_azimuth_m"] / 0.886)
        metrics[f"resolution_azimuth_squint_{q:g}_m"] = meas[-1]
        metrics[f"resolution_azimuth_squint_{q:g}_theory_m"] = float(resolution_vs_squint(
            base.waveform.wavelength, L0, col.n_pulses * base.platform.speed / base.waveform.prf, q))
    metrics["max_squint_within_1p1_deg"] = max_squint_for(1.1)
    from ..geometry.orbit import max_squint_for, resolution_vs_squint
    q = np.linspace(-20, 20, 201)
    sub_len = col.n_pulses * base.platform.speed / base.waveform.prf
    plot.resolution_squint_figure(sq_meas, meas, q, resolution_vs_squint(base.waveform.wavelength, L0, sub_len, q),
                                  max_squint_for(1.1), out / "resolution_squint.png")
    plot.spaceborne_figures(truth, fig7, np.abs(single), np.sqrt(stacked), counts, curve, nz.snr_theory,
                            az, rg, out)
    metrics["run_s"] = time.perf_counter() - t0
    metrics["computed_subimages"] = computed
    write_json_atomic(out / "metrics.json", metrics)
    from ..report import write_spaceborne_report
    write_spaceborne_report(out, scenario, metrics)
    return metrics
