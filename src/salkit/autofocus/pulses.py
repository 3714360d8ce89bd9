"""Autofocus on the full phase history: one phase per pulse, estimated by backprojection
sharpness (:mod:`salkit.autofocus.sharpness`) and applied to the data before image formation.

Unlike PGA and minimum entropy on a formed image, whose azimuth spectrum has only as many bins as
the grid has rows, this estimates a phase for every pulse, so a white (pulse-to-pulse) error is
recoverable as well as a smooth one.
"""
from __future__ import annotations

import math
import time
from typing import Callable, Optional

import numpy as np
import xarray as xr

from ..choices import PLANES, check_choice
from ..errors import ScenarioError
from ..focus import PhaseHistory, default_grid, grid_of, phase_history
from ..focus.bp_kernel import pulse_contributions
from ..focus.profiles import range_profiles
from ..focus.pfa import illuminated_extent
from ..geometry.collection import grid_axes, plane_from
from ..params.models import Grid
from ..tolerances import BP_UPSAMPLE
from .sharpness import PulseAutofocusResult, pulse_sharpness

#: Largest contribution matrix (pulses x pixels) held in memory: 2**26 complex64 = 512 MiB.
MAX_ENTRIES = 2 ** 26
#: The sharpness is measured over the scene the data hold, up to this many times the output
#: grid's extent on each axis (``support = "scene"``).
SUPPORT_FACTOR = 3.0


def support_grid(ph: PhaseHistory, grid: Grid, factor: float = SUPPORT_FACTOR) -> Grid:
    """The grid the per-pulse sharpness is measured on: ``grid`` widened, at its spacing and
    centre, to the scene the data hold (:func:`salkit.focus.pfa.illuminated_extent`: what the
    pulse spacing and frequency step hold without ambiguity, and the beam's footprint where the
    telescope is known), at most ``factor`` times its extent per axis and never narrower than it.

    A per-pulse error moves the energy of the whole illuminated scene, not only of the output
    grid: measured over the grid alone, a scene larger than the grid leaves the estimate with a
    fraction of the information (on the wide-angle testbed, 0.14-0.17 rad residual against
    0.04-0.06 rad over the scene).

    Parameters
    ----------
    ph : PhaseHistory
    grid : Grid
    factor : float
        Largest widening per axis.

    Returns
    -------
    Grid
    """
    plane = plane_from(ph.track, ph.center_position, grid.plane)
    ext = illuminated_extent(ph.freq, ph.positions, plane, ph.real_aperture)
    ext_a, ext_r = ext["azimuth"], ext["range"]
    nx = int(min(max(grid.nx, math.floor(ext_a / grid.dx)), math.ceil(factor * grid.nx)))
    ny = int(min(max(grid.ny, math.floor(ext_r / grid.dy)), math.ceil(factor * grid.ny)))
    return grid.model_copy(update={"nx": nx, "ny": ny})


