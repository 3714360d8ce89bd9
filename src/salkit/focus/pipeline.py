"""Focusing a dataset: ``focus(raw, processing) -> image``, its memory estimate, and the image
dataset's coordinates and collection geometry.

``focus`` dispatches on the kind of the data (:data:`PROCESSORS`: SAL raw data and phase
histories, down-looking SAL raw data); SAL images are formed by the declared formers
(:data:`salkit.registry.FORMERS`), which share one signature and one normalisation
(:mod:`salkit.focus.formers`). The built-in formers declare themselves in their modules, which
this module imports, every one of the package (the registry's provider).
"""
from __future__ import annotations

import importlib
import logging
import pkgutil
import sys
import warnings
from typing import Callable, Mapping, Optional

import numpy as np
import xarray as xr
from pydantic import ValidationError

from ..choices import ACCURACY, PLANES, check_choice
from ..errors import NOT_GIVEN, DataFileError, ResourceError, ScenarioError, shown
from ..geometry.collection import build_collection, grid_axes, plane_from, truth_positions
from ..geometry.geodesy import image_geolocation
from ..io.datasets import make_image_dataset
from ..io.reading import lazy_reads, open_dataset, require_dataset
from ..io.writing import ImageFileWriter
from ..metrics.pointtarget import support_ipr, window_ipr
from ..params.models import Grid, Processing, Scenario
from ..params.scenario import require_scenario, stored_scenario
from ..registry import FORMERS
from ..resources import available_memory, parse_size, size_text, user_limit
from ..signals.windows import Window
from ..tolerances import GRID_SPACING_OF_RESOLUTION
from ..simulate.echoes import fast_time_axis, memory_estimate as simulate_memory_estimate, signal_shape
from .downlooking import focus_downlooking_raw
from .formers import DEFAULT_UPSAMPLE, ImageGrid, ImageResult, former_spec, get_former, upsample_bounds
from .phasehistory import PhaseHistory, default_grid, phase_history, theory_resolution
from .tiles import DatasetPulses, Geometry, InMemoryPulses, form_tiles, memory_estimate, plan_tiling

_log = logging.getLogger("salkit.focus")

#: Every module of this package, imported here: the built-in formers declare themselves in their own
#: modules, so a new one is found without a list to edit (the registry's provider is this module).
BUILT_IN_MODULES = tuple(sorted(m.name for m in pkgutil.iter_modules(sys.modules[__package__].__path__)
                                if m.name != __name__.rsplit(".", 1)[-1]))
for _name in BUILT_IN_MODULES:
    importlib.import_module(f"{__package__}.{_name}")


def range_upsample(processing: Optional[Processing], accuracy: str | None = None,
                   override: int | None = None, algorithm: str | None = None) -> int:
    """Backprojection's range-profile upsampling for these settings: ``override`` if given, else
    the processing's ``range_upsample``, else the former's own default (its declaration's
    ``upsample``: ``bp`` 6, ``bp_cubic`` and ``bp_fitted`` 16), and at ``accuracy: high`` at least
    the former's high one (``bp`` 8, the others :data:`salkit.tolerances.HIGH_ACCURACY_UPSAMPLE`).

    Parameters
    ----------
    processing : Processing or None
    accuracy : {"standard", "high"}, optional
        Overrides the processing's.
    override : int, optional
        Overrides the processing's upsampling (``focus(..., upsample=)``, ``--range-upsample``).
    algorithm : str, optional
        The former; overrides the processing's (default ``bp``). A name that is no image former
        (a processor such as ``downlooking``) takes :data:`salkit.tolerances.BP_UPSAMPLE`.

    Returns
    -------
    int

    Examples
    --------
    >>> range_upsample(None), range_upsample(None, "high"), range_upsample(None, None, 12)
    (6, 8, 12)
    >>> range_upsample(None, algorithm="bp_cubic"), range_upsample(None, "high", algorithm="bp_cubic")
    (16, 32)
    """
    alg = algorithm or (processing.algorithm if processing is not None else "bp")
    own = FORMERS[alg].upsample if alg in FORMERS else DEFAULT_UPSAMPLE
    given = processing.range_upsample if processing is not None else None
    up = override if override is not None else (given if given is not None else own["standard"])
    acc = accuracy or (processing.accuracy if processing is not None else "standard")
    return up if acc == "standard" else max(up, own["high"])


def check_upsample(upsample, name: str = "upsample") -> int | None:
    """``upsample`` as an int within what ``processing.range_upsample`` allows (2 to 64), or None.

    Parameters
    ----------
    upsample : int or None
    name : str
        The field to name in the error.

    Returns
    -------
    int or None

    Raises
    ------
    ScenarioError
        Naming ``name``, the value and the constraint.
    """
    if upsample is None:
        return None
    lo, hi = upsample_bounds()
    if isinstance(upsample, bool) or not float(upsample).is_integer() or not lo <= int(upsample) <= hi:
        raise ScenarioError(name, upsample, f"backprojection's range-profile upsampling: an integer from {lo} to {hi}")
    return int(upsample)


