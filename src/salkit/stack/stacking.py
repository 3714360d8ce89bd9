"""Stacks of sub-images: incoherent (mean intensity; on Dask, checkpointed in Zarr, resumable) and
coherent (phase-aligned), and the memory a stack needs."""
from __future__ import annotations

from contextlib import nullcontext

import lazy_loader as _lazy
import numpy as np

from ..errors import SalkitError
from ..focus import run_memory_estimate
from ..metrics.pointtarget import ipr_1d
from ..params.models import Scenario
from ..params.scenario import dump_scenario, parse_scenario
from ..resources import dask_client, task_numba_threads
from .subapertures import nearest_squints, point_target, squint_of, subimage
from .._lazy import load as _deferred

_dask_distributed = _deferred("dask.distributed")  # not lazy_loader: it imports dask itself at once
zarr = _lazy.load("zarr", suppress_warning=True)


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
    task_numba_threads()
    return _subimage_chunk(parse_scenario(base_dict), indices, squints, noise, complex_)


def _subimage_chunk(base: Scenario, indices: list, squints: list, noise: bool, complex_: bool = False):
    """A chunk of sub-images, in this process: (indices, intensities or complex64 images)."""
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
    """Stack ``count`` sub-images as Dask tasks (or, with ``workers=0``, in this process),
    checkpointed in a Zarr store.

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
    workers : int
        Worker processes of the local cluster; 0: the sub-images in this process, no cluster.
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
    here = workers == 0 and scheduler is None
    if workers < 0 or (workers == 0 and not here):
        raise ValueError(f"workers = {workers}: a cluster's worker count is at least 1, or 0 (in this process) "
                         "without a scheduler")
    with (nullcontext() if here else dask_client(scheduler, workers)) as client:  # an unreachable scheduler writes nothing
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
        if here:  # one sub-image a step: the progress bar moves, and numba's threads are this process's
            futures = []
            results = (_subimage_chunk(base, [i], [squints[i]], noise, keep_complex) for i in todo)
        else:
            bd = base.model_dump(mode="json")
            size = int(chunk or max(1, min(64, len(todo) // (4 * workers))))
            chunks = [todo[a:a + size] for a in range(0, len(todo), size)]
            futures = [client.submit(_subimage_chunk_task, bd, ch, [squints[i] for i in ch], noise, keep_complex,
                                     pure=False) for ch in chunks]
            results = (fut.result() for fut in _dask_distributed.as_completed(futures))
        for idx, imgs in results:
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
