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
    rng = np.random.default_rng(base.seed)
    from ..simulate.scene import build_scatterers  # noqa: F401  (same scene: same seed first)
    raw = simulate(sc, noise=False, rng=rng)
    if noise and base.receiver.noise.enabled:
        from ..simulate import photon_noise
        sig = raw["signal"].values.copy()
        photon_noise(sig, base.receiver.noise, np.random.default_rng(10_000_019 + noise_seed))
        raw["signal"].values[...] = sig
    return focus(raw, sc.processing)["image"].values


def stack(base: Scenario, count: int, squint_max_deg: float, noise: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Incoherent stack (mean intensity) of ``count`` sub-images, and the first sub-image."""
    acc = None
    first = None
    for i in range(count):
        img = subimage(base, squint_of(i, count, squint_max_deg), i, noise)
        first = img if first is None else first
        acc = np.abs(img) ** 2 if acc is None else acc + np.abs(img) ** 2
    return acc / count, first


def stack_snr(stacked_intensity: np.ndarray, clean_intensity: np.ndarray, mask: np.ndarray) -> float:
    """SNR of a (stacked) intensity image against the truth: mean signal intensity / std."""
    return float(clean_intensity[mask].mean() / stacked_intensity[mask].std())


del math


def _subimage_task(base_dict: dict, index: int, count: int, squint_max_deg: float, noise: bool):
    """Dask task: the intensity of sub-image ``index`` (top level, so workers can import it)."""
    from ..params.scenario import parse_scenario
    base = parse_scenario(base_dict)
    img = subimage(base, squint_of(index, count, squint_max_deg), index, noise)
    return index, (np.abs(img) ** 2).astype(np.float32)


def run_stack(base: Scenario, count: int, squint_max_deg: float, store, scheduler: str | None = None,
              workers: int = 2, noise: bool = True, progress=None, stop_after: int | None = None):
    """Stack ``count`` sub-images as Dask tasks, checkpointed in a Zarr store.

    Parameters
    ----------
    base : Scenario
    count : int
        Sub-apertures over +-``squint_max_deg``.
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
        raise SalkitError(f"--scheduler {scheduler}: no Dask scheduler answers there ({type(err).__name__}); "
                          "nothing was written") from None
    try:
        g = base.processing.grid
        root = zarr.open_group(str(store), mode="a")
        text = dump_scenario(base)
        if "intensity" in root:
            if root.attrs.get("scenario") != text or root.attrs.get("count") != count:
                raise SalkitError(f"{store}: the checkpoint belongs to another run (scenario or count differs)")
        else:
            root.create_array("intensity", shape=(count, g.nx, g.ny), chunks=(1, g.nx, g.ny), dtype="float32")
            root.create_array("done", shape=(count,), chunks=(count,), dtype="bool", fill_value=False)
            root.attrs.update({"scenario": text, "count": count, "squint_max_deg": squint_max_deg})
        done = np.asarray(root["done"][:])
        todo = [i for i in range(count) if not done[i]]
        computed = 0
        bd = base.model_dump(mode="json")
        futures = client.map(_subimage_task, [bd] * len(todo), todo, [count] * len(todo),
                             [squint_max_deg] * len(todo), [noise] * len(todo), pure=False)
        for fut in as_completed(futures):
            i, inten = fut.result()
            root["intensity"][i] = inten
            done[i] = True
            root["done"][:] = done
            computed += 1
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