def run_memory_estimate(scenario: Scenario) -> tuple[float, str]:
    """Peak memory of :func:`salkit.simulate.simulate` then :func:`focus`: the larger of simulating and of focusing while the raw signal is
    held (:func:`salkit.simulate.memory_estimate`, :func:`salkit.focus.memory_estimate`), bytes.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (float, str)
    """
    sim, _ = simulate_memory_estimate(scenario)
    P, N = signal_shape(scenario)
    g = scenario.processing.grid
    foc, _ = memory_estimate(P, N, g.nx, g.ny, scenario.processing.algorithm, raw=True,
                             upsample=range_upsample(scenario.processing))
    return max(sim, foc + 8.0 * P * N), (f"simulating and focusing {P} pulses x {N} samples "
                                         f"({8.0 * P * N / 2 ** 30:.3g} GiB of signal) onto {g.nx} x {g.ny} pixels")


def _as_grid(grid) -> Grid | None:
    """``focus``'s grid: a Grid, None, or a mapping of a Grid's fields (validated into one)."""
    if grid is None or isinstance(grid, Grid):
        return grid
    if not isinstance(grid, Mapping):
        raise ScenarioError("grid", shown(grid), "must be a Grid (salkit.params.Grid), a mapping of its fields "
                            "(nx, ny, dx, dy, ...) or None")
    try:
        return Grid.model_validate(dict(grid))
    except ValidationError as err:
        e = err.errors()[0]
        field = ".".join(["grid", *map(str, e["loc"])])
        value = e.get("input") if e["type"] != "missing" else NOT_GIVEN
        raise ScenarioError(field, value, e["msg"].removeprefix("Value error, ")) from None


def focus(raw: xr.Dataset, processing: Optional[Processing] = None, *, scenario=None, algorithm: str | None = None,
          grid: Grid | None = None, window_name: str | None = None, plane: str | None = None,
          progress: Optional[Callable[[int, int], None]] = None, accuracy: str | None = None,
          memory_limit: float | str | None = None, client=None, upsample: int | None = None) -> xr.Dataset:
    """Form a complex image from raw data or a phase history, with the processor its kind names.

    Parameters
    ----------
    raw : xarray.Dataset
        A salkit raw (dechirped) or phase-history dataset, or down-looking raw data
        (``docs/data-format.md``).
    processing : Processing, optional
        Algorithm, window and grid. Default: the processing block of ``scenario``, else of the
        scenario stored in ``raw``, else backprojection on :func:`default_grid`.
    scenario : Scenario, optional
        The scenario ``raw`` was simulated from, when the caller has it (saves parsing the copy
        stored in ``raw.attrs``; used for the processing defaults and the true target positions).
    algorithm : str, optional
        A declared former (:data:`salkit.registry.FORMERS`); overrides ``processing.algorithm``.
    grid : Grid or mapping, optional
        Overrides ``processing.grid`` (a mapping of a Grid's fields is validated into one).
    window_name : {"none", "hamming", "taylor"}, optional
        Overrides ``processing.window``.
    plane : {"slant", "ground"}, optional
        Overrides the grid's image plane (the grid's size and spacing are kept).
    progress : callable, optional
        ``progress(done, total)`` in pulses (in tiles when tiled; one with a ``renamed(unit)``
        method, :class:`salkit.systems.result.Stage`, is renamed "tiles formed").
    accuracy : {"standard", "high"}, optional
        Overrides ``processing.accuracy`` (each former declares what a level does and promises:
        bp 32x profiles or more, ffbp finer polar grids).
    memory_limit : int, float or str, optional
        Memory budget, bytes or a size such as ``"512MiB"`` (default, and at most: the memory
        available, :func:`salkit.resources.available_memory`). A job whose estimate exceeds it is
        formed in tiles of the output grid (formers that declare ``tiles``) and, for spotlight
        data, with its pulses in blocks read from ``raw`` as needed (those that declare ``blocks``) (``raw`` may be opened lazily from a file);
        the image's ``tiling`` attribute says how (:mod:`salkit.focus.tiles`).
    client : dask.distributed.Client, optional
        Form the tiles on Dask (formers that tile): at least two tiles a worker; a file's pulses
        read by each worker itself. ``memory_limit`` is then per worker on a remote cluster, and
        shared by the workers of a local one (``client.cluster`` a ``LocalCluster``).
    upsample : int, optional
        Backprojection's range-profile upsampling, 2 to 64; overrides ``processing.range_upsample``
        and the former's own (:func:`range_upsample`: ``bp`` 6; ``accuracy: high`` still takes at
        least the former's high one, ``bp`` 8, the others 32). The fitted taps of ``bp`` and
        ``bp_fitted`` are -74, -88 and -98 dB against the truth at 4, 6 and 8 (docs/performance.md).

    Returns
    -------
    xarray.Dataset
        ``image`` (azimuth, range) complex64, coordinates in metres from the scene centre,
        normalised so that a unit-reflectance point at the beam centre peaks near 1.

    Raises
    ------
    ScenarioError
        For an undeclared former, a grid coarser than the resolution, or a former that does not
        form such data (its declared modes and tracks: PFA on stripmap, omega-k on spotlight).
    DataFileError
        For inconsistent arrays.
    ResourceError
        When the estimated peak memory exceeds the budget and the job cannot be cut to fit (a
        former that does not tile; or one tile alone too big): the message names the memory and
        the budget.

    Examples
    --------
    >>> image = focus(raw, algorithm="pfa")  # doctest: +SKIP
    >>> image = focus(raw, algorithm="ffbp", memory_limit="512MiB")  # doctest: +SKIP
    """
    require_dataset(raw, "focus")
    if processing is not None and not isinstance(processing, Processing):
        hint = (f"; to choose a former by name, algorithm={processing!r}" if isinstance(processing, str) else "")
        raise ScenarioError("processing", shown(processing),
                            f"must be a Processing block (a scenario's .processing) or None{hint}")
    if scenario is not None:
        require_scenario(scenario)
    grid = _as_grid(grid)
    proc = PROCESSORS.get(str(raw.attrs.get("salkit_kind", "raw")), focus_sal)
    return proc(raw, processing, scenario=scenario, algorithm=algorithm, grid=grid, window_name=window_name,
                plane=plane, progress=progress, accuracy=accuracy, memory_limit=memory_limit, client=client,
                upsample=upsample)


