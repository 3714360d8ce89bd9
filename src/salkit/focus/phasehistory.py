"""The phase history as the image formers consume it: range-compressed arrays and geometry."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..constants import SPEED_OF_LIGHT
from ..errors import DataFileError
from ..geometry.collection import plane_from, plane_resolution, processed_angle, support_resolution
from ..io.ingest import normalise_phase_history
from ..params.models import Grid
from .rangecomp import range_compress


@dataclass(frozen=True)
class PhaseHistory:
    """Arrays of a range-compressed collection.

    Attributes
    ----------
    data : complex64 (P, M)
        Phase history, pulses x frequencies.
    freq : float64 (M,)
        Frequencies, Hz, increasing and uniform.
    positions : float64 (P, 3)
        Antenna phase centres relative to the scene centre, m.
    reference_range : float64 (P,)
        Range of the dechirp reference per pulse, m.
    track : float64 (3,)
        Unit along-track vector.
    center_position : float64 (3,)
        Aperture centre relative to the scene centre, m.
    mode : {"spotlight", "stripmap"}
    real_aperture : float
        Telescope diameter, m (0 when unknown).
    attrs : dict
        The dataset's attributes.
    """

    data: np.ndarray
    freq: np.ndarray
    positions: np.ndarray
    reference_range: np.ndarray
    track: np.ndarray
    center_position: np.ndarray
    mode: str
    real_aperture: float
    attrs: dict

    @property
    def wavelength(self) -> float:
        """Wavelength at the reference frequency (sample M//2), m."""
        return SPEED_OF_LIGHT / float(self.freq[self.freq.size // 2])

    @property
    def bandwidth(self) -> float:
        """M times the frequency step, Hz."""
        return self.freq.size * float(self.freq[1] - self.freq[0])

    @property
    def beam_limited(self) -> bool:
        """Stripmap with a telescope: each pixel sees only the pulses of its beam (spotlight, or a
        stripmap without an aperture, lets every pulse see every pixel)."""
        return self.mode == "stripmap" and self.real_aperture > 0


def phase_history(raw: xr.Dataset, chirp_correction: str = "none",
                  phase_noise_correction: str = "none") -> PhaseHistory:
    """Range-compress ``raw`` (with an optional nonlinear-chirp correction) and extract arrays.

    Parameters
    ----------
    raw : xarray.Dataset
        salkit raw (dechirped) or phase-history dataset; outside phase histories are normalised
        first (:func:`salkit.io.normalise_phase_history`).
    chirp_correction : {"none", "resample", "deskew"}
    phase_noise_correction : {"none", "reference"}
        As :func:`salkit.focus.range_compress`.

    Returns
    -------
    PhaseHistory

    Raises
    ------
    DataFileError
        When the arrays' shapes disagree or there are fewer than 2 pulses or samples.
    """
    ds = range_compress(raw, chirp_correction, phase_noise_correction)
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
    if np.diff(freq)[0] < 0:
        freq, data = freq[::-1].copy(), data[:, ::-1].copy()
    track = np.asarray(ds.attrs.get("track", pos[-1] - pos[0]), dtype=np.float64)
    track = track / np.linalg.norm(track)
    cpos = np.asarray(ds.attrs.get("center_position", pos[P // 2]), dtype=np.float64)
    return PhaseHistory(data, freq, pos, ref, track, cpos, str(ds.attrs.get("mode", "spotlight")),
                        float(ds.attrs.get("real_aperture", 0.0)), dict(ds.attrs))


def theory_resolution(ph: PhaseHistory, plane) -> dict:
    """Unweighted resolutions that the data support in an image plane: spotlight from the extent
    of the K-space support (:func:`salkit.geometry.collection.support_resolution`), stripmap from the
    beam (:func:`salkit.geometry.plane_resolution`); the same theory as
    :func:`salkit.geometry.resolution_theory` for a scenario.

    Parameters
    ----------
    ph : PhaseHistory
    plane : ImagePlane

    Returns
    -------
    dict
        ``range``, ``azimuth`` (m), ``bandwidth`` (Hz), ``angle`` (rad).
    """
    ang = processed_angle(ph.positions, ph.wavelength, ph.mode, ph.real_aperture)
    if ph.beam_limited:
        look = -ph.center_position / np.linalg.norm(ph.center_position)
        rho_r, rho_a, _ = plane_resolution(ph.bandwidth, ph.wavelength, ang, look, plane.range)
    else:  # every pulse sees every pixel: the K-space support's extent
        rho_r, rho_a = support_resolution(ph.positions, ph.bandwidth, ph.wavelength, ph.center_position,
                                          plane.azimuth, plane.range)
    return {"range": rho_r, "azimuth": rho_a, "bandwidth": ph.bandwidth, "angle": ang}


def default_grid(ph: PhaseHistory, n: int = 256, plane: str = "slant") -> Grid:
    """A grid of n x n pixels at 0.8 of the resolution, for data without a scenario.

    Parameters
    ----------
    ph : PhaseHistory
    n : int
        Pixels on a side.
    plane : {"slant", "ground"}

    Returns
    -------
    Grid
    """
    res = theory_resolution(ph, plane_from(ph.track, ph.center_position, plane))
    return Grid(nx=n, ny=n, dx=0.8 * res["azimuth"], dy=0.8 * res["range"], plane=plane)