def select_pixels(ph: PhaseHistory, grid: Grid, max_entries: int = MAX_ENTRIES) -> np.ndarray:
    """Pixels (K, 3) of ``grid`` used for the sharpness: all of them when P x K fits in
    ``max_entries``, else whole range columns in order of their energy in the range-compressed
    data (a per-pulse phase does not move energy across range), every azimuth row kept.

    Parameters
    ----------
    ph : PhaseHistory
    grid : Grid
    max_entries : int
        Largest P x K.

    Returns
    -------
    float64 (K, 3)
        Points in the scene frame, m.
    """
    plane = plane_from(ph.track, ph.center_position, grid.plane)
    az, rg = grid_axes(grid)
    P = ph.data.shape[0]
    rows = az if P * az.size <= max_entries else az[:: int(np.ceil(P * az.size / max_entries))]
    ncol = max(1, min(rg.size, max_entries // max(P * rows.size, 1)))
    if ncol < rg.size:
        prof, r0, dr, _ = range_profiles(ph.data[:: max(1, P // 64)], ph.freq, 2, np.ones(ph.freq.size))
        energy = np.sum(np.abs(prof) ** 2, axis=0)
        look = -ph.center_position / np.linalg.norm(ph.center_position)
        x = (rg * float(look @ plane.range) - r0) / dr
        e_col = np.interp(x, np.arange(energy.size), energy)
        cols = np.sort(np.argsort(e_col)[::-1][:ncol])
        rg = rg[cols]
    A, R = np.meshgrid(rows, rg, indexing="ij")
    return plane.points(A.ravel(), R.ravel())


def fix_ramp(phase: np.ndarray) -> np.ndarray:
    """Fix the constant and linear phase terms that sharpness leaves free (a linear phase is an
    azimuth shift of the image).

    The ramp at the peak of the weights' spectrum is removed first, then the least-squares line
    of the unwrapped remainder, as PGA does. For an error whose pulse-to-pulse steps stay below
    pi this is the error's own detrended phase. A white error leaves no trace of the scene's
    absolute azimuth position in the data: the image is then recovered up to an azimuth shift,
    as by any autofocus.

    Parameters
    ----------
    phase : float (P,)
        Per-pulse phases, rad.

    Returns
    -------
    float64 (P,)
        rad.
    """
    P = phase.size
    n = np.arange(P) - (P - 1) / 2.0
    a = np.exp(1j * np.asarray(phase, np.float64))
    nfft = 1 << int(np.ceil(np.log2(16 * P)))
    kk = int(np.argmax(np.abs(np.fft.fft(a, nfft))))
    w0 = 2 * np.pi * (kk if kk < nfft // 2 else kk - nfft) / nfft
    z = a * np.exp(-1j * w0 * n)
    z *= np.conj(z.sum()) / max(abs(z.sum()), 1e-300)
    phi = np.unwrap(np.angle(z))
    return phi - phi.mean() - n * (n @ phi) / (n @ n)


def as_dataset(ph: PhaseHistory, data: np.ndarray, attrs: dict | None = None) -> xr.Dataset:
    """A phase-history dataset (docs/data-format.md) from a :class:`PhaseHistory` and new data.

    Parameters
    ----------
    ph : PhaseHistory
    data : complex (P, M)
        The new phase history.
    attrs : dict
        Extra attributes.

    Returns
    -------
    xarray.Dataset
    """
    a = dict(ph.attrs)
    a.update(attrs or {})
    a["salkit_kind"] = "phase_history"
    a["rvp_removed"] = 1
    a["track"] = ph.track
    a["center_position"] = ph.center_position
    a["mode"] = ph.mode
    a["real_aperture"] = ph.real_aperture
    return xr.Dataset(
        {"signal": (("slow_time", "frequency"), data.astype(np.complex64)),
         "position": (("slow_time", "xyz"), ph.positions),
         "reference_range": (("slow_time",), ph.reference_range)},
        coords={"frequency": ("frequency", ph.freq, {"units": "Hz"}), "xyz": ("xyz", ["x", "y", "z"])},
        attrs=a)


def pulse_autofocus(raw: xr.Dataset, grid: Grid | None = None, *, chirp_correction: str = "none",
                    phase_noise_correction: str = "none", plane: str | None = None, max_sweeps: int = 10, tol: float = 1e-3,
                    max_entries: int = MAX_ENTRIES, upsample: int = BP_UPSAMPLE,
                    support: str = "scene") -> tuple[xr.Dataset, PulseAutofocusResult]:
    """Estimate one phase per pulse by backprojection sharpness and correct the phase history.

    Parameters
    ----------
    raw : xarray.Dataset
        Raw or phase-history dataset.
    grid : Grid, optional
        Pixels the sharpness is measured on (default: :func:`salkit.focus.default_grid`). Pick the
        region holding the bright scene content; its azimuth extent needs no relation to the
        number of pulses.
    chirp_correction : {"none", "resample", "deskew"}
        Range-compression option, as in :func:`salkit.focus.focus`.
    phase_noise_correction : {"none", "reference"}
        Range-compression option, as ``processing.phase_noise_correction``.
    plane : {"slant", "ground"}, optional
        Overrides the grid's plane.
    max_sweeps : int
        Coordinate-ascent sweeps at most.
    tol : float
        Convergence: RMS phase change of a sweep, rad.
    max_entries : int
        Memory bound on pulses x pixels (complex64, 8 bytes each).
    upsample : int
        Range-profile upsampling of the contributions.
    support : {"scene", "grid"}
        Pixels the sharpness is measured on: the grid widened to the scene the data hold
        (:func:`support_grid`), or the grid alone.

    Returns
    -------
    (xarray.Dataset, PulseAutofocusResult)
        The corrected phase history (``salkit_kind = "phase_history"``, variable
        ``autofocus_phase`` in rad, attributes ``autofocus = "pulse"``) and the result.

    Raises
    ------
    ScenarioError
        A grid with plane other than slant or ground.
    """
    ph = phase_history(raw, chirp_correction, phase_noise_correction)
    g = grid if grid is not None else default_grid(ph, plane=plane or "slant")
    if plane is not None:
        check_choice("plane", plane, PLANES)
        g = g.model_copy(update={"plane": plane})
    if support not in ("scene", "grid"):
        raise ScenarioError("support", support, "must be scene or grid")
    t0 = time.perf_counter()
    if support == "scene":
        g = support_grid(ph, g)
    pts = select_pixels(ph, g, max_entries)
    B = pulse_contributions(ph.data, ph.freq, ph.positions, ph.reference_range, pts, upsample=upsample)
    res = pulse_sharpness(B, max_sweeps=max_sweeps, tol=tol)
    res.phase = fix_ramp(res.phase)
    del B
    data = ph.data * np.exp(1j * res.phase)[:, None]
    ds = as_dataset(ph, data, {"autofocus": "pulse", "autofocus_pixels": int(pts.shape[0]),
                               "autofocus_support": f"{g.nx}x{g.ny}",
                               "autofocus_sweeps": len(res.history) - 1,
                               "autofocus_s": time.perf_counter() - t0})
    if "slow_time" in raw.coords and raw.sizes.get("slow_time") == data.shape[0]:
        ds = ds.assign_coords(slow_time=("slow_time", np.asarray(raw["slow_time"].values, np.float64)))
    ds["autofocus_phase"] = (("slow_time",), res.phase, {"units": "rad",
                                                         "long_name": "per-pulse phase correction applied"})
    return ds, res


__all__ = ["MAX_ENTRIES", "SUPPORT_FACTOR", "as_dataset", "fix_ramp", "pulse_autofocus", "select_pixels",
           "support_grid"]


def pulse_metrics(res: PulseAutofocusResult, prefix: str = "autofocus") -> dict:
    """Flat numbers for metrics.json from a per-pulse autofocus: sweeps, sharpness per sweep,
    pixels used, RMS of the applied correction (rad).

    Parameters
    ----------
    res : PulseAutofocusResult
    prefix : str
        Key prefix.

    Returns
    -------
    dict
    """
    out = {f"{prefix}_iterations": len(res.history) - 1, f"{prefix}_converged": int(res.converged),
           f"{prefix}_pixels": res.n_pixels, f"{prefix}_phase_rms": float(np.sqrt(np.mean(res.phase ** 2)))}
    for h in res.history:
        out[f"{prefix}_sharpness_{h['iteration']}"] = h["sharpness"]
    return out


def pulse_correct(raw: xr.Dataset, grid: Grid, chirp_correction: str = "none",
                  phase_noise_correction: str = "none") -> tuple[xr.Dataset, dict]:
    """Per-pulse autofocus of ``raw`` on ``grid``: the corrected phase history and its metrics
    (:func:`pulse_metrics` and ``autofocus_s``, the seconds it took).

    Parameters
    ----------
    raw : xarray.Dataset
        Raw data or a phase history.
    grid : Grid
        The output grid (m); the sharpness is measured over the scene around it (:func:`support_grid`).
    chirp_correction : str
        As ``processing.chirp_correction``.
    phase_noise_correction : str
        As ``processing.phase_noise_correction``.

    Returns
    -------
    (xarray.Dataset, dict)
    """
    corrected, res = pulse_autofocus(raw, grid, chirp_correction=chirp_correction,
                                     phase_noise_correction=phase_noise_correction)
    m = pulse_metrics(res)
    m["autofocus_s"] = float(corrected.attrs.get("autofocus_s", 0.0))
    return corrected, m


def pulse_focus(raw: xr.Dataset, form: Callable[..., xr.Dataset], chirp_correction: str = "none",
                progress: Optional[Callable[[int, int], None]] = None,
                phase_noise_correction: str = "none") -> tuple[xr.Dataset, xr.Dataset, dict]:
    """Focus with per-pulse autofocus: form the image, estimate one phase per pulse on its grid
    (:func:`pulse_correct`), form the image of the corrected data.

    Parameters
    ----------
    raw : xarray.Dataset
        Raw data or a phase history.
    form : callable
        ``form(raw, progress=None) -> image dataset``: the image former with its settings, e.g.
        ``functools.partial(salkit.focus.focus, processing=p)``.
    chirp_correction : str
        As ``processing.chirp_correction``.
    progress : callable, optional
        ``progress(done, total)`` of the final image's formation.
    phase_noise_correction : str
        As ``processing.phase_noise_correction``.

    Returns
    -------
    (xarray.Dataset, xarray.Dataset, dict)
        The corrected image (with ``autofocus_phase`` (pulse), rad: the correction applied), the
        image before correction, and the autofocus metrics.
    """
    before = form(raw)
    corrected, metrics = pulse_correct(raw, grid_of(before), chirp_correction, phase_noise_correction)
    image = form(corrected, progress=progress)
    # the correction applied, kept with the image: a white error fixes the image only up to an azimuth
    # shift (the linear term), which a user registers with it against a reference (docs/performance.md)
    image["autofocus_phase"] = (("pulse",), np.asarray(corrected["autofocus_phase"].values, np.float64),
                                {"units": "rad", "long_name": "per-pulse phase correction applied to the data"})
    return image, before, metrics