def focus_sal(raw: xr.Dataset, processing: Optional[Processing] = None, *, scenario=None,
              algorithm: str | None = None, grid: Grid | None = None, window_name: str | None = None,
              plane: str | None = None, progress: Optional[Callable[[int, int], None]] = None,
              accuracy: str | None = None, memory_limit: float | str | None = None, out=None,
              client=None, upsample: int | None = None) -> xr.Dataset:
    """The SAL processor of :func:`focus` (raw dechirped data and phase histories): range
    compression, then the declared former :func:`get_former` names. Parameters as :func:`focus`.

    Returns
    -------
    xarray.Dataset

    Parameters
    ----------
    raw, processing, scenario, algorithm, grid, window_name, plane, progress, accuracy, memory_limit, client
        As :func:`focus`.
    out : path, optional
        Write the image tile by tile into this file (:func:`focus_to_file`) and return it opened lazily.
    """
    if scenario is None:
        scenario = stored_scenario(raw.attrs)
    if not isinstance(scenario, Scenario):
        scenario = None
    if processing is None and scenario is not None:
        processing = scenario.processing
    alg = algorithm or (processing.algorithm if processing else "bp")
    former = former_spec(alg)  # an undeclared former is refused before any work
    stripmap = str(raw.attrs.get("mode", "spotlight")) == "stripmap" and float(raw.attrs.get("real_aperture", 0)) > 0
    if not former.accepts("stripmap" if stripmap else "spotlight", True):  # the track is checked by the former
        raise ScenarioError("processing.algorithm", alg, former.refusal("stripmap" if stripmap else "spotlight", True))
    P, N = raw["signal"].shape
    chirp = processing.chirp_correction if processing is not None else "none"
    noise_fix = processing.phase_noise_correction if processing is not None else "none"
    spread = _spread(client)
    upsample = check_upsample(upsample)
    up = range_upsample(processing, accuracy, upsample, alg)
    if plane is not None:
        check_choice("plane", plane, PLANES)
    g, geometry, source = None, None, None
    if former.footprint is not None:  # its memory follows the pulses' positions and the grid: planned on them
        source = DatasetPulses(raw, chirp, noise_fix)
        geo = source.geometry()
        g = _grid_for(geo, grid, processing, plane)
        geometry = _geometry(geo, g, processing, accuracy)
        tiling, held = _plan(raw, alg, g.nx, g.ny, memory_limit, out is None, spread, up, geometry)
    else:
        g0 = grid or (processing.grid if processing else None)
        tiling, held = _plan(raw, alg, g0.nx if g0 else 256, g0.ny if g0 else 256, memory_limit, out is None, spread,
                             up)
    if tiling.pulse_block < P:  # the signal is read and range-compressed a block at a time
        pulses = source or DatasetPulses(raw, chirp, noise_fix)
        ph = geo if source is not None else pulses.geometry()
    else:
        source = raw.encoding.get("source")
        with lazy_reads("signal", source):
            ph = phase_history(raw, chirp, noise_fix)
        if not held and not np.isfinite(ph.data).all():  # a lazily opened file is checked as it is read
            raise DataFileError(f"{source + ': ' if source else ''}variable 'signal' has non-finite values")
        pulses = InMemoryPulses(ph)
    if g is None:
        g = _grid_for(ph, grid, processing, plane)
    p = processing or Processing(grid=g)
    if upsample is not None:  # validated above; form_image reads it from the processing
        p = p.model_copy(update={"range_upsample": upsample})
    res = theory_resolution(ph, ImageGrid.of(ph, g).plane)
    if (g.nx, g.ny) != (tiling.nx, tiling.ny):
        tiling, _ = _plan(raw, alg, g.nx, g.ny, memory_limit, out is None, spread, up)
    if tiling.tiled:
        _log.info("focusing %s", tiling.describe())
        if hasattr(progress, "renamed"):  # a stage of a run's progress: its unit is now the tile
            progress = progress.renamed("tiles formed")
    ig = ImageGrid.of(ph, g)
    win = Window(window_name or p.window, p.taylor_nbar, p.taylor_sll)
    attrs = _image_attrs(ph, raw, scenario, g, alg, win, res)
    if "origin_llh" in attrs:  # placed on the earth: the pixels' geodetic positions (corners, centre)
        attrs.update(image_geolocation(attrs["origin_llh"], ig.plane, ig.azimuth, ig.range))
    truth = None
    if scenario is not None and scenario.scene.points:
        truth = truth_positions(scenario.model_copy(update={"processing": scenario.processing.model_copy(
            update={"grid": g})}))
    if out is not None:  # tile by tile into a chunked file, never whole in memory
        blank = np.broadcast_to(np.complex64(0), ig.shape)
        skel = add_collection_geometry(make_image_dataset(blank, ig.azimuth, ig.range, ig.plane, attrs, truth),
                                       raw, ph).drop_vars("image")
        with ImageFileWriter(out, skel, (tiling.tile_nx, tiling.tile_ny)) as w:
            result, _, _, used = form_image(ph, p, g, algorithm=alg, window_name=window_name, accuracy=accuracy,
                                            progress=progress, tiling=tiling, pulses=pulses, sink=w.write,
                                            client=client)
            w.close(_result_attrs(result.info, used, tiling, attrs))
        return open_dataset(out, lazy=True)
    result, ig, win, used = form_image(ph, p, g, algorithm=alg, window_name=window_name, accuracy=accuracy,
                                       progress=progress, tiling=tiling, pulses=pulses, client=client)
    attrs.update(_result_attrs(result.info, used, tiling, attrs))
    image = make_image_dataset(result.image, ig.azimuth, ig.range, ig.plane, attrs, truth)
    return add_collection_geometry(image, raw, ph)


