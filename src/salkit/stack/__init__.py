"""Sub-images and their stacks (seed 001): one sub-aperture's image on the common target grid,
incoherent stacks on Dask (checkpointed in Zarr, resumable), coherent stacks with phase alignment.

Sub-aperture p of the collection is centred at along-track offset u_p = L0 tan(theta_p) on the
straight-line model, has length L_sa and forms one sub-image by backprojection onto the common
target-frame grid: exact for any squint, so the sub-image is already geometrically corrected.
Each sub-aperture has its own photon noise; the scene's scatterers are the same physical target,
so its speckle decorrelates between sub-apertures through the change of aspect alone.
"""
from __future__ import annotations

import math

import numpy as np

from ..focus import ImageGrid, focus, get_former, phase_history, run_memory_estimate
from ..signals.windows import Window
from ..metrics.pointtarget import ipr_1d
from ..params.models import PointTarget, RelativeOrbit, Scenario, Scene
from ..simulate import photon_noise, simulate
from ..geometry.orbit import relative_speed, subaperture_length
from ..params.scenario import parse_scenario
from ..errors import SalkitError
from ..params.scenario import dump_scenario
from ..errors import EnvironmentProblem
import lazy_loader as _lazy
_dask_distributed = _lazy.load("dask.distributed", suppress_warning=True)
_scipy_ndimage = _lazy.load("scipy.ndimage", suppress_warning=True)
zarr = _lazy.load("zarr", suppress_warning=True)


def squint_of(index: int, count: int, squint_max_deg: float) -> float:
    """Squint (deg) of sub-aperture ``index`` of ``count`` spread evenly over +-squint_max.

    Parameters
    ----------
    index, count : int
    squint_max_deg : float
        deg.

    Returns
    -------
    float
        deg.

    Examples
    --------
    >>> [squint_of(i, 4, 5.0) for i in range(4)]
    [-3.75, -1.25, 1.25, 3.75]
    """
    if count == 1:
        return 0.0
    return -squint_max_deg + 2 * squint_max_deg * (index + 0.5) / count


def geo_base(scenario: Scenario) -> Scenario:
    """The sub-aperture scenario implied by the experiment: straight-line pass at V and L0, one
    sub-aperture L_sa long, spotlight on the target, no experiment block.

    Parameters
    ----------
    scenario : Scenario
        With ``experiment.kind = spaceborne_geo``.

    Returns
    -------
    Scenario
    """
    exp = scenario.experiment
    L0 = exp.r2 - exp.r1
    V = relative_speed(exp.r1, exp.r2)
    L = subaperture_length(scenario.waveform.wavelength, L0, exp.resolution)
    orbit = (RelativeOrbit(r1=exp.r1, r2=exp.r2, attitude=exp.target_attitude)
             if scenario.platform.trajectory == "keplerian" else None)
    p = scenario.platform.model_copy(update={"mode": "spotlight", "speed": V, "standoff": L0, "altitude": 0.0,
                                             "aperture_length": L, "squint_deg": 0.0, "positions": None,
                                             "orbit": orbit})
    return scenario.model_copy(update={"platform": p, "experiment": None})


def nearest_squints(count: int, sub_length: float, closest: float) -> list[float]:
    """Squints (deg) of the ``count`` consecutive sub-apertures nearest closest approach.

    Parameters
    ----------
    count : int
    sub_length : float
        m.
    closest : float
        L0, m.

    Returns
    -------
    list of float
        deg.
    """
    k = np.arange(count) - (count - 1) / 2
    return [float(v) for v in np.degrees(np.arctan(k * sub_length / closest))]


def uncorrect(img: np.ndarray, az: np.ndarray, rg: np.ndarray, squint_deg: float) -> np.ndarray:
    """|image| resampled into the squinted frame of eq 11 (X = -x0 - z0 tan th, Y = z0 cos th +
    x0 sin th): the sub-image as a squinted processor delivers it, before geometric correction.

    Parameters
    ----------
    img : complex (nx, ny)
    az, rg : float64
        m.
    squint_deg : float
        deg.

    Returns
    -------
    float ndarray
    """
    th = math.radians(squint_deg)
    X, Y = np.meshgrid(-az, rg, indexing="ij")
    # invert eq 11 for (x0, z0)
    A = np.array([[-1.0, -math.tan(th)], [math.sin(th), math.cos(th)]])
    inv = np.linalg.inv(A)
    x0 = inv[0, 0] * X + inv[0, 1] * Y
    z0 = inv[1, 0] * X + inv[1, 1] * Y
    ia = (x0 - az[0]) / (az[1] - az[0])
    ir = (z0 - rg[0]) / (rg[1] - rg[0])
    return _scipy_ndimage.map_coordinates(np.abs(img), [ia, ir], order=1, cval=0.0)


