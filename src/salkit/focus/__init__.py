"""Image formation: one entry point, ``focus(raw, processing) -> image``, over interchangeable
algorithms (``bp`` backprojection, ``pfa`` polar format, ``omegak`` wavenumber domain)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
import xarray as xr

from ..choices import ALGORITHMS, PLANES, check_choice
from ..constants import SPEED_OF_LIGHT
from ..errors import DataFileError, ScenarioError
from ..geometry.collection import (angle_between, beam_gain_table, grid_axes, plane_from, truth_positions,
                                   two_way_3db_sin)
from ..io.datasets import make_image_dataset
from ..io.ingest import normalise_phase_history
from ..params.models import Grid, Processing
from ..resources import check_memory
from ..metrics.pointtarget import window_ipr
from ..signals.windows import window
from .backprojection import backproject
from .omegak import omegak as omega_k  # keep salkit.focus.omegak the module
from .pfa import pfa as polar_format  # keep salkit.focus.pfa the module
from .rangecomp import range_compress
from .stripmap_bp import stripmap_backprojection



@dataclass(frozen=True)
class PhaseHistory:
    """Arrays of a range-compressed collection, as the algorithms consume them."""

    data: np.ndarray  # complex64 (P, M)
    freq: np.ndarray  # float64 (M,), increasing, uniform
    positions: np.ndarray  # float64 (P, 3), scene centre at origin
    reference_range: np.ndarray  # float64 (P,)
    track: np.ndarray  # unit (3,)
    center_position: np.ndarray  # (3,)
    mode: str
    real_aperture: float
    attrs: dict

    @property
    def wavelength(self) -> float:
        """Wavelength at the reference frequency (sample M//2), m."""
        return SPEED_OF_LIGHT / float(self.freq[self.freq.size // 2])


def phase_history(raw: xr.Dataset, chirp_correction: str = "none") -> PhaseHistory:
    """Range-compress ``raw`` (with an optional nonlinear-chirp correction) and extract arrays."""
    ds = range_compress(raw, chirp_correction)
    if raw.attrs.get("salkit_kind") == "phase_history":
        ds = normalise_phase_history(ds)
    data = np.asarray(ds["signal"].values, dtype=np.complex64)
    freq = np.asarray(ds["frequency"].values, dtype=np.float64)
    pos = np.asarray(ds["position"].values, dtype=np.float64)
    ref = np.asarray(ds["reference_range"].values, dtype=np.float64)
    P, M = data.shape
    if pos.shape != (P, 3) or ref.shape != (P,):
        raise DataFileError(f"position {pos.shape} and reference_range {ref.shape} must match "
                            f"{P} pulses")
    if M < 2 or P < 2:
        raise DataFileError(f"signal has shape {data.shape}; at least 2 pulses and 2 samples are needed")
    d = np.diff(freq)
    if d[0] < 0:
        freq, data = freq[::-1].copy(), data[:, ::-1].copy()
    track = np.asarray(ds.attrs.get("track", pos[-1] - pos[0]), dtype=np.float64)
    track = track / np.linalg.norm(track)
    cpos = np.asarray(ds.attrs.get("center_position", pos[P // 2]), dtype=np.float64)
    return PhaseHistory(data, freq, pos, ref, track, cpos, str(ds.attrs.get("mode", "spotlight")),
                        float(ds.attrs.get("real_aperture", 0.0)), dict(ds.attrs))


def theory_resolution(ph: PhaseHistory, plane) -> dict:
    """Unweighted resolutions (m) that the data support in the image plane."""
    c = SPEED_OF_LIGHT
    M = ph.freq.size
    B = M * (ph.freq[1] - ph.freq[0])
    look = -ph.center_position / np.linalg.norm(ph.center_position)
    rho_r = c / (2 * B) / max(abs(float(look @ plane.range)), 1e-12)
    lam = ph.wavelength
    if ph.mode == "stripmap" and ph.real_aperture > 0:
        ang = 2 * math.asin(min(two_way_3db_sin(lam, ph.real_aperture), 1.0))
    else:
        u = ph.positions / np.linalg.norm(ph.positions, axis=1, keepdims=True)
        P = u.shape[0]
        ang = angle_between(u[0], u[-1]) * P / (P - 1)
    return {"range": rho_r, "azimuth": lam / (2 * ang), "bandwidth": B, "angle": ang}


def default_grid(ph: PhaseHistory, n: int = 256, plane: str = "slant") -> Grid:
    """A grid of n x n pixels at 0.8 of the resolution, for data without a scenario."""
    pl = plane_from(ph.track, ph.center_position, plane)
    res = theory_resolution(ph, pl)
    return Grid(nx=n, ny=n, dx=0.8 * res["azimuth"], dy=0.8 * res["range"], plane=plane)


def memory_estimate(n_pulses: int, n_samples: int, nx: int, ny: int, algorithm: str = "bp",
                    raw: bool = True, cover_pixels: int | None = None) -> tuple[float, str]:
    """Peak memory of focusing, bytes, from the sizes.

    The signal (complex64, pulses x samples) once, and from raw data the deskew's 2N-point FFT
    buffers and the phase history (6 more); the image's float32 accumulators and complex64 output
    (24 bytes a pixel); PFA adds its formed (cover) grid and K-space buffer, omega-k its
    Stolt-interpolated spectrum.

    Parameters
    ----------
    n_pulses, n_samples : int
        Signal shape.
    nx, ny : int
        Output grid, pixels.
    algorithm : {"bp", "pfa", "omegak"}
    raw : bool
        Dechirped fast-time data (deskewed here) rather than a phase history.
    cover_pixels : int, optional
        PFA's formed grid when larger than nx x ny.

    Returns
    -------
    (float, str)
        Bytes, and the sizes that drive it.
    """
    sig = 8.0 * n_pulses * n_samples
    px = float(nx) * ny
    need = sig * (7 if raw else 2) + 24.0 * px
    if algorithm == "pfa":
        need += 24.0 * max(cover_pixels or 0, px) + sig
    elif algorithm == "omegak":
        need += 4 * sig + 16.0 * px
    return need, (f"focusing {n_pulses} pulses x {n_samples} samples onto {nx} x {ny} pixels "
                  f"({algorithm})")


def focus(raw: xr.Dataset, processing: Optional[Processing] = None, *, algorithm: str | None = None,
          grid: Grid | None = None, window_name: str | None = None, plane: str | None = None,
          progress: Optional[Callable[[int, int], None]] = None) -> xr.Dataset:
    """Form a complex image from raw data or a phase history.

    Parameters
    ----------
    raw : xarray.Dataset
        A salkit raw (dechirped) or phase-history dataset (``docs/data-format.md``).
    processing : Processing, optional
        Algorithm, window and grid. Default: the processing block of the scenario stored in
        ``raw``, else backprojection on :func:`default_grid`.
    algorithm : {"bp", "pfa", "omegak"}, optional
        Overrides ``processing.algorithm``.
    grid : Grid, optional
        Overrides ``processing.grid``.
    window_name : {"none", "hamming", "taylor"}, optional
        Overrides ``processing.window``.
    plane : {"slant", "ground"}, optional
        Overrides the grid's image plane (the grid's size and spacing are kept).
    progress : callable, optional
        ``progress(done, total)``.

    Returns
    -------
    xarray.Dataset
        ``image`` (azimuth, range) complex64, coordinates in metres from the scene centre,
        normalised so that a unit-reflectance point at the beam centre peaks near 1.

    Examples
    --------
    >>> image = focus(raw, algorithm="pfa")  # doctest: +SKIP
    """
    from ..params.scenario import parse_scenario
    import yaml

    scenario = None
    if "scenario" in raw.attrs:
        try:
            scenario = parse_scenario(yaml.safe_load(raw.attrs["scenario"]))
        except Exception:  # noqa: BLE001 - outside data may carry anything
            scenario = None
    if processing is None:
        processing = scenario.processing if scenario is not None else None
    g0 = grid or (processing.grid if processing else None)
    sig = raw["signal"]
    need, what = memory_estimate(sig.shape[0], sig.shape[1], g0.nx if g0 else 256, g0.ny if g0 else 256,
                                 algorithm or (processing.algorithm if processing else "bp"),
                                 raw=raw.attrs.get("salkit_kind") == "raw")
    check_memory(need, what, "use a smaller grid (--nx --ny) or fewer pulses")
    ph = phase_history(raw, processing.chirp_correction if processing is not None else "none")
    alg = algorithm or (processing.algorithm if processing else "bp")
    if alg not in ALGORITHMS:
        raise ScenarioError("processing.algorithm", alg, f"must be one of {ALGORITHMS}")
    if plane is not None:
        check_choice("plane", plane, PLANES)
    g = grid or (processing.grid if processing else default_grid(ph, plane=plane or "slant"))
    if plane is not None and g.plane != plane:
        g = g.model_copy(update={"plane": plane})
    win = window_name or (processing.window if processing else "none")
    nbar = processing.taylor_nbar if processing else 4
    sll = processing.taylor_sll if processing else 35.0
    ups = processing.range_upsample if processing else 8
    wfun = lambda n: window(win, n, nbar, sll)  # noqa: E731
    plane = plane_from(ph.track, ph.center_position, g.plane)
    az, rg = grid_axes(g)
    res = theory_resolution(ph, plane)
    if g.dx > res["azimuth"] * 1.01 or g.dy > res["range"] * 1.01:
        raise ScenarioError("processing.grid", f"dx={g.dx:g}, dy={g.dy:g}",
                            f"spacing must not exceed the resolution (azimuth {res['azimuth']:.4g} m, "
                            f"range {res['range']:.4g} m)")
    P, M = ph.data.shape
    if alg == "pfa":
        if ph.mode != "spotlight":
            raise ScenarioError("processing.algorithm", "pfa", "the polar format algorithm needs spotlight data")
        img, info = polar_format(ph.data, ph.freq, ph.positions, ph.reference_range, plane, az, rg, wfun, wfun,
                                 real_aperture=ph.real_aperture)
        if progress:
            progress(P, P)
    elif alg == "omegak":
        if ph.mode != "stripmap" or ph.real_aperture <= 0:
            raise ScenarioError("processing.algorithm", "omegak", "omega-k needs stripmap data")
        table, dsin = beam_gain_table(ph.wavelength, ph.real_aperture)
        img, info = omega_k(ph.data, ph.freq, ph.positions, ph.reference_range, plane, az, rg, ph.track,
                           ph.center_position, table, dsin, two_way_3db_sin(ph.wavelength, ph.real_aperture),
                           wfun, wfun)
        if progress:
            progress(P, P)
    elif ph.mode == "stripmap" and ph.real_aperture > 0:
        img = stripmap_backprojection(ph, plane, az, rg, wfun, upsample=ups, progress=progress)
        info = {"support_azimuth": P, "support_range": M}
    else:
        W = np.broadcast_to(wfun(P).astype(np.float32)[None, :], (az.size, P))
        wsum = W.sum(axis=1)
        row_origin = plane.points(az, np.zeros_like(az))
        wr = wfun(M)
        img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, row_origin, plane.range,
                          rg, W, wr, upsample=ups, progress=progress)
        norm = np.maximum(wsum, 1e-30) * wr.sum()
        img = (img / norm[:, None]).astype(np.complex64)
        info = {"support_azimuth": P, "support_range": M}
    wi = window_ipr(win, nbar, sll)
    attrs = {
        "algorithm": alg, "window": win, "plane": g.plane,
        "wavelength": ph.wavelength, "carrier_frequency": float(ph.freq[M // 2]),
        "bandwidth": res["bandwidth"], "mode": ph.mode,
        "resolution_range": res["range"], "resolution_azimuth": res["azimuth"],
        "irw_range_theory": float(wi["irw_factor"]) * res["range"],
        "irw_azimuth_theory": float(wi["irw_factor"]) * res["azimuth"],
        "pslr_theory": wi["pslr_db"], "islr_theory": wi["islr_db"],
        "grid_dx": g.dx, "grid_dy": g.dy,
        # stripmap pixels are focused about their own broadside: image phase follows the track
        "phase_reference": "track" if (alg == "omegak" or ph.mode == "stripmap") else "aperture_centre",
        "aperture_center": ph.center_position,
    }
    attrs.update({k: v for k, v in info.items() if k.startswith(("support_", "cover_", "illuminated_"))})
    for k in ("frequency_fit_residual_steps", "frequency_fit_residual", "phase_sign_converted"):
        if k in ph.attrs:
            attrs[k] = ph.attrs[k]
    if "scenario" in raw.attrs:
        attrs["scenario"] = raw.attrs["scenario"]
    truth = None
    if scenario is not None and scenario.scene.points:
        try:
            truth = truth_positions(scenario.model_copy(update={"processing": scenario.processing.model_copy(
                update={"grid": g})}))
        except Exception:  # noqa: BLE001
            truth = None
    attrs["frequency_min"], attrs["frequency_max"] = float(ph.freq[0]), float(ph.freq[-1])
    if "origin_llh" in ph.attrs:
        attrs["origin_llh"] = np.asarray(ph.attrs["origin_llh"], np.float64)
    out = make_image_dataset(img, az, rg, plane, attrs, truth)
    return add_collection_geometry(out, raw, ph)


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
    times 1 ms stands in and ``collection_time_nominal = 1``."""
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


__all__ = ["ALGORITHMS", "PhaseHistory", "default_grid", "focus", "grid_of", "memory_estimate", "phase_history", "range_compress",
           "theory_resolution"]


from .._callable import make_callable as _make_callable  # noqa: E402

_make_callable(__name__, "focus")