def _geometry(geo: PhaseHistory, g: Grid, processing: Optional[Processing], accuracy: str | None) -> Geometry:
    """The pulses and the grid a former's declared ``footprint`` weighs (the planner's
    :class:`salkit.focus.tiles.Geometry`), at the accuracy the processing or ``accuracy`` names."""
    acc = accuracy or (processing.accuracy if processing is not None else "standard")
    return Geometry(geo.positions, geo.freq, ImageGrid.of(geo, g), acc)


def _grid_for(ph: PhaseHistory, grid: Grid | None, processing: Optional[Processing], plane: str | None) -> Grid:
    """The grid :func:`focus_sal` forms: the one given, the processing's, or the default for the
    data (:func:`default_grid`), in ``plane`` when one is named; refused when its spacing exceeds the
    resolution; a warning when a spotlight grid spans more azimuth than the pulse spacing holds
    without ambiguity (:func:`salkit.focus.pfa.illuminated_extent`, the data's limit): targets
    would repeat in the image, as the scenario's own check warns before a simulation."""
    g = grid or (processing.grid if processing else default_grid(ph, plane=plane or "slant"))
    if plane is not None and g.plane != plane:
        g = g.model_copy(update={"plane": plane})
    ig_plane = ImageGrid.of(ph, g).plane
    if ph.mode != "stripmap" and ph.positions.shape[0] > 1:
        from .pfa import illuminated_extent  # here: importing it registers pfa, ahead of the formers' declared order
        # at the band's centre, as the scenario's check (lambda R PRF / 2v): the data's extent is
        # given at the shortest wavelength, lambda_min / (2 dtheta)
        f = np.asarray(ph.freq, np.float64)
        unamb = illuminated_extent(f, ph.positions, ig_plane)["azimuth"] * float(f.max()) / float(f[f.size // 2])
        if g.nx * g.dx > unamb * (1 + 1e-6):
            warnings.warn(f"processing.grid spans {g.nx * g.dx:.4g} m in azimuth, more than the unambiguous "
                          f"azimuth extent the pulse spacing holds, lambda / (2 dtheta) = {unamb:.4g} m at the "
                          "band's centre: targets would repeat in the image", UserWarning, stacklevel=3)
    res = theory_resolution(ph, ig_plane)
    if g.dx > res["azimuth"] * GRID_SPACING_OF_RESOLUTION or g.dy > res["range"] * GRID_SPACING_OF_RESOLUTION:
        raise ScenarioError("processing.grid", f"dx={g.dx:g}, dy={g.dy:g}",
                            f"spacing must not exceed the resolution (azimuth {res['azimuth']:.4g} m, "
                            f"range {res['range']:.4g} m)")
    return g


def _plan(raw: xr.Dataset, alg: str, nx: int, ny: int, memory_limit, hold_image: bool, spread: dict,
          upsample: int | None = None, geometry: Geometry | None = None):
    """The tiling of focusing ``raw`` onto nx x ny (:func:`salkit.focus.tiles.plan_tiling`) within
    the budget, counting the signal as held when it is in memory; and the bytes held. ``geometry``:
    the pulses and the grid, for a former whose memory follows them."""
    P, N = raw["signal"].shape
    held = float(raw["signal"].nbytes) if getattr(raw["signal"].variable, "_in_memory", True) else 0.0  # lazily opened: not held
    stripmap = str(raw.attrs.get("mode", "spotlight")) == "stripmap" and float(raw.attrs.get("real_aperture", 0)) > 0
    tiling = plan_tiling(P, N, nx, ny, alg, memory_budget(memory_limit, held), raw=raw.attrs.get("salkit_kind") == "raw",
                         stripmap=stripmap, hold_image=hold_image, upsample=upsample, geometry=geometry, **spread)
    return tiling, held


def _spread(client) -> dict:
    """How tiles share the budget on Dask: two tiles a worker at least; on a local cluster the
    workers' tiles are in work at once on this machine's budget."""
    if client is None:
        return {}
    n = max(1, len(client.scheduler_info().get("workers", {})))
    local = type(getattr(client, "cluster", None)).__name__ == "LocalCluster"
    return {"min_tiles": 2 * n, "at_once": n if local else 1}


def _image_attrs(ph: PhaseHistory, raw: xr.Dataset, scenario, g: Grid, alg: str, win: Window, res: dict) -> dict:
    """An image's attributes known before it is formed: the processing, the theory, the collection."""
    M = ph.freq.size
    wi = window_ipr(win.name, win.nbar, win.sll)
    attrs = {
        "algorithm": alg, "window": win.name, "plane": g.plane,
        "wavelength": ph.wavelength, "carrier_frequency": float(ph.freq[M // 2]),
        "bandwidth": res["bandwidth"], "mode": ph.mode,
        "resolution_range": res["range"], "resolution_azimuth": res["azimuth"],
        "irw_range_theory": float(wi["irw_factor"]) * res["range"],
        "irw_azimuth_theory": float(wi["irw_factor"]) * res["azimuth"],
        "pslr_theory": wi["pslr_db"], "islr_theory": wi["islr_db"], "window_irw_factor": float(wi["irw_factor"]),
        "ipr_theory": "window",
        "grid_dx": g.dx, "grid_dy": g.dy,
        # stripmap pixels are focused about their own broadside: image phase follows the track
        "phase_reference": "track" if ph.mode == "stripmap" else former_spec(alg).phase_reference,
        "aperture_center": ph.center_position,
    }
    if not ph.beam_limited and former_spec(alg).support == "collection":
        # a spotlight image holding the collection's K-space support: its point's response is that
        # support's transform (an annular sector past a few degrees, not the window's rectangle)
        plane = ImageGrid.of(ph, g).plane
        t = support_ipr(ph.positions, ph.freq, plane.azimuth, plane.range, res["azimuth"], res["range"], win.name,
                        win.nbar, win.sll)
        attrs["ipr_theory"] = "support"
        for ax in ("range", "azimuth"):
            if np.isfinite(t[f"irw_{ax}"]):
                attrs[f"irw_{ax}_theory"] = t[f"irw_{ax}"]
                attrs[f"pslr_{ax}_theory"], attrs[f"islr_{ax}_theory"] = t[f"pslr_{ax}"], t[f"islr_{ax}"]
    for k in ("frequency_fit_residual_steps", "frequency_fit_residual", "phase_sign_converted"):
        if k in ph.attrs:
            attrs[k] = ph.attrs[k]
    if "scenario" in raw.attrs:
        attrs["scenario"] = raw.attrs["scenario"]
    attrs["frequency_min"], attrs["frequency_max"] = float(ph.freq[0]), float(ph.freq[-1])
    if "origin_llh" in ph.attrs:
        attrs["origin_llh"] = np.asarray(ph.attrs["origin_llh"], np.float64)
    return attrs


def _result_attrs(info: dict, used: dict, tiling, known: dict | None = None) -> dict:
    """An image's attributes from its forming: accuracy, support, and how it was cut; and, for a
    former that resampled onto a rectangle of support (``support_*_extent``, rad/m, polar format),
    the IRW theory of that rectangle: the window's factor times 2 pi over its extents (``known``:
    the attributes set before forming, with the window's factor)."""
    attrs = {"accuracy": used["accuracy"], "range_upsample": used["range_upsample"]}
    attrs.update({k: v for k, v in info.items() if k.startswith(("support_", "cover_", "illuminated_", "ffbp_", "pfa_"))})
    if known is not None and known.get("ipr_theory") == "window" and "window_irw_factor" in known:
        for ax in ("range", "azimuth"):
            if info.get(f"support_{ax}_extent", 0) > 0:
                attrs[f"irw_{ax}_theory"] = float(known["window_irw_factor"]) * 2 * np.pi / float(
                    info[f"support_{ax}_extent"])
    if tiling.tiled:
        attrs.update(tiling=tiling.describe(), tiles=tiling.n_tiles, tile_nx=tiling.tile_nx, tile_ny=tiling.tile_ny,
                     pulse_block=tiling.pulse_block)
    return attrs


def image_fits(raw: xr.Dataset, processing: Optional[Processing] = None, *, grid: Grid | None = None,
               algorithm: str | None = None, memory_limit: float | str | None = None, client=None,
               accuracy: str | None = None, upsample: int | None = None) -> bool:
    """Whether :func:`focus` can hold the whole image of ``raw`` in memory within the budget (in
    tiles if need be); when not, :func:`focus_to_file` writes it tile by tile.

    Parameters
    ----------
    raw : xarray.Dataset
    processing : Processing, optional
    grid : Grid, optional
    algorithm : str, optional
    memory_limit : int, float or str, optional
    client : dask.distributed.Client, optional
        As :func:`focus` (a local cluster's tiles share the budget).
    accuracy : {"standard", "high"}, optional
    upsample : int, optional
        As :func:`focus` (backprojection's profiles, in the estimate, follow them).

    Returns
    -------
    bool
    """
    scenario = stored_scenario(raw.attrs)
    proc = processing or (scenario.processing if isinstance(scenario, Scenario) else None)
    g = grid or (proc.grid if proc is not None else None)
    if g is None:
        return True  # the default grid, 256 x 256
    alg = algorithm or (proc.algorithm if proc is not None else "bp")
    geometry = None
    if former_spec(alg).footprint is not None:  # its memory follows the pulses' positions and the grid
        geo = DatasetPulses(raw, proc.chirp_correction if proc is not None else "none",
                            proc.phase_noise_correction if proc is not None else "none").geometry()
        geometry = _geometry(geo, g, proc, accuracy)
    try:
        _plan(raw, alg, g.nx, g.ny, memory_limit, True, _spread(client),
              range_upsample(proc, accuracy, check_upsample(upsample), alg), geometry)
    except ResourceError:
        return False
    return True


def focus_to_file(raw: xr.Dataset, path, processing: Optional[Processing] = None, **options) -> xr.Dataset:
    """Form an image straight into a chunked NetCDF file, tile by tile, never whole in memory: for
    images larger than the memory budget (:class:`salkit.io.ImageFileWriter`; the file is complete
    under ``path`` or absent).

    Parameters
    ----------
    raw : xarray.Dataset
        As :func:`focus` (opened lazily from a file, :func:`salkit.io.open_dataset` ``lazy=True``,
        for a history larger than memory: spotlight ``bp`` then reads it in pulse blocks).
    path : path
        The image file to write.
    processing : Processing, optional
    **options
        ``scenario``, ``algorithm``, ``grid``, ``window_name``, ``plane``, ``progress``,
        ``accuracy``, ``memory_limit``, ``upsample`` as :func:`focus`.

    Returns
    -------
    xarray.Dataset
        The written image, opened lazily.

    Raises
    ------
    ResourceError, ScenarioError, DataFileError
        As :func:`focus`; nothing is written.
    """
    if str(raw.attrs.get("salkit_kind", "raw")) not in ("raw", "phase_history"):
        raise ScenarioError("raw", raw.attrs.get("salkit_kind"), "focus_to_file forms SAL raw data or phase histories")
    return focus_sal(raw, processing, out=path, **options)


def form_image(ph: PhaseHistory, processing: Processing, grid: Grid, *, algorithm: str | None = None,
               window_name: str | None = None, accuracy: str | None = None,
               progress: Optional[Callable[[int, int], None]] = None, tiling=None, pulses=None, sink=None,
               client=None):
    """Form the image of a phase history with a scenario's processing settings: the former, window
    and accuracy they name (each overridable), on ``grid``. The one place these settings become a
    former call (:func:`focus_sal`, and the sub-images of :mod:`salkit.stack`, which need no dataset).

    Parameters
    ----------
    ph : PhaseHistory
    processing : Processing
    grid : Grid
        Output grid (m).
    algorithm, window_name, accuracy : str, optional
        Overrides of ``processing.algorithm``, ``processing.window`` and ``processing.accuracy``.
    progress : callable, optional
        ``progress(done, total)`` in pulses (in tiles when tiled).
    tiling : Tiling, optional
        Form the image in the tiles (and pulse blocks) it names (:func:`salkit.focus.tiles.plan_tiling`).
    pulses : InMemoryPulses or DatasetPulses, optional
        Where the pulse blocks come from when tiled (default: ``ph``).
    sink : callable, optional
        ``sink(i0, j0, tile)`` receives the tiles instead of an image in memory (the result's
        ``image`` is then None).
    client : dask.distributed.Client, optional
        Form the tiles on Dask (:func:`salkit.focus.tiles.form_tiles`).

    Returns
    -------
    (ImageResult, ImageGrid, Window, dict)
        The former's result, the grid it was formed on, the window, and the settings used
        (``algorithm``, ``accuracy``, ``range_upsample``).
    """
    alg = algorithm or processing.algorithm
    acc = accuracy or processing.accuracy
    check_choice("processing.accuracy", acc, ACCURACY)
    upsample = range_upsample(processing, acc, algorithm=alg)
    win = Window(window_name or processing.window, processing.taylor_nbar, processing.taylor_sll)
    ig = ImageGrid.of(ph, grid)
    if sink is not None or client is not None or (tiling is not None and tiling.tiled):
        img = None if sink is not None else np.empty(ig.shape, np.complex64)

        def keep(i0, j0, tile):
            img[i0:i0 + tile.shape[0], j0:j0 + tile.shape[1]] = tile

        info = form_tiles(pulses or InMemoryPulses(ph), ig, win, tiling, upsample=upsample, accuracy=acc,
                          sink=sink or keep, progress=progress, client=client)
        result = ImageResult(img, info)
    else:
        result = get_former(alg)(ph, ig, win, upsample=upsample, accuracy=acc, progress=progress)
    return result, ig, win, {"algorithm": alg, "accuracy": acc, "range_upsample": upsample}


def memory_budget(limit: float | str | None = None, held: float = 0.0) -> float:
    """The memory a job may use, bytes: the smallest of ``limit`` (bytes or a size string), the
    memory available now (:func:`salkit.resources.available_memory`) and the user's limit
    (:func:`salkit.resources.user_limit`) less ``held``, what the caller already holds (a cap counts
    it; the memory available now has it taken out already).

    Parameters
    ----------
    limit : int, float or str, optional
    held : float
        Bytes the caller holds (an input signal in memory).

    Returns
    -------
    float

    Raises
    ------
    ScenarioError
        An unreadable or non-positive size (``memory_limit``).
    """
    cands = [float(available_memory())]
    if limit is not None:
        try:  # the library's argument (the command line checks its --memory-limit before)
            b = float(parse_size(limit, "memory_limit")) if isinstance(limit, str) else float(limit)
        except (TypeError, ValueError):
            raise ScenarioError("memory_limit", limit, "must be bytes or a size such as 8GiB, 512MB or 2e9") from None
        if not b > 0:
            raise ScenarioError("memory_limit", limit, "must be positive")
        cands.append(b - held)
    cap = user_limit()
    if cap is not None:
        cands.append(cap - held)
    return max(min(cands), 0.0)


def run_memory_plan(scenario: Scenario, limit: float | str | None = None):
    """The memory plan of :func:`salkit.simulate.simulate` then :func:`focus`: simulating must fit
    the budget; focusing, with the raw signal held, runs in tiles when it does not fit whole (FFBP
    weighed on the collection the scenario will simulate, as :func:`focus` will weigh it).

    Parameters
    ----------
    scenario : Scenario
    limit : int, float or str, optional
        As :func:`memory_budget`.

    Returns
    -------
    Tiling
        How focusing will be cut (:func:`salkit.focus.tiles.plan_tiling`).

    Raises
    ------
    ResourceError
        When simulating does not fit, or focusing cannot be cut to fit beside the signal.
    ScenarioError
        When FFBP cannot form the collection (pulses past the scene).
    """
    sim, what = simulate_memory_estimate(scenario)
    budget = memory_budget(limit)
    if sim > budget:
        raise ResourceError(f"{what} needs about {size_text(sim)} of memory, more than the {size_text(budget)} "
                            "available (the memory free now, --max-memory or --memory-limit); reduce "
                            "receiver.adc_rate, platform.aperture_length or waveform.prf")
    P, N = signal_shape(scenario)
    g, p = scenario.processing.grid, scenario.processing
    stripmap = scenario.platform.mode == "stripmap" and scenario.platform.real_aperture > 0
    return plan_tiling(P, N, g.nx, g.ny, p.algorithm, budget - 8.0 * P * N, raw=True, stripmap=stripmap,
                       upsample=range_upsample(p), geometry=_scenario_geometry(scenario, N))


def _scenario_geometry(scenario: Scenario, n_samples: int) -> Geometry | None:
    """The collection a scenario will simulate and the grid it will be formed on, for a former
    whose memory follows them (a declared ``footprint``): the pulses' positions, the phase history's
    frequencies (c / wavelength + rate x fast time, as range compression makes them) and the
    processing grid; None for other formers."""
    p = scenario.processing
    if former_spec(p.algorithm).footprint is None:
        return None
    col = build_collection(scenario)
    w = scenario.waveform
    freq = w.carrier_frequency + w.rate * fast_time_axis(n_samples, scenario.receiver.adc_rate)
    g = p.grid
    ig = ImageGrid(plane_from(col.track, col.center_position, g.plane), *grid_axes(g), g)
    return Geometry(col.positions, freq, ig, p.accuracy)


def _focus_downlooking(raw: xr.Dataset, processing=None, *, scenario=None, progress=None, **options) -> xr.Dataset:
    """The down-looking processor of :func:`focus`: its processing is in the scenario it carries."""
    for name, v in (("processing", processing), *options.items()):
        if v is not None:
            flag = "--range-upsample" if name == "upsample" else f"--{name.replace('_name', '')}"
            raise ScenarioError(flag, v, "does not apply to down-looking SAL raw data "
                                "(its processing is in the scenario the file carries)")
    return focus_downlooking_raw(raw, progress=progress)


#: data kind (``salkit_kind``) -> processor, all ``f(raw, processing, *, scenario, algorithm,
#: grid, window_name, plane, progress, accuracy, memory_limit, client, upsample) -> xr.Dataset``.
PROCESSORS = {"raw": focus_sal, "phase_history": focus_sal, "raw_downlooking": _focus_downlooking}


def grid_of(image: xr.Dataset) -> Grid:
    """The :class:`~salkit.params.models.Grid` an image was formed on (size, spacing, plane, centre).

    Parameters
    ----------
    image : xarray.Dataset
        salkit image.

    Returns
    -------
    Grid
    """
    az, rg = image["azimuth"].values, image["range"].values
    return Grid(nx=az.size, ny=rg.size, dx=float(az[1] - az[0]), dy=float(rg[1] - rg[0]),
                plane=str(image.attrs.get("plane", "slant")),
                center=(float(az[az.size // 2]), float(rg[rg.size // 2])))


def add_collection_geometry(image: xr.Dataset, raw: xr.Dataset, ph: PhaseHistory) -> xr.Dataset:
    """Carry the per-pulse antenna positions and times of the collection with its image
    (variables ``collection_position`` (pulse, xyz), m, and ``collection_time`` (pulse,), s), so
    that exports (SICD) need no other file. Without pulse times in the data, the pulse index
    times 1 ms stands in and ``collection_time_nominal = 1``.

    Parameters
    ----------
    image : xarray.Dataset
        The formed image.
    raw : xarray.Dataset
        The data it was formed from (for ``slow_time``).
    ph : PhaseHistory
        Its phase history (positions, m).

    Returns
    -------
    xarray.Dataset
        ``image`` with ``collection_position`` and ``collection_time``.
    """
    P = ph.positions.shape[0]
    t = None
    if "slow_time" in raw.coords and raw.sizes.get("slow_time") == P:
        t = np.asarray(raw["slow_time"].values, np.float64)
    nominal = t is None or raw.attrs.get("slow_time_units") == "pulse"
    if nominal:
        t = np.arange(P, dtype=np.float64) * 1e-3
    image = image.assign(collection_position=(("pulse", "xyz"), ph.positions, {"units": "m"}),
                         collection_time=(("pulse",), t, {"units": "s"}))
    image = image.assign_coords(xyz=("xyz", ["x", "y", "z"]))
    image.attrs["collection_time_nominal"] = int(nominal)
    return image
