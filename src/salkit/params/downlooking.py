"""Parameter objects of the self-interferometric down-looking SAL (seeds 000 and 003).

Coordinates: the beam frame has its z axis along the transmit boresight, x across track and y
along track (the flight direction). ``x_in`` and ``y_in`` are positions in the field stop at the
focal plane of the transmit telescope; the telescope projects them to angles -x_in/f_t, -y_in/f_t.
All lengths in metres, times in seconds, angles in degrees where the name says ``_deg``.
"""
from __future__ import annotations

import math
from typing import Literal, Optional

from pydantic import Field, model_validator

from .base import PhaseError, _Frozen


class DLRequirements(_Frozen):
    """The design example's requirements (seed 000, section 5)."""

    range: float = Field(gt=0, description="working range to the scene centre, m")
    spot: float = Field(gt=0, description="side of the square illuminated spot, m")
    resolution: float = Field(gt=0, description=(
        "imaging resolution, m: the first-null (Rayleigh) distance of the PSF, half the eq-22 width"))


class DLOptics(_Frozen):
    """Field stops, cylindrical lenses, transmit telescope and receiver optics."""

    wavelength: Optional[float] = Field(default=None, gt=1e-8, lt=1e-3, description=(
        "optical wavelength, m; None: derived from requirements.resolution (the paper does not state it)"))
    stop_x: float = Field(gt=0, description="field-stop width W_x across track, m")
    stop_y: float = Field(gt=0, description="field-stop width W_y along track, m")
    focal_x: float = Field(gt=0, description="focal length f_x of the scanning cross-track cylindrical lenses, m")
    focal_y: float = Field(gt=0, description="focal length f_y of the fixed along-track cylindrical lenses, m")
    focal_transmit: float = Field(gt=0, description="focal length f_t of the transmit telescope, m")
    bias_common: float = Field(description="common lens-centre offset S_b, m (sideband shift)")
    bias_opposite: float = Field(ge=0, description="opposite lens-centre offset S_a, m (forward/backward delay)")
    receive_aperture: float = Field(default=0.3, gt=0, description="receive telescope diameter, m")
    hwp_angle_deg: float = Field(default=22.5, ge=-90, le=90, description=(
        "fast axis of the receiving half-wave plate, deg (22.5: polarisation rotated by 45 deg)"))


class DLScan(_Frozen):
    """Cross-track lens scan: one forward or backward sweep per along-track sample."""

    speed: float = Field(gt=0, description="lens speed v_x, m/s")
    duration: float = Field(gt=0, description="scan time T_f, s")
    factor: Optional[float] = Field(default=None, gt=0, description=(
        "K = v_x T_f / W_x if stated; must agree with speed, duration and optics.stop_x"))
    samples: Optional[int] = Field(default=None, ge=16, le=1 << 20, description=(
        "fast-time samples per scan (ADC); default the next power of two above 1.25 x Nyquist"))


class DLTrack(_Frozen):
    """Platform track: a straight line along y; the beam looks down at ``look_angle_deg`` from nadir."""

    range: float = Field(gt=0, description="distance along the boresight to the scene centre, m")
    look_angle_deg: float = Field(default=0.0, ge=0, lt=80, description="boresight angle from nadir, deg")
    spacing: float = Field(gt=0, description="along-track distance Delta-Y between successive scans, m")
    speed: Optional[float] = Field(default=None, gt=0, description=(
        "platform speed, m/s; when given, the motion during each scan is simulated and the scan "
        "must fit in the time between samples"))
    length: Optional[float] = Field(default=None, gt=0, description=(
        "track length, m; default scene extent along track plus the footprint M W_y"))


class Terrain(_Frozen):
    """A 3-D surface: smooth height map with reflectivity and speckle, in ground coordinates."""

    extent: tuple[float, float] = Field(description="size along track and across track (ground), m")
    spacing: float = Field(gt=0, description="scatterer spacing on the ground, m")
    kind: Literal["hills", "random"] = "hills"
    peak_height: float = Field(default=0.5, ge=0, description=(
        "hills: amplitude of the tallest hill (overlapping hills add, so the surface may rise higher); "
        "random: RMS height, m"))
    correlation_length: float = Field(default=0.6, gt=0, description="width of the hills / correlation length, m")
    speckle: bool = True
    seed: int = Field(default=0, ge=0)

    @model_validator(mode="after")
    def _size(self) -> "Terrain":
        if self.extent[0] <= 0 or self.extent[1] <= 0:
            raise ValueError(f"extent {self.extent} must be positive in both axes")
        n = (self.extent[0] / self.spacing) * (self.extent[1] / self.spacing)
        if n > 2e6:
            raise ValueError(f"extent/spacing gives {n:.3g} scatterers (> 2e6); increase spacing")
        return self


