"""Image formation under a memory budget: the output grid in tiles and, for backprojection and FFBP
of spotlight data, the pulses in blocks, each sized to fit.

:func:`plan_tiling` turns the sizes of a job and a budget (bytes) into a :class:`Tiling`: the whole
image at once when the estimate (:func:`memory_estimate`) fits, else tiles
(and pulse blocks) halved until one tile fits; a :class:`~salkit.errors.ResourceError` naming the
memory one tile needs and the budget when even the smallest tile does not. :func:`form_tiles` forms
the tiles one after another from a pulse source (:class:`InMemoryPulses`, or
:class:`DatasetPulses`, which range-compresses each block of a lazily opened dataset as it is
needed) and hands each finished tile to a sink (an array in memory, or a chunked file).

Tiles are independent images of sub-grids, so a tiled image is the untiled one: backprojection
pixel for pixel (pulse blocks accumulate into the same float32 accumulators, kernel call for kernel
call), FFBP to its own accuracy (each tile's polar grids are sized for the tile; pulse blocks are
FFBP images of their pulses, added: FFBP is linear in the data).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable, NamedTuple, Optional

import numpy as np

from ..errors import DataFileError, ResourceError, ScenarioError
from ..io.reading import lazy_reads
from ..io.formats import read_phase_data
from ..resources import in_dask_task, size_text as gib, task_numba_threads
from ..signals.windows import Window
from ..registry import FORMERS
from .formers import ImageGrid, Sizes, former_spec
from .phasehistory import PhaseHistory, phase_history
from .._lazy import load as _deferred

_dask_distributed = _deferred("dask.distributed")  # not lazy_loader: it imports dask itself at once

#: Smallest tile side, pixels.
MIN_TILE = 32
#: Smallest pulse block (a multiple of :data:`KERNEL_BLOCK`).
MIN_BLOCK = 64
#: Pulse blocks are multiples of this many pulses (the image is the same bits whatever the blocks:
#: each pixel sums its pulses in order; backprojection's kernel takes up to
#: :data:`salkit.focus.bp_kernel.PULSE_BLOCK` a call).
KERNEL_BLOCK = 32


class Geometry(NamedTuple):
    """A collection's geometry and the grid it is formed on, for formers whose memory follows them
    (a declared ``footprint``: FFBP).

    Attributes
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    freq : float64 (M,)
        Frequencies, Hz.
    grid : ImageGrid
        The whole output grid.
    accuracy : {"standard", "high"}
    """

    positions: np.ndarray
    freq: np.ndarray
    grid: ImageGrid
    accuracy: str = "standard"

    def part(self, a: int, b: int, i0: int, i1: int, j0: int, j1: int) -> "Geometry":
        """Pulses ``a`` to ``b`` onto the pixels [i0:i1, j0:j1].

        Parameters
        ----------
        a, b, i0, i1, j0, j1 : int

        Returns
        -------
        Geometry
        """
        return self._replace(positions=self.positions[a:b], grid=tile_grid(self.grid, i0, i1, j0, j1))


def memory_estimate(n_pulses: int, n_samples: int, nx: int, ny: int, algorithm: str = "bp",
                    raw: bool = True, cover_pixels: int | None = None, upsample: int | None = None,
                    geometry: Geometry | None = None) -> tuple[float, str]:
    """Peak memory of focusing, bytes, from the sizes.

    What every former holds: the signal (complex64, pulses x samples) once, and from raw data the
    deskew's 2N-point FFT buffers and the phase history (6 more); the image's float32 accumulators
    and complex64 output (24 bytes a pixel). Then what the former declares it adds
    (:attr:`salkit.focus.formers.FormerSpec.memory`: PFA its formed grid and K-space buffer, omega-k
    its Stolt-interpolated spectrum, FFBP its polar grids and range profiles, bp one kernel call's
    upsampled range profiles).

    Parameters
    ----------
    n_pulses, n_samples : int
        Signal shape.
    nx, ny : int
        Output grid, pixels.
    algorithm : str
        A declared former.
    raw : bool
        Dechirped fast-time data (deskewed here) rather than a phase history.
    cover_pixels : int, optional
        PFA's formed grid when larger than nx x ny.
    upsample : int, optional
        Backprojection's range-profile upsampling (its profiles grow with it); default the
        former's own (its declaration's ``upsample`` at "standard").
    geometry : Geometry, optional
        The pulses and the grid themselves (``n_pulses`` of them, ``nx`` x ``ny``): a former that
        declares a ``footprint`` is counted by it, exactly, rather than from the sizes.

    Returns
    -------
    (float, str)
        Bytes, and the sizes that drive it.

    Raises
    ------
    ScenarioError
        For an undeclared former.
    """
    spec = former_spec(algorithm)
    sig = 8.0 * n_pulses * n_samples
    px = float(nx) * ny
    need = sig * (7 if raw else 2) + 24.0 * px
    up = spec.upsample["standard"] if upsample is None else int(upsample)
    if geometry is not None and spec.footprint is not None:
        need += float(spec.footprint(geometry.positions, geometry.freq, geometry.grid, geometry.accuracy))
    else:
        need += float(spec.memory(Sizes(n_pulses, n_samples, nx, ny, int(max(cover_pixels or 0, px)), up)))
    return need, (f"focusing {n_pulses} pulses x {n_samples} samples onto {nx} x {ny} pixels "
                  f"({algorithm})")


@dataclass(frozen=True)
class Tiling:
    """How an image is formed: tiles of the output grid and blocks of pulses.

    Attributes
    ----------
    nx, ny : int
        The whole grid, pixels.
    tile_nx, tile_ny : int
        A tile's size, pixels (the last row and column of tiles may be smaller).
    pulses, pulse_block : int
        Pulses of the collection and per block (``pulse_block == pulses``: not blocked).
    need : float
        Estimated peak memory with one tile in work, bytes.
    budget : float
        The memory budget, bytes.
    algorithm : str
    """

    nx: int
    ny: int
    tile_nx: int
    tile_ny: int
    pulses: int
    pulse_block: int
    need: float
    budget: float
    algorithm: str

    @property
    def tiled(self) -> bool:
        """Whether the job runs in more than one tile or pulse block."""
        return self.n_tiles > 1 or self.pulse_block < self.pulses

    @property
    def tiles(self) -> list[tuple[int, int, int, int]]:
        """(i0, i1, j0, j1) pixel ranges of every tile, azimuth-major."""
        return [(i, min(i + self.tile_nx, self.nx), j, min(j + self.tile_ny, self.ny))
                for i in range(0, self.nx, self.tile_nx) for j in range(0, self.ny, self.tile_ny)]

    @property
    def n_tiles(self) -> int:
        """Number of tiles."""
        return math.ceil(self.nx / self.tile_nx) * math.ceil(self.ny / self.tile_ny)

    @property
    def blocks(self) -> list[tuple[int, int]]:
        """(a, b) pulse ranges of the blocks (a last block shorter than 2 pulses joins the one before)."""
        edges = list(range(0, self.pulses, self.pulse_block)) + [self.pulses]
        if len(edges) > 2 and edges[-1] - edges[-2] < 2:
            del edges[-2]
        return list(zip(edges[:-1], edges[1:]))

    def describe(self) -> str:
        """One line for the log: how the job is cut and why."""
        if not self.tiled:
            return f"whole image at once (about {gib(self.need)}, budget {gib(self.budget)})"
        parts = [f"{self.n_tiles} tiles of up to {self.tile_nx} x {self.tile_ny} pixels"]
        if self.pulse_block < self.pulses:
            parts.append(f"{len(self.blocks)} blocks of up to {self.pulse_block} of the {self.pulses} pulses")
        return (f"{self.algorithm} in " + ", ".join(parts) + f": about {gib(self.need)} with one tile in work, "
                f"within the budget of {gib(self.budget)}")


def plan_tiling(n_pulses: int, n_samples: int, nx: int, ny: int, algorithm: str, budget: float, *,
                raw: bool = True, stripmap: bool = False, hold_image: bool = True, at_once: int = 1,
                min_tiles: int = 1, upsample: int | None = None, geometry: Geometry | None = None) -> Tiling:
    """The largest tiles (and pulse blocks) whose estimated memory fits ``budget``.

    Parameters
    ----------
    n_pulses, n_samples : int
        Signal shape.
    nx, ny : int
        Output grid, pixels.
    algorithm : str
        The former; only those that declare ``tiles`` are cut, and in pulse blocks those that
        declare ``blocks``.
    budget : float
        Bytes.
    raw : bool
        Dechirped fast-time data (range-compressed here) rather than a phase history.
    stripmap : bool
        Stripmap data (backprojection equalises the beam over all pulses: no pulse blocks; FFBP is
        for spotlight data).
    hold_image : bool
        The whole image is assembled in memory (8 bytes a pixel more once tiled); False when the
        tiles go to a file.
    at_once : int
        Tiles in work at the same time on this budget (the workers of a local Dask cluster).
    min_tiles : int
        At least this many tiles (work for every worker), even when fewer would fit.
    upsample : int, optional
        Backprojection's range-profile upsampling (:func:`memory_estimate`; default the former's own).
    geometry : Geometry, optional
        The collection and the whole grid: a former that declares a ``footprint`` (FFBP) is then
        weighed by it, each candidate cut at its largest over the tiles at the grid's corners, its
        edges' midpoints and its centre and the first, middle and last pulse blocks (its polar
        grids and profiles follow the aperture's angle and where the tile lies, not only the sizes).

    Returns
    -------
    Tiling

    Raises
    ------
    ResourceError
        When the job does not fit and cannot be cut (not a tileable former), or when one tile of
        the smallest size does not fit: the message names the memory and the budget.
    """
    spec = former_spec(algorithm)
    known = {}
    exact = geometry is not None and spec.footprint is not None

    def former_need(tx, ty, pb):
        cut = (tx, ty, pb) != (nx, ny, n_pulses)
        m = spec.tile_overlap if cut else 0  # the overlap a tile is formed with, each side
        if not exact:
            return memory_estimate(pb, n_samples, min(nx, tx + 2 * m), min(ny, ty + 2 * m), algorithm, raw=raw,
                                   upsample=upsample)[0]
        plan = Tiling(nx, ny, tx, ty, n_pulses, pb, 0.0, 0.0, algorithm)
        tiles, blocks = plan.tiles, plan.blocks
        corners = {next(k for k, (i0, i1, j0, j1) in enumerate(tiles) if i0 <= i < i1 and j0 <= j < j1)
                   for i in (0, nx // 2, nx - 1) for j in (0, ny // 2, ny - 1)}
        worst = 0.0
        for k in sorted(corners):
            i0, i1, j0, j1 = tiles[k]
            box = (max(0, i0 - m), min(nx, i1 + m), max(0, j0 - m), min(ny, j1 + m))
            for a, b in {blocks[0], blocks[len(blocks) // 2], blocks[-1]}:
                worst = max(worst, memory_estimate(b - a, n_samples, box[1] - box[0], box[3] - box[2], algorithm,
                                                   raw=raw, upsample=upsample, geometry=geometry.part(a, b, *box))[0])
        return worst

    def need(tx, ty, pb):
        if (tx, ty, pb) not in known:
            cut = (tx, ty, pb) != (nx, ny, n_pulses)
            known[tx, ty, pb] = (former_need(tx, ty, pb) * max(at_once, 1)
                                 + (8.0 * nx * ny if (cut and hold_image) else 0.0))
        return known[tx, ty, pb]

    def count(tx, ty):
        return math.ceil(nx / tx) * math.ceil(ny / ty)

    tx, ty, pb = nx, ny, n_pulses
    if min_tiles > 1 and spec.tiles:  # work for every worker: halve the larger side
        while count(tx, ty) < min_tiles and max(tx, ty) > MIN_TILE:
            tx, ty = (max(MIN_TILE, math.ceil(tx / 2)), ty) if tx >= ty else (tx, max(MIN_TILE, math.ceil(ty / 2)))
    est = need(tx, ty, pb)
    what = memory_estimate(n_pulses, n_samples, nx, ny, algorithm, raw=raw)[1]
    if est <= budget:
        return Tiling(nx, ny, tx, ty, n_pulses, pb, est, budget, algorithm)
    if not spec.tiles:
        tileable = " or ".join(n for n, s in FORMERS.items() if s.tiles)
        raise ResourceError(f"{what} needs about {gib(est)} of memory, more than the {gib(budget)} available "
                            f"(the budget); {algorithm} cannot run in tiles: use --algorithm {tileable}, a smaller "
                            "grid or fewer pulses")
    blockable = spec.pulse_blocks(stripmap)
    while est > budget:
        options = []
        if max(tx, ty) > MIN_TILE:
            if tx >= ty:
                options.append((max(MIN_TILE, math.ceil(tx / 2)), ty, pb))
            else:
                options.append((tx, max(MIN_TILE, math.ceil(ty / 2)), pb))
        if blockable and pb > MIN_BLOCK:
            options.append((tx, ty, max(MIN_BLOCK, KERNEL_BLOCK * math.ceil(pb / 2 / KERNEL_BLOCK))))
        if not options:
            image = 8.0 * nx * ny if hold_image else 0.0
            raise ResourceError(
                f"{what}: one tile of {tx} x {ty} pixels" + (f" with blocks of {pb} pulses" if pb < n_pulses else "")
                + f" needs about {gib(est)} of memory"
                + (f" ({gib(image)} of it the whole image, assembled in memory; `salkit focus` and "
                   "focus_to_file write an image tile by tile into its file instead)" if image else "")
                + f", more than the {gib(budget)} available (the budget); raise --memory-limit"
                + (", or use fewer pulses or samples" if not blockable else ", or use fewer samples"))
        tx, ty, pb = min(options, key=lambda o: need(*o))
        est = need(tx, ty, pb)
    return Tiling(nx, ny, tx, ty, n_pulses, pb, est, budget, algorithm)


#: The last whole phase history a :class:`DatasetPulses` read on this Dask worker (one entry).
_WHOLE: dict = {}


class InMemoryPulses:
    """Pulse blocks of a phase history held in memory.

    Parameters
    ----------
    ph : PhaseHistory
    """

    def __init__(self, ph: PhaseHistory):
        self.ph = ph

    @property
    def n_pulses(self) -> int:
        """Pulses."""
        return self.ph.data.shape[0]

    def block(self, a: int, b: int) -> PhaseHistory:
        """Pulses ``a`` to ``b`` (the collection's track and centre kept)."""
        return dataclasses.replace(self.ph, data=self.ph.data[a:b], positions=self.ph.positions[a:b],
                                   reference_range=self.ph.reference_range[a:b])

    def whole(self) -> PhaseHistory:
        """The whole phase history."""
        return self.ph

    @property
    def probe(self) -> PhaseHistory:
        """The phase history itself, which tells the collection's kind of data (its mode and telescope)."""
        return self.ph


class DatasetPulses:
    """Pulse blocks of a raw or phase-history dataset, range-compressed block by block as they are
    read: the dataset may be opened lazily from a file (NetCDF through xarray), and only one block's
    signal is in memory at a time.

    Parameters
    ----------
    raw : xarray.Dataset
    chirp_correction : str
    phase_noise_correction : str
    """

    def __init__(self, raw, chirp_correction: str = "none", phase_noise_correction: str = "none"):
        self.raw, self.chirp, self.noise_fix = raw, chirp_correction, phase_noise_correction
        self.source = raw.encoding.get("source")  # the file, when opened from one: workers reopen it
        P = raw.sizes["slow_time"]
        with lazy_reads("signal", self.source):
            probe = phase_history(raw.isel(slow_time=[0, P // 2, P - 1]), chirp_correction, phase_noise_correction)  # first, centre, last
        self.track, self.center_position = probe.track, probe.center_position
        self.probe = probe

    @property
    def n_pulses(self) -> int:
        """Pulses."""
        return self.raw.sizes["slow_time"]

    def block(self, a: int, b: int) -> PhaseHistory:
        """Pulses ``a`` to ``b``, read and range-compressed now."""
        with lazy_reads("signal", self.source):
            ph = phase_history(self.raw.isel(slow_time=slice(a, b)), self.chirp, self.noise_fix)
        if not np.isfinite(ph.data).all():
            where = f"{self.source}: " if self.source else ""
            raise DataFileError(f"{where}variable 'signal': non-finite values in pulses {a} to {b - 1}")
        return dataclasses.replace(ph, track=self.track, center_position=self.center_position)

    def whole(self) -> PhaseHistory:
        """Every pulse at once (on a Dask worker, kept for its next tile: the tiles of FFBP a worker
        forms read the file once; elsewhere nothing is kept beyond the caller's use)."""
        key = (self.source, self.chirp, self.noise_fix) if self.source and in_dask_task() else None
        if key is not None and _WHOLE.get("key") == key:
            return _WHOLE["ph"]
        with lazy_reads("signal", self.source):
            ph = phase_history(self.raw, self.chirp, self.noise_fix)
        if key is not None:
            _WHOLE.clear()
            _WHOLE.update(key=key, ph=ph)
        return ph

    def __getstate__(self):
        if not self.source:
            raise TypeError("DatasetPulses of a dataset not opened from a file cannot go to other processes")
        return {"source": self.source, "chirp": self.chirp, "noise_fix": self.noise_fix}

    def __setstate__(self, state):
        from_file = read_phase_data(state["source"], lazy=True)  # a worker opens the file itself
        self.__init__(from_file, state["chirp"], state["noise_fix"])

    def geometry(self, block: int = 4096) -> PhaseHistory:
        """The collection without its signal (``data`` of zero samples): every pulse's position and
        reference range, read block by block."""
        pos, ref = [], []
        for a in range(0, self.n_pulses, block):
            b = min(self.n_pulses, a + block)
            sub = self.raw.isel(slow_time=slice(a, b))
            pos.append(np.asarray(sub["position"].values, np.float64))
            ref.append(np.asarray(sub["reference_range"].values, np.float64))
        return dataclasses.replace(self.probe, data=np.zeros((self.n_pulses, 0), np.complex64),
                                   positions=np.concatenate(pos), reference_range=np.concatenate(ref))


def tile_grid(ig: ImageGrid, i0: int, i1: int, j0: int, j1: int) -> ImageGrid:
    """The sub-grid of pixels [i0:i1, j0:j1] of ``ig``: the same plane and the same coordinates.

    Parameters
    ----------
    ig : ImageGrid
    i0, i1, j0, j1 : int

    Returns
    -------
    ImageGrid
    """
    az, rg = ig.azimuth[i0:i1], ig.range[j0:j1]
    spec = ig.spec.model_copy(update={"nx": az.size, "ny": rg.size})
    return ImageGrid(ig.plane, az, rg, spec)


def form_tile(pulses, tig: ImageGrid, window: Window, tiling: Tiling, upsample: int, accuracy: str):
    """One tile's image: formed a pulse block at a time by the former's declared ``blocks`` when
    the pulses are cut (spotlight data), else by the former on the whole phase history.

    Parameters
    ----------
    pulses : InMemoryPulses or DatasetPulses
    tig : ImageGrid
        The tile (:func:`tile_grid`).
    window : Window
    tiling : Tiling
    upsample : int
    accuracy : str

    Returns
    -------
    (complex64 ndarray, dict)
        The tile and the former's info.
    """
    spec = former_spec(tiling.algorithm)
    probe = pulses.probe
    if tiling.pulse_block < tiling.pulses and spec.pulse_blocks(probe.beam_limited):
        return spec.blocks(pulses, tig, window, tiling.blocks, upsample, accuracy)
    res = spec.form(pulses.whole(), tig, window, upsample=upsample, accuracy=accuracy)
    return res.image, res.info


def tile_image(pulses, ig: ImageGrid, window: Window, tiling: Tiling, box, upsample: int, accuracy: str):
    """The pixels ``box`` = (i0, i1, j0, j1) of the image: formed on that sub-grid grown by the
    former's declared ``tile_overlap`` pixels each side (inside the grid; FFBP's 16) and cropped, so
    that the error a former makes near the edge of what it forms stays out of the tile (no seam).

    Parameters
    ----------
    pulses : InMemoryPulses or DatasetPulses
    ig : ImageGrid
        The whole grid.
    window : Window
    tiling : Tiling
    box : (int, int, int, int)
    upsample : int
    accuracy : str

    Returns
    -------
    (complex64 ndarray, dict)
    """
    i0, i1, j0, j1 = box
    m = former_spec(tiling.algorithm).tile_overlap if tiling.tiled else 0
    e0, e1, f0, f1 = max(0, i0 - m), min(ig.shape[0], i1 + m), max(0, j0 - m), min(ig.shape[1], j1 + m)
    img, info = form_tile(pulses, tile_grid(ig, e0, e1, f0, f1), window, tiling, upsample, accuracy)
    return img[i0 - e0:i1 - e0, j0 - f0:j1 - f0], info


def _tile_task(pulses, ig: ImageGrid, window: Window, tiling: Tiling, k: int, upsample: int, accuracy: str):
    """Dask task: tile ``k`` of the plan (top level, so workers import it); the worker reads its own
    pulses (a file's blocks) or holds the scattered phase history."""
    task_numba_threads()
    i0, i1, j0, j1 = tiling.tiles[k]
    img, info = tile_image(pulses, ig, window, tiling, (i0, i1, j0, j1), upsample, accuracy)
    return k, img, info


def form_tiles(pulses, ig: ImageGrid, window: Window, tiling: Tiling, *, upsample: int, accuracy: str,
               sink: Callable[[int, int, np.ndarray], None],
               progress: Optional[Callable[[int, int], None]] = None, client=None) -> dict:
    """Form the image tile by tile and hand each tile to ``sink(i0, j0, tile)``.

    Parameters
    ----------
    pulses : InMemoryPulses or DatasetPulses
    ig : ImageGrid
        The whole grid.
    window : Window
    tiling : Tiling
    upsample : int
    accuracy : str
    sink : callable
        Receives each finished tile (complex64) at its pixel offsets (in this process).
    progress : callable, optional
        ``progress(done, total)`` in tiles.
    client : dask.distributed.Client, optional
        Form the tiles as Dask tasks, one a tile: a file's pulses are read by each worker itself
        (:class:`DatasetPulses` reopens the file), a phase history in memory is scattered to the
        workers once. The tiles are the same as in this process; a worker lost mid-tile has its
        tile recomputed by Dask.

    Returns
    -------
    dict
        The former's info of a tile (support figures) and ``tiles``, ``tile_nx``, ``tile_ny``,
        ``pulse_block``.
    """
    blocked = tiling.pulse_block < tiling.pulses
    probe = pulses.probe
    spotlight = not probe.beam_limited
    if blocked and not former_spec(tiling.algorithm).pulse_blocks(not spotlight):
        blockers = ", ".join(n for n, s in FORMERS.items() if s.blocks is not None)
        raise ScenarioError("processing.algorithm", tiling.algorithm, f"only {blockers} form the pulses of spotlight "
                            "data in blocks")
    remote_file = client is not None and isinstance(pulses, DatasetPulses) and pulses.source
    if not blocked and not remote_file:
        pulses = InMemoryPulses(pulses.whole())  # read once, for every tile
    info, tiles = {}, tiling.tiles
    if client is None:
        for k, (i0, i1, j0, j1) in enumerate(tiles):
            img, info = tile_image(pulses, ig, window, tiling, (i0, i1, j0, j1), upsample, accuracy)
            sink(i0, j0, img)
            if progress is not None:
                progress(k + 1, len(tiles))
    else:
        src = pulses if remote_file else client.scatter(pulses, broadcast=True, hash=False)  # a key of its own
        futures = [client.submit(_tile_task, src, ig, window, tiling, k, upsample, accuracy, pure=False)
                   for k in range(len(tiles))]
        try:
            for n, fut in enumerate(_dask_distributed.as_completed(futures)):
                k, img, info = fut.result()
                fut.release()
                sink(tiles[k][0], tiles[k][2], img)
                if progress is not None:
                    progress(n + 1, len(tiles))
        finally:
            client.cancel(futures)
    info = {k: v for k, v in info.items() if v is not None}
    info.update({"tiles": len(tiles), "tile_nx": tiling.tile_nx, "tile_ny": tiling.tile_ny,
                 "pulse_block": tiling.pulse_block})
    return info