def subaperture(base: Scenario, squint_deg: float, noise_seed: int) -> Scenario:
    """The scenario of one sub-aperture: same target and grid, its squint, its own noise seed.

    Parameters
    ----------
    base : Scenario
    squint_deg : float
        deg.
    noise_seed : int

    Returns
    -------
    Scenario
    """
    p = base.platform.model_copy(update={"squint_deg": squint_deg})
    return base.model_copy(update={"platform": p, "seed": noise_seed})


def subimage(base: Scenario, squint_deg: float, noise_seed: int, noise: bool = True) -> np.ndarray:
    """Complex sub-image on the common target grid. The scene (speckle) uses ``base.seed``; the
    photon noise uses ``noise_seed``.

    Parameters
    ----------
    base : Scenario
    squint_deg : float
        deg.
    noise_seed : int
    noise : bool

    Returns
    -------
    complex64 (nx, ny)
    """
    sc = subaperture(base, squint_deg, base.seed)
    rng = np.random.default_rng(base.seed)  # the scene (speckle) draws first: the same target every time
    raw = simulate(sc, noise=False, rng=rng)
    if noise and base.receiver.noise.enabled:
        sig = raw["signal"].values.copy()
        photon_noise(sig, base.receiver.noise, np.random.default_rng(10_000_019 + noise_seed))
        raw["signal"].values[...] = sig
    # the former alone: a sub-image needs no dataset, no truth positions, no collection record
    p = sc.processing
    ph = phase_history(raw, p.chirp_correction)
    res = get_former(p.algorithm)(ph, ImageGrid.of(ph, p.grid), Window(p.window, p.taylor_nbar, p.taylor_sll),
                                  upsample=p.range_upsample)
    return res.image