class DLDisturbance(_Frozen):
    """Phase disturbances for the immunity experiment.

    Common-mode ones act identically on both polarisations (platform vibration along the line of
    sight, an atmosphere both beams share); the others do not (a turbulent layer at the transmit
    pupil, which the two beams cross at different places; a polarisation-dependent path).
    """

    vibration: Optional[PhaseError] = Field(default=None, description=(
        "round-trip line-of-sight vibration, rad, per scan (common mode)"))
    jitter_rms: float = Field(default=0.0, ge=0, le=100, description=(
        "white round-trip phase noise per fast-time sample, rad RMS (common mode)"))
    path_r0: Optional[float] = Field(default=None, gt=0, description=(
        "Fried parameter of a turbulent screen both beams share on the way to each target point, m "
        "(common mode, different for each point)"))
    transmitter_r0: Optional[float] = Field(default=None, gt=0, description=(
        "Fried parameter of a turbulent layer at the transmit pupil, m (not common mode)"))
    transmitter_screen_shift: float = Field(default=0.0, ge=0, description=(
        "how far that layer moves between scans (wind), m"))
    differential_rms: float = Field(default=0.0, ge=0, le=100, description=(
        "polarisation-dependent phase between the two beams, rad RMS, per scan (not common mode)"))
    seed: int = Field(default=11, ge=0)

    @property
    def active(self) -> bool:
        """True when any disturbance is set."""
        return bool(self.vibration or self.jitter_rms or self.path_r0 or self.transmitter_r0
                    or self.differential_rms)


class DownlookingExperiment(_Frozen):
    """Seeds 000/003: self-interferometric down-looking SAL (DL-SAL) for 3-D imaging."""

    kind: Literal["downlooking"] = "downlooking"
    requirements: Optional[DLRequirements] = None
    optics: DLOptics
    scan: DLScan
    track: DLTrack
    detection: Literal["aperture_averaged", "point_detector"] = Field(default="aperture_averaged", description=(
        "aperture_averaged: each scatterer beats only with itself (a receive aperture much wider than "
        "lambda R / resolution averages the cross-scatterer terms away); point_detector: the fields of "
        "all scatterers add at one point before detection"))
    noise_snr_db: Optional[float] = Field(default=None, ge=-60, le=200, description=(
        "receiver noise: SNR (dB) per fast-time sample of a unit point's beat against white noise"))
    order: Literal["focus_then_add", "paper"] = Field(default="focus_then_add", description=(
        "focus_then_add: each scan direction is focused along track with its own chirp, then the pairs "
        "are added (eq 19); paper: pairs added right after the cross-track FFT (eq 16), then one "
        "along-track matched filter (eq 17)"))
    oversample: int = Field(default=2, ge=1, le=8, description="zero-padding factor of the cross-track FFT")
    window: Literal["none", "hamming"] = "none"
    allow_twin_overlap: bool = Field(default=False, description=(
        "accept S_b < W_x/2 (the twin image overlaps the swath), for demonstrating it"))
    disturbance: DLDisturbance = DLDisturbance()
    terrain: Optional[Terrain] = None
    terrain_look_angle_deg: float = Field(default=45.0, ge=0, lt=80, description=(
        "look angle of the oblique 3-D observation, deg from nadir"))
    unwrap: Literal["skimage", "least_squares"] = "skimage"
    side_looking_comparison: bool = True

    @model_validator(mode="after")
    def _consistent(self) -> "DownlookingExperiment":
        o, s = self.optics, self.scan
        if o.wavelength is None and self.requirements is None:
            raise ValueError("optics.wavelength is not given and there are no requirements to derive it from")
        k = s.speed * s.duration / o.stop_x
        if s.factor is not None and abs(k - s.factor) > 1e-6 * s.factor:
            raise ValueError(
                f"scan.speed x scan.duration / optics.stop_x = {s.speed:g} x {s.duration:g} / {o.stop_x:g} "
                f"= {k:.6g}, but scan.factor K = {s.factor:g}: the scan is inconsistent with the aperture")
        if not self.allow_twin_overlap and o.bias_common < o.stop_x / 2 * (1 - 1e-9):
            m = self.track.range / o.focal_transmit
            raise ValueError(
                f"sideband condition M S_b > X_p/2 violated: M S_b = {m * o.bias_common:.4g} m < X_p/2 = "
                f"{m * o.stop_x / 2:.4g} m (S_b = {o.bias_common:g} m < W_x/2 = {o.stop_x / 2:g} m), so "
                "the twin image overlaps the swath (set allow_twin_overlap: true to simulate it anyway)")
        if self.track.speed is not None:
            dt = self.track.spacing / self.track.speed
            if dt < s.duration:
                raise ValueError(
                    f"scan.duration T_f = {s.duration:g} s is longer than the time between along-track "
                    f"samples track.spacing / track.speed = {dt:.4g} s: scans would overlap")
        if o.bias_opposite >= o.bias_common + o.stop_x:
            raise ValueError(f"bias_opposite S_a = {o.bias_opposite:g} m must be below S_b + W_x = "
                             f"{o.bias_common + o.stop_x:g} m")
        if math.isclose(self.track.range, 0.0):
            raise ValueError("track.range must be positive")
        return self