def incoherent_stack(base: Scenario, count: int, squint_max_deg: float, noise: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Incoherent stack (mean intensity) of ``count`` sub-images, and the first sub-image.

    Parameters
    ----------
    base : Scenario
    count : int
    squint_max_deg : float
        deg.
    noise : bool

    Returns
    -------
    (float ndarray, complex ndarray)
    """
    acc = None
    first = None
    for i in range(count):
        img = subimage(base, squint_of(i, count, squint_max_deg), i, noise)
        first = img if first is None else first
        acc = np.abs(img) ** 2 if acc is None else acc + np.abs(img) ** 2
    return acc / count, first


def coherent_stack(images, align: bool = True):
    """Coherent sum of complex sub-images on the common grid, with phase alignment.

    Backprojection keeps absolute phase, so sub-images of one phase-coherent collection add in
    phase and their sum is the image of the combined (longer) aperture: finer along-track
    resolution, not lower speckle. Real collections drift in phase between sub-apertures (laser
    phase, residual motion), so each sub-image's constant offset is estimated against the running
    sum, arg sum(img conj(acc)), and removed before it is added.

    Parameters
    ----------
    images : iterable of complex ndarray
    align : bool
        Remove each sub-image's constant phase offset.

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


def _subimage_chunk_task(base_dict: dict, indices: list, squints: list, noise: bool, complex_: bool = False):
    """Dask task: a chunk of sub-images (top level, so workers can import it), as intensities, or
    complex64 when ``complex_`` (coherent stacking).

    Chunks amortise the per-task costs (scheduling, parsing the scenario) that otherwise take twice
    the compute of a sub-image."""
    base = parse_scenario(base_dict)
    imgs = np.stack([subimage(base, q, i, noise) for i, q in zip(indices, squints)])
    return list(indices), (imgs.astype(np.complex64) if complex_ else (np.abs(imgs) ** 2).astype(np.float32))


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
    one, _ = run_memory_estimate(base)
    g = base.processing.grid
    stack_bytes = 4.0 * count * g.nx * g.ny
    return (workers + 1) * one + 2 * stack_bytes, (f"stacking {count} sub-images of {g.nx} x {g.ny} pixels on "
                                                   f"{workers} worker(s)")


def run_stack(base: Scenario, squints, store, scheduler: str | None = None,
              workers: int = 2, noise: bool = True, progress=None, stop_after: int | None = None,
              chunk: int | None = None, keep_complex: bool = False):
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
    keep_complex : bool
        Also store each complex sub-image (``image``, complex64) for a coherent stack
        (:func:`coherent_stack`); twice the intensity store's size.

    Returns
    -------
    (stack, computed)
        The mean intensity over all stored sub-images and how many this call computed.
    """


    cluster = None
    try:  # connect first: an unreachable scheduler writes nothing
        if scheduler:
            client = _dask_distributed.Client(scheduler, timeout="5s")
        else:
            # one compute thread per worker process: numba's own pool would otherwise put
            # workers x cores threads on the cores
            cluster = _dask_distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                                     dashboard_address=None,
                                                     env={"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"})
            client = _dask_distributed.Client(cluster)
    except (OSError, TimeoutError) as err:
        raise EnvironmentProblem(f"--scheduler {scheduler}: no Dask scheduler answers there "
                                 f"({type(err).__name__})") from None
    try:
        squints = [float(q) for q in squints]
        count = len(squints)
        g = base.processing.grid
        root = zarr.open_group(str(store), mode="a")
        text = dump_scenario(base)
        if "intensity" in root:
            if (root.attrs.get("scenario") != text or root.attrs.get("squints") != squints
                    or bool(root.attrs.get("complex", False)) != keep_complex):
                raise SalkitError(f"{store}: the checkpoint belongs to another run (scenario or count differs)")
        else:
            root.create_array("intensity", shape=(count, g.nx, g.ny), chunks=(1, g.nx, g.ny), dtype="float32")
            root.create_array("done", shape=(count,), chunks=(count,), dtype="bool", fill_value=False)
            if keep_complex:
                root.create_array("image", shape=(count, g.nx, g.ny), chunks=(1, g.nx, g.ny), dtype="complex64")
            root.attrs.update({"scenario": text, "count": count, "squints": squints, "complex": keep_complex})
        done = np.asarray(root["done"][:])
        todo = [i for i in range(count) if not done[i]]
        computed = 0
        bd = base.model_dump(mode="json")
        size = int(chunk or max(1, min(64, len(todo) // (4 * max(workers, 1)))))
        chunks = [todo[a:a + size] for a in range(0, len(todo), size)]
        futures = [client.submit(_subimage_chunk_task, bd, ch, [squints[i] for i in ch], noise, keep_complex,
                                 pure=False) for ch in chunks]
        for fut in _dask_distributed.as_completed(futures):
            idx, imgs = fut.result()
            for i, im in zip(idx, imgs):
                if keep_complex:
                    root["image"][i] = im
                root["intensity"][i] = (np.abs(im) ** 2).astype(np.float32) if keep_complex else im
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


def point_target(base: Scenario, grid=None) -> Scenario:
    """``base`` with one point scatterer at the scene centre, photon noise off, and optionally
    another image grid: the scenario the resolution studies measure.

    Parameters
    ----------
    base : Scenario
    grid : Grid, optional

    Returns
    -------
    Scenario
    """
    nz = base.receiver.noise
    update = {"scene": Scene(points=(PointTarget(),)),
              "receiver": base.receiver.model_copy(update={"noise": nz.model_copy(update={"enabled": False})})}
    if grid is not None:
        update["processing"] = base.processing.model_copy(update={"grid": grid})
    return base.model_copy(update=update)


def coherent_resolution(base: Scenario, counts, oversample: float = 4.0) -> dict:
    """Along-track resolution of coherent stacks of ``P`` consecutive sub-apertures nearest closest
    approach, measured on a noise-free point target, against the combined aperture's theory.

    ``P`` contiguous sub-apertures of length L_sa form one aperture P L_sa long, so the 3 dB width
    is 0.886 lambda L0 / (2 P L_sa) with uniform weighting: P times finer than one sub-image.
    Each stack is formed on a grid fine enough for its largest P (``oversample`` samples per
    resolution cell) around the point.

    Parameters
    ----------
    base : Scenario
        One sub-aperture's scenario (:func:`geo_base`).
    counts : sequence of int
        Sub-apertures per stack.
    oversample : float
        Pixels per resolution cell of the finest stack.

    Returns
    -------
    dict
        ``counts``, ``irw_m`` (measured), ``irw_theory_m`` (lists, m).
    """
    L0 = base.platform.standoff
    L = base.platform.aperture_length
    lam = base.waveform.wavelength
    fine = lam * L0 / (2 * max(counts) * L) / oversample
    span = 24 * max(counts) / min(counts)  # finest cells across: 24 of the coarsest stack's
    g = base.processing.grid.model_copy(update={"nx": int(span * oversample) + 1, "ny": 9, "dx": fine,
                                                "dy": base.processing.grid.dy})
    pt = point_target(base, g)
    out = {"counts": [int(c) for c in counts], "irw_m": [], "irw_theory_m": []}
    for P in counts:
        qs = nearest_squints(int(P), L, L0)
        acc, _ = coherent_stack(subimage(pt, q, i, noise=False) for i, q in enumerate(qs))
        cut = acc[:, acc.shape[1] // 2]
        out["irw_m"].append(float(ipr_1d(cut, fine, lam * L0 / (2 * P * L))["irw"]))
        out["irw_theory_m"].append(0.886 * lam * L0 / (2 * P * L))
    return out


#: The name the seed-001 tests know it by.
stack = incoherent_stack
