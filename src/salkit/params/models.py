"""Typed, frozen, validated parameter objects.

Every object is immutable and validated on construction; derived quantities are
properties. Units are SI (metres, seconds, hertz, radians) unless a field name says
otherwise (``*_deg`` in degrees).
"""
from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Annotated, Literal, Optional, Union

import numpy as np
from pydantic import Discriminator, Field, Tag, field_validator, model_validator

from ..choices import (ACCURACY, ATMOSPHERE_MODELS, AUTOFOCUS_METHODS, CHIRP_CORRECTIONS, PGA_KERNELS,
                       PHASE_NOISE_CORRECTIONS,
                       PLANES, STACK_MODES, WINDOWS)
from ..constants import SPEED_OF_LIGHT
from ..registry import FORMERS, MATERIALS, OBJECT_KINDS, PATTERNS, SHAPES, SURFACES
from .base import FieldProblem, PhaseError, _Frozen
from .downlooking import DownlookingExperiment


# --------------------------------------------------------------------------- waveform
class ChirpPhaseError(_Frozen):
    """An arbitrary phase error e(t) of the transmitted chirp (rad): a seeded random band-limited
    process, or a measured one from a file (.npy of shape (2, M): t in s and e in rad)."""

    kind: Literal["random", "file"] = "random"
    rms: float = Field(default=10.0, gt=0, description="random: RMS of e(t), rad")
    bandwidth: float = Field(default=1e6, gt=0, description="random: bandwidth of e(t), Hz")
    seed: int = Field(default=0, ge=0)
    file: Optional[str] = None

    @model_validator(mode="after")
    def _file(self) -> "ChirpPhaseError":
        if self.kind == "file" and not self.file:
            raise ValueError("kind=file needs a file")
        return self

    def table(self, pulse_width: float, n: int = 8192):
        """(t, e) samples of the error over the pulse plus margins, s and rad."""
        if self.kind == "file":
            p = Path(self.file)
            if not p.is_file():
                raise ValueError(f"chirp phase-error file {self.file} does not exist")
            data = np.load(p)
            if data.ndim != 2 or data.shape[0] != 2 or not np.all(np.isfinite(data)):
                raise ValueError(f"{self.file}: must hold finite (2, M) samples: t (s) and e (rad)")
            return data[0].astype(float), data[1].astype(float)
        t = np.linspace(-0.6 * pulse_width, 0.6 * pulse_width, n)
        rng = np.random.default_rng(self.seed)
        white = rng.standard_normal(4 * n)
        f = np.fft.fftfreq(4 * n, t[1] - t[0])
        e = np.real(np.fft.ifft(np.fft.fft(white) * (np.abs(f) <= self.bandwidth)))[:n]
        e -= np.polyval(np.polyfit(t, e, 1), t)  # constant and linear parts are not phase errors
        return t, self.rms * e / e.std()


class Waveform(_Frozen):
    """Linear-FM (chirp) laser waveform, optionally with a polynomial frequency error.

    The instantaneous optical frequency over a pulse, ``t`` in ``[-pulse_width/2, pulse_width/2]``, is
    ``f(t) = c/wavelength + chirp_rate*t + sum_n nonlinearity[n-2] * t**n`` (n = 2, 3, ...).
    """

    wavelength: float = Field(gt=0, lt=1.0, description="centre wavelength, m")
    bandwidth: float = Field(gt=0, description="swept bandwidth, Hz")
    pulse_width: float = Field(gt=0, lt=1.0, description="pulse (chirp) duration, s")
    prf: float = Field(gt=0, le=1e9, description="pulse repetition frequency, Hz")
    chirp_rate: Optional[float] = Field(default=None, description="Hz/s; defaults to bandwidth/pulse_width")
    nonlinearity: tuple[float, ...] = Field(
        default=(), description="coefficients of t**2, t**3, ... in the frequency sweep, Hz/s**n")
    phase_error: Optional[ChirpPhaseError] = Field(default=None, description="arbitrary chirp phase error")
    linewidth: float = Field(default=0.0, ge=0, lt=1e12, description=(
        "laser linewidth, Hz (FWHM of a Lorentzian line): Wiener phase noise, a phase error of variance "
        "2 pi linewidth |tau - tau_LO| in each echo (salkit.simulate.linewidth); 0: a perfectly coherent laser"))

    @model_validator(mode="after")
    def _consistent(self) -> "Waveform":
        if self.bandwidth >= self.carrier_frequency:
            raise FieldProblem("bandwidth", self.bandwidth, f"must be below the carrier frequency "
                                                            f"{self.carrier_frequency:g} Hz")
        if self.chirp_rate is not None:
            expected = self.bandwidth / self.pulse_width
            if not math.isfinite(self.chirp_rate) or abs(self.chirp_rate - expected) > 1e-6 * expected:
                raise FieldProblem("chirp_rate", self.chirp_rate, f"must equal bandwidth/pulse_width = {expected:g} Hz/s")
        if self.prf * self.pulse_width > 1.0:
            raise FieldProblem("prf", self.prf, f"duty cycle prf*pulse_width = {self.prf * self.pulse_width:g} must be <= 1")
        return self

    @property
    def carrier_frequency(self) -> float:
        """Centre optical frequency c/wavelength, Hz."""
        return SPEED_OF_LIGHT / self.wavelength

    @property
    def rate(self) -> float:
        """Linear chirp rate, Hz/s."""
        return self.bandwidth / self.pulse_width

    @property
    def range_resolution(self) -> float:
        """Slant-range resolution c/(2B), m."""
        return SPEED_OF_LIGHT / (2.0 * self.bandwidth)

    @property
    def is_linear(self) -> bool:
        """True when the chirp has no nonlinearity (polynomial or arbitrary)."""
        return not any(self.nonlinearity) and self.phase_error is None


# --------------------------------------------------------------------------- platform
class RelativeOrbit(_Frozen):
    """Two circular coplanar orbits (the SAL inside the target's) and the target's attitude: the
    true relative motion of a space-borne collection (:func:`salkit.geometry.orbit.relative_positions`)."""

    r1: float = Field(gt=0, description="SAL orbit radius, m")
    r2: float = Field(gt=0, description="target orbit radius, m")
    attitude: Literal["inertial", "earth_pointing"] = Field(default="inertial", description=(
        "the frame the target's scatterers are fixed in"))

    @model_validator(mode="after")
    def _radii(self) -> "RelativeOrbit":
        if not self.r1 < self.r2:
            raise FieldProblem("r1", self.r1, f"must be below r2 = {self.r2} m")
        return self


class Platform(_Frozen):
    """Straight-line platform (or explicit per-pulse positions) with its beam pointing.

    Geometry: the scene centre ``scene.center`` is the origin of the ground frame (x, y, z = up).
    A straight track with ``heading_deg`` = 0 runs along +x at height ``altitude`` and a horizontal
    ``standoff`` from the scene centre; the scene lies to the ``side`` of the track.
    """

    mode: Literal["spotlight", "stripmap"] = "spotlight"
    speed: float = Field(gt=0, le=3e5, description="platform speed, m/s (at most 1e-3 c)")
    altitude: float = Field(ge=0, le=1e9, description="height above the scene plane, m")
    standoff: float = Field(ge=0, le=1e9, description="horizontal distance from track to scene centre, m")
    heading_deg: float = Field(default=0.0, ge=-360, le=360, description="track direction, deg from +x")
    side: Literal["left", "right"] = "left"
    squint_deg: float = Field(default=0.0, gt=-60, lt=60, description="squint of aperture centre, deg")
    aperture_length: Optional[float] = Field(default=None, gt=0, le=1e9, description=(
        "synthetic aperture length, m (spotlight); stripmap: collection length, default scene + footprint"))
    real_aperture: float = Field(gt=0, le=1e3, description="diameter of the (circular) telescope aperture, m")
    positions: Optional[tuple[tuple[float, float, float], ...]] = Field(
        default=None, description="explicit antenna position per pulse, m (overrides the straight line)")
    intra_pulse_motion: bool = Field(default=False, description="model motion during each pulse")
    trajectory: Literal["straight", "keplerian"] = Field(default="straight", description=(
        "straight: the line at speed; keplerian: each pulse moved onto the true relative orbit "
        "(``orbit``, set by the space-borne experiment from its radii)"))
    orbit: Optional[RelativeOrbit] = Field(default=None, description="the relative orbit of a keplerian trajectory")
    phase_error: Optional[PhaseError] = Field(default=None, description="known per-pulse phase error")

    @model_validator(mode="after")
    def _geometry(self) -> "Platform":
        if math.hypot(self.altitude, self.standoff) <= 0:
            raise ValueError("altitude and standoff cannot both be 0 (zero range to scene centre)")
        if self.positions is not None and len(self.positions) < 2:
            raise ValueError(f"positions has {len(self.positions)} pulses; at least 2 are needed")
        if self.trajectory == "keplerian" and self.positions is not None:
            raise FieldProblem("positions", f"<{len(self.positions)} positions>",
                               "trajectory keplerian moves the straight line onto the orbit: give no positions")
        return self

    @property
    def slant_range(self) -> float:
        """Range from the track to the scene centre at closest approach, m."""
        return math.hypot(self.altitude, self.standoff)


# --------------------------------------------------------------------------- scene
class PointTarget(_Frozen):
    """Point scatterer at ground coordinates (x along track, y across, z up), m."""

    x: float = Field(default=0.0, ge=-1e6, le=1e6, description="m")
    y: float = Field(default=0.0, ge=-1e6, le=1e6, description="m")
    z: float = Field(default=0.0, ge=-1e6, le=1e6, description="m")
    amplitude: float = Field(default=1.0, ge=0, le=1e12, description="reflectivity magnitude (1 = unit cell)")
    phase: float = Field(default=0.0, description="reflectivity phase, rad")


class ExtendedScene(_Frozen):
    """Distributed scene sampled by scatterers on a regular ground grid."""

    kind: str = Field(default="pattern", description="a declared scene object kind (salkit.registry.OBJECT_KINDS): "
                      "pattern, image, ...")
    pattern: str = Field(default="letter_I", description="a declared pattern (salkit.registry.PATTERNS) for kind=pattern")
    file: Optional[str] = Field(default=None, description="image file (PNG/NPY) for kind=image")
    material: Optional[str] = Field(default=None, description=(
        "a declared material (salkit.registry.MATERIALS): diffuse (speckle) or smooth; default from speckle"))
    extent: tuple[float, float] = Field(description="size along x (azimuth) and y (ground range), m (each <= 1e5)")
    spacing: float = Field(gt=0, description="scatterer spacing, m (below the resolution cell)")
    speckle: bool = True
    height: float = Field(default=0.0, ge=-1e6, le=1e6, description="height of the scene plane, m")
    amplitude: float = Field(default=1.0, gt=0, description="reflectivity of a bright cell")

    @field_validator("extent")
    @classmethod
    def _positive(cls, v):
        if not (0 < v[0] <= 1e5 and 0 < v[1] <= 1e5):
            raise ValueError(f"extent {v} must be positive and at most 1e5 m in both axes")
        return v

    @model_validator(mode="before")
    @classmethod
    def _speckle_of_material(cls, data):
        # a material alone says whether the scene is speckled (speckle is derived, not a default)
        if isinstance(data, dict) and data.get("material") in MATERIALS and "speckle" not in data:
            data = {**data, "speckle": MATERIALS.get(data["material"]).speckle}
        return data

    @field_validator("kind")
    @classmethod
    def _declared_kind(cls, v: str) -> str:
        return OBJECT_KINDS.require(v)

    @field_validator("pattern")
    @classmethod
    def _declared_pattern(cls, v: str) -> str:
        return PATTERNS.require(v)

    @field_validator("material")
    @classmethod
    def _declared_material(cls, v: Optional[str]) -> Optional[str]:
        return v if v is None else MATERIALS.require(v)

    @model_validator(mode="after")
    def _file(self) -> "ExtendedScene":
        for need in OBJECT_KINDS.get(self.kind).needs:  # what the kind declares it reads
            if not getattr(self, need, None):
                raise ValueError(f"kind={self.kind} needs a {need}")
        if self.material is not None and MATERIALS.get(self.material).speckle != self.speckle:
            raise FieldProblem("material", self.material, f"is {'' if MATERIALS.get(self.material).speckle else 'not '}"
                               f"speckled, but speckle = {self.speckle}: give one of the two")
        n = (self.extent[0] / self.spacing) * (self.extent[1] / self.spacing)
        if n > 5e7:
            raise ValueError(f"extent/spacing gives {n:.3g} scatterers (> 5e7); increase spacing")
        return self


class SurfaceMaterial(_Frozen):
    """How a 3-D object's surface scatters back (a declared surface kind, :data:`salkit.registry.SURFACES`)."""

    kind: str = Field(default="lambertian", description="lambertian | specular | retroreflector (declared)")
    reflectance: float = Field(default=0.3, gt=0, le=1, description="reflectance (Lambertian albedo, or the "
                                                                     "specular Fresnel power reflectance)")
    roughness: float = Field(default=0.1, ge=0, le=1, description="rms surface slope of a specular surface "
                                                                   "(its lobe about the mirror direction)")
    speckle: bool = Field(default=True, description="rough (circular Gaussian speckle) or smooth (coherent glint)")

    @field_validator("kind")
    @classmethod
    def _declared_surface(cls, v: str) -> str:
        return SURFACES.require(v)


class SceneObject(_Frozen):
    """A 3-D object: a built-in shape or a mesh file, placed, turned and scaled, with a material
    (per named part if it has parts)."""

    name: str = ""
    shape: Optional[str] = Field(default=None, description="a declared shape: box | plate | sphere | cylinder | "
                                                           "satellite | vehicle")
    mesh: Optional[str] = Field(default=None, description="a mesh file (OBJ, STL, PLY, glTF/GLB) read with trimesh")
    size: tuple[float, ...] = Field(default=(1.0, 1.0, 1.0), description=(
        "m: box [x, y, z]; plate [x, y]; sphere [diameter]; cylinder [diameter, height]; the models their "
        "overall [x, y, z]"))
    position: tuple[float, float, float] = Field(default=(0.0, 0.0, 0.0), description="centre, m (scene frame)")
    attitude_deg: tuple[float, float, float] = Field(default=(0.0, 0.0, 0.0), description=(
        "yaw, pitch, roll, deg (at slow time 0, the aperture's centre)"))
    attitude_rate_deg_s: tuple[float, float, float] = Field(default=(0.0, 0.0, 0.0), description=(
        "angular velocity about the scene's x, y, z axes through the object's centre, deg/s: a spinning or "
        "tumbling object (a space object), turned by it at each pulse"))
    scale: float = Field(default=1.0, gt=0, le=1e4)
    material: SurfaceMaterial = Field(default_factory=SurfaceMaterial)  # made when used (its kind is declared)
    parts: dict[str, SurfaceMaterial] = Field(default_factory=dict, description="material by part name")

    @field_validator("shape")
    @classmethod
    def _declared_shape(cls, v):
        return v if v is None else SHAPES.require(v)

    @model_validator(mode="after")
    def _one_source(self) -> "SceneObject":
        if (self.shape is None) == (self.mesh is None):
            raise FieldProblem("shape", self.shape, "give exactly one of shape and mesh")
        if self.mesh is not None and not Path(self.mesh).is_file():
            raise FieldProblem("mesh", self.mesh, "file does not exist")
        if any(not (0 < v <= 1e4) for v in self.size):
            raise FieldProblem("size", list(self.size), "each must be in (0, 1e4] m")
        if math.hypot(*self.attitude_rate_deg_s) > 3600.0:
            raise FieldProblem("attitude_rate_deg_s", list(self.attitude_rate_deg_s),
                               "the rate must be at most 3600 deg/s")
        return self

    @property
    def spinning(self) -> bool:
        """Whether the object turns during the collection."""
        return any(v != 0.0 for v in self.attitude_rate_deg_s)


class Scene(_Frozen):
    """Point targets, an extended scene and/or 3-D objects."""

    points: tuple[PointTarget, ...] = ()
    extended: Optional[ExtendedScene] = None
    objects: tuple[SceneObject, ...] = ()
    origin: Optional[tuple[float, float, float]] = Field(default=None, description=(
        "where the scene frame's origin (x east, y north, z up) lies on the earth: WGS84 latitude (deg), "
        "longitude (deg), height above the ellipsoid (m); images then carry the geodetic positions of "
        "their pixels, and SICD, CPHD and GeoTIFF exports place them there"))

    @field_validator("origin")
    @classmethod
    def _origin(cls, v):
        if v is not None and (abs(v[0]) > 90 or not -180 <= v[1] <= 360):
            raise ValueError(f"{list(v)} must be [latitude deg, longitude deg, height m] with |latitude| <= 90 "
                             "and longitude in [-180, 360]")
        return v

    @model_validator(mode="after")
    def _nonempty(self) -> "Scene":
        if not self.points and self.extended is None and not self.objects:
            raise ValueError("the scene needs at least one point target, an extended scene or an object")
        return self


# --------------------------------------------------------------------------- receiver
class Noise(_Frozen):
    """Photon-limited heterodyne detection (seed 001, eqs 6-8 and 13-15).

    ``signal_photons`` is N_s: the mean number of signal photons collected over the synthetic
    aperture from one resolution cell of unit reflectance. The image carrier-to-noise ratio of
    such a cell is eta_d*eta_mix*N_s and the speckled-image SNR is eta*N_s/(1 + eta*N_s).
    """

    enabled: bool = False
    model: Literal["gaussian", "poisson"] = "gaussian"
    lo_photons: float = Field(default=1e6, gt=0, description="LO photons per pulse window, N_L")
    signal_photons: float = Field(default=100.0, gt=0, description="N_s per unit cell over the aperture")
    quantum_efficiency: float = Field(default=1.0, gt=0, le=1, description="eta_d")
    mixing_efficiency: float = Field(default=1.0, gt=0, le=1, description="eta_mix")

    @property
    def efficiency(self) -> float:
        """eta = eta_d * eta_mix."""
        return self.quantum_efficiency * self.mixing_efficiency

    @property
    def cnr(self) -> float:
        """Image carrier-to-noise ratio of a unit-reflectance cell, eta*N_s."""
        return self.efficiency * self.signal_photons

    @property
    def snr_theory(self) -> float:
        """Single-look speckled image SNR eta*N_s/(1 + eta*N_s) (seed 001 eq 14)."""
        return self.cnr / (1.0 + self.cnr)


class ReferenceChannel(_Frozen):
    """A reference (delay-line) channel beside the target channel, seed 002: the beat of the
    reference path d_r against the reference-LO path d_rlo measures the chirp."""

    d_r: float = Field(ge=0, description="reference path length, m")
    d_rlo: float = Field(ge=0, description="reference-LO path length, m")
    snr_db: float = Field(default=60.0, description="reference beat SNR per sample, dB")

    @model_validator(mode="after")
    def _length(self) -> "ReferenceChannel":
        if self.d_r == self.d_rlo:
            raise ValueError(f"d_r = d_rlo = {self.d_r} m is a zero-length reference: it cannot measure the chirp")
        return self

    @property
    def delay(self) -> float:
        """Differential delay (d_r - d_rlo)/c, s."""
        return (self.d_r - self.d_rlo) / SPEED_OF_LIGHT


class Receiver(_Frozen):
    """Dechirp (stretch) receiver."""

    adc_rate: float = Field(gt=0, description="complex (I/Q) or real sample rate, Hz")
    reference_range: Optional[float] = Field(default=None, gt=0, description=(
        "dechirp reference range, m; default: scene centre range per pulse (spotlight), "
        "constant closest-approach range (stripmap)"))
    iq: bool = True
    gate: Optional[float] = Field(default=None, gt=0, description=(
        "ADC window, s; default pulse_width minus the scene's delay spread"))
    noise: Noise = Noise()
    reference_channel: Optional[ReferenceChannel] = None
    lo_delay: Optional[float] = Field(default=None, ge=0, lt=10.0, description=(
        "delay of the local oscillator's path, s, for the laser's phase noise (waveform.linewidth): "
        "default matched to the dechirp reference range (a delay-line LO); 0: an undelayed LO"))


# --------------------------------------------------------------------------- processing
class Grid(_Frozen):
    """Image grid on a plane through the scene centre: azimuth (along track) x range."""

    nx: int = Field(gt=1, le=32768, description="number of azimuth samples")
    ny: int = Field(gt=1, le=32768, description="number of range samples")
    dx: float = Field(gt=0, description="azimuth spacing, m")
    dy: float = Field(gt=0, description="range spacing, m")
    plane: Literal[PLANES] = "slant"
    center: tuple[float, float] = (0.0, 0.0)
    auto: tuple[Literal["dx", "dy"], ...] = Field(default=(), description=(
        "spacings that follow the resolution (written dx: auto / dy: auto): AUTO_GRID_FRACTION of the "
        "nominal slant-plane resolution, recomputed whenever the scenario changes (a sweep's points)"))

    @property
    def extent(self) -> tuple[float, float]:
        """Grid size (azimuth, range), m."""
        return self.nx * self.dx, self.ny * self.dy


class Processing(_Frozen):
    """Image formation settings."""

    algorithm: str = Field(default="bp", description=(
        "the image former: a declared one (salkit.registry.FORMERS; `salkit focus --help` lists them)"))
    window: Literal[WINDOWS] = "none"
    taylor_nbar: int = Field(default=4, ge=1)
    taylor_sll: float = Field(default=35.0, gt=13.3, description="Taylor sidelobe level, dB")
    grid: Grid
    autofocus: Literal[AUTOFOCUS_METHODS] = Field(
        default="none", description="pga / min-entropy on the image; pulse: one phase per pulse on the phase history")
    autofocus_kernel: Literal[PGA_KERNELS] = "lumv"
    autofocus_max_iter: int = Field(default=30, ge=1, le=500)
    accuracy: Literal[ACCURACY] = Field(
        default="standard", description=("image-formation accuracy against the exact matched filter: standard or high "
                                          "(for interferometry); what each former promises at each level is in its "
                                          "declaration (the README's table of formers)"))
    range_upsample: Optional[int] = Field(default=None, ge=2, le=64, description=(
        "backprojection's range-profile upsampling; default the former's own: bp 6 (its four taps fitted to the "
        "band, -87 to -89 dB against the exact matched filter; 8 at accuracy high, -97 to -99 dB), bp_cubic and "
        "bp_fitted 16 (32 at accuracy high)"))
    chirp_correction: Literal[CHIRP_CORRECTIONS] = Field(
        default="none", description="nonlinear-chirp correction from the reference channel")
    phase_noise_correction: Literal[PHASE_NOISE_CORRECTIONS] = Field(
        default="none", description=("reference: remove the laser phase noise the reference channel recorded for each "
                                     "pulse (exact for echoes whose delay difference equals the reference delay)"))

    @field_validator("algorithm")
    @classmethod
    def _declared_former(cls, v: str) -> str:
        return FORMERS.require(v)


# --------------------------------------------------------------------------- atmosphere
class Atmosphere(_Frozen):
    """Turbulence on the path: frozen phase-screen layers with constant Cn^2 (seed 004)."""

    cn2: float | tuple[float, ...] = Field(description=(
        "refractive-index structure constant, m^(-2/3): constant, or one value per layer from the "
        "scene to the platform (profile); in a scenario, a constant 0 is the turbulence-free path (the "
        "atmosphere is dropped)"))
    layers: int = Field(default=50, ge=1, le=1000)
    screen_dx: float = Field(default=0.01, gt=0, description="screen sample spacing, m")
    screen_n: Optional[int] = Field(default=None, ge=16, le=8192, description="screen size; default: fits the rays")
    outer_scale: Optional[float] = Field(default=None, gt=0, description="von Karman L0, m")
    inner_scale: Optional[float] = Field(default=None, ge=0, description="inner scale l0, m")
    seed: int = Field(default=0, ge=0)
    model: Literal[ATMOSPHERE_MODELS] = Field(default="phase_screen", description=(
        "phase_screen: two-way phase along each ray through the screens (geometric optics); "
        "wave_optics: the transmit beam propagated through the screens by split-step angular spectrum, "
        "two-way complex gain per pulse and scatterer (amplitude and phase, by reciprocity)"))

    @model_validator(mode="after")
    def _profile(self) -> "Atmosphere":
        values = self.cn2 if isinstance(self.cn2, tuple) else (self.cn2,)
        for v in values:
            if not (v > 0 and v < 1e-9):
                raise ValueError(f"cn2 value {v!r} must be in (0, 1e-9) m^(-2/3)")
        if isinstance(self.cn2, tuple) and len(self.cn2) != self.layers:
            raise ValueError(f"a cn2 profile needs one value per layer: {len(self.cn2)} values, {self.layers} layers")
        return self


class TurbulenceExperiment(_Frozen):
    """Seed 004's experiment: point and "I" targets under turbulence classes, PFA, PGA."""

    kind: Literal["turbulence_pga"] = "turbulence_pga"
    classes: dict[str, float] = Field(default_factory=lambda: {"none": 0.0, "weak": 1e-15, "medium": 1e-14,
                                                               "strong": 1e-13},
                                      description="class name -> Cn^2 (0: no turbulence), m^(-2/3)")
    i_target_extent: tuple[float, float] = (0.6, 0.6)
    i_target_spacing: float = Field(default=0.04, gt=0, description="point spacing of the I target, m")
    ensemble_screens: int = Field(default=200, ge=100, description="screens for the structure-function figure")
    ensemble_n: int = Field(default=64, ge=16, le=1024)
    pga_iterations: tuple[int, ...] = (5, 10, 20)

    @field_validator("classes")
    @classmethod
    def _cn2(cls, v):
        for name, c in v.items():
            if not (c >= 0 and c < 1e-9):
                raise ValueError(f"class {name!r}: Cn2 = {c!r} must be in [0, 1e-9)")
        return v


class ChirpExperiment(_Frozen):
    """Seed 002's experiment: points A, B, C; Table 1 at (d_r, d_rlo, R1, R2); Tables 2 and 3 sweeps."""

    kind: Literal["nonlinear_chirp"] = "nonlinear_chirp"
    points: dict[str, float] = Field(default_factory=lambda: {"A": 26.9355, "B": 19.8645, "C": 19.8645},
                                     description="point -> equivalent distance, m")
    d_r: float = Field(default=0.8, ge=0, description="reference path, m")
    d_rlo: float = Field(default=0.5, ge=0, description="reference-LO path, m")
    r1: float = Field(default=50.0, gt=2, description="quadratic term = 1/R1 of the linear sweep at the edge")
    r2: float = Field(default=50.0, gt=0, description="cubic term = 1/R2 of the quadratic at the edge")
    sweep_d_r: tuple[float, ...] = tuple(round(0.5 + 0.1 * i, 1) for i in range(15))
    sweep_d_rlo: tuple[float, ...] = tuple(round(0.5 + 0.1 * i, 1) for i in range(7))
    sweep_r1: tuple[float, ...] = (10, 20, 30, 40, 50, 60, 70, 100, 200, 300)
    sweep_r2: tuple[float, ...] = (10, 20, 30, 40, 50, 70, 100, 150, 200, 300)

    @model_validator(mode="after")
    def _ref(self) -> "ChirpExperiment":
        if self.d_r == self.d_rlo:
            raise ValueError(f"d_r = d_rlo = {self.d_r} m is a zero-length reference")
        if any(r <= 2 for r in self.sweep_r1):
            raise ValueError("sweep_r1 values must be > 2 (the sweep must stay monotonic)")
        return self


class StackSettings(_Frozen):
    """Sub-image stacking at scale (seed 001)."""

    max_subimages: Optional[int] = Field(default=None, ge=1, description="the N sub-apertures nearest closest approach")
    workers: int = Field(default=2, ge=0, le=64, description=(
        "worker processes of the local Dask cluster started for the stack; 0: the sub-images in this "
        "process, no cluster (a cluster's start, about 8 s on 2 cores, outweighs a stack of tens)"))
    mode: Literal[STACK_MODES] = Field(default="incoherent", description=(
        "incoherent: mean intensity (speckle and noise average down, resolution stays); coherent: "
        "phase-aligned complex sum (the combined aperture's finer resolution, one look)"))
    scheduler: Optional[str] = Field(default=None, description="address of an existing Dask scheduler")

    @field_validator("scheduler")
    @classmethod
    def _address(cls, v):
        if v is not None and not re.fullmatch(r"(tcp|tls|ws|wss|ucx|inproc)://[^\s/:]+(:\d{1,5})?|[^\s/:]+:\d{1,5}", v):
            raise ValueError(f"scheduler address {v!r} must look like tcp://HOST:PORT (or HOST:PORT)")
        return v

    @model_validator(mode="after")
    def _where(self) -> "StackSettings":
        if self.workers == 0 and self.scheduler is not None:
            raise ValueError(f"workers = 0 (in this process) and scheduler = {self.scheduler!r} (an existing "
                             "cluster) contradict each other: give one")
        return self


class SpaceborneExperiment(_Frozen):
    """Seed 001: a GEO target seen from a lower coplanar circular orbit near closest approach."""

    kind: Literal["spaceborne_geo"] = "spaceborne_geo"
    r1: float = Field(default=41_978e3, gt=0, description="SAL orbit radius, m")
    r2: float = Field(default=42_178e3, gt=0, description="target orbit radius, m")
    squint_max_deg: float = Field(default=5.0, gt=0, lt=90)
    resolution: float = Field(default=0.05, gt=0, description="along-track resolution at zero squint, m")
    target_attitude: Literal["inertial", "earth_pointing"] = Field(default="inertial", description=(
        "with platform.trajectory keplerian: the frame the target is fixed in (inertial, as the "
        "seed's straight line at V assumes, or turning with its orbit, facing the Earth)"))

    @model_validator(mode="after")
    def _orbits(self) -> "SpaceborneExperiment":
        if not self.r1 < self.r2:
            raise FieldProblem("r1", self.r1, f"must be below r2 = {self.r2} m (the SAL inside the target's orbit)")
        return self


# --------------------------------------------------------------------------- scenario


class _ScenarioBase(_Frozen):
    name: str = "scenario"
    description: str = ""
    seed: int = Field(default=0, ge=0)
    scene: Scene


#: ``dx: auto`` / ``dy: auto``: the pixel spacing as this fraction of the nominal resolution (two
#: pixels a resolution cell: the impulse response is sampled at better than complex Nyquist, and its
#: IRW, PSLR and ISLR are measured at every point of a sweep of the bandwidth or the aperture).
AUTO_GRID_FRACTION = 0.5


def _number(section: dict, key: str, default=None):
    v = section.get(key, default)
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def nominal_resolution(data: dict) -> dict:
    """The nominal slant-plane resolutions (m) of a scenario given as data, for ``dx: auto``:
    range c / (2 B); azimuth lambda R / (2 L) for a spotlight aperture L at the slant range R, D / 2
    for stripmap (D the telescope aperture). The exact image-plane figures
    (:func:`salkit.geometry.resolution_theory`) are the same or coarser (a ground plane, a window).

    Parameters
    ----------
    data : dict
        The scenario mapping (``waveform``, ``platform``).

    Returns
    -------
    dict
        ``range``, ``azimuth`` (m).

    Raises
    ------
    FieldProblem
        Naming ``processing.grid.dx`` or ``dy`` when the fields it needs are missing.

    Examples
    --------
    >>> r = nominal_resolution({"waveform": {"wavelength": 1.55e-6, "bandwidth": 7.5e9},
    ...                         "platform": {"mode": "spotlight", "altitude": 3000, "standoff": 4000,
    ...                                      "aperture_length": 0.19375}})
    >>> round(r["range"], 4), round(r["azimuth"], 4)
    (0.02, 0.02)
    """
    w = data.get("waveform") if isinstance(data.get("waveform"), dict) else {}
    p = data.get("platform") if isinstance(data.get("platform"), dict) else {}
    bw = _number(w, "bandwidth")
    if bw is None and _number(w, "chirp_rate") and _number(w, "pulse_width"):
        bw = _number(w, "chirp_rate") * _number(w, "pulse_width")
    if not bw or bw <= 0:
        raise FieldProblem("processing.grid.dy", "auto", "needs waveform.bandwidth (a positive number)")
    out = {"range": SPEED_OF_LIGHT / (2 * bw)}
    lam = _number(w, "wavelength")
    if p.get("mode", "spotlight") == "stripmap":
        D = _number(p, "real_aperture")
        out["azimuth"] = D / 2 if D else None
    else:
        R = math.hypot(_number(p, "altitude", 0.0) or 0.0, _number(p, "standoff", 0.0) or 0.0)
        L = _number(p, "aperture_length")
        out["azimuth"] = lam * R / (2 * L) if lam and L and R else None
    if not out["azimuth"] or out["azimuth"] <= 0:
        raise FieldProblem("processing.grid.dx", "auto", "needs waveform.wavelength and platform.aperture_length "
                           "(spotlight) or platform.real_aperture (stripmap)")
    return out


class Simulation(_Frozen):
    """How the echoes are computed: the direct sum over scatterers (the reference), or one
    non-uniform FFT a pulse (:mod:`salkit.simulate.fast`) to a stated accuracy against it."""

    method: Literal["direct", "nufft", "auto"] = Field(default="direct", description=(
        "direct: the exact sum (scatterers x pulses x samples); nufft: one non-uniform FFT a pulse (linear "
        "chirp, the ADC gate inside every echo; refused otherwise); auto: nufft where it holds and the sum "
        "is large, else direct"))
    accuracy_db: float = Field(default=-80.0, ge=-120.0, le=-40.0, description=(
        "the fast method's error energy against the direct sum, dB (-80 default; -100 for interferometry)"))


class Scenario(_ScenarioBase):
    """A synthetic aperture ladar scenario: waveform, platform, scene, receiver, processing, and
    optionally an atmosphere, one of the seed experiments (turbulence, chirp, space-borne) and
    the stacking settings.

    The down-looking SAL (seeds 000/003) has physics of its own (no optical chirp, scanning
    cylindrical lenses) and is a :class:`DownlookingScenario`; :func:`salkit.params.parse_scenario`
    picks the model from ``experiment.kind`` (:data:`AnyScenario`).
    """

    waveform: Waveform
    platform: Platform
    receiver: Receiver
    processing: Processing
    atmosphere: Optional[Atmosphere] = None
    experiment: Optional[TurbulenceExperiment | ChirpExperiment | SpaceborneExperiment] = Field(
        default=None, discriminator="kind")
    stack: StackSettings = StackSettings()
    simulation: Simulation = Simulation()

    @model_validator(mode="before")
    @classmethod
    def _auto_grid(cls, data):
        # processing.grid.dx/dy = auto: a spacing that follows the resolution (nominal_resolution)
        if not isinstance(data, dict):
            return data
        proc = data.get("processing")
        grid = proc.get("grid") if isinstance(proc, dict) else None
        if not isinstance(grid, dict):
            return data
        auto = [k for k in ("dx", "dy") if grid.get(k) == "auto" or k in (grid.get("auto") or ())]
        if not auto:
            return data
        res = nominal_resolution(data)
        grid = {**grid, "auto": tuple(auto)}
        for k in auto:
            grid[k] = AUTO_GRID_FRACTION * res["azimuth" if k == "dx" else "range"]
        return {**data, "processing": {**proc, "grid": grid}}

    @model_validator(mode="before")
    @classmethod
    def _vacuum(cls, data):
        # atmosphere.cn2 = 0 is the turbulence-free path: no atmosphere (a sweep of Cn2 may start there)
        atm = data.get("atmosphere") if isinstance(data, dict) else None
        if isinstance(atm, dict) and isinstance(atm.get("cn2"), (int, float)) and atm["cn2"] == 0:
            return {**data, "atmosphere": None}
        return data

    @model_validator(mode="after")
    def _beam(self) -> "Scenario":
        if (self.platform.trajectory == "keplerian" and self.platform.orbit is None
                and not (self.experiment is not None and self.experiment.kind == "spaceborne_geo")):
            raise FieldProblem("platform.trajectory", "keplerian",
                               "needs the orbits: a spaceborne_geo experiment (or platform.orbit)")
        lam, D = self.waveform.wavelength, self.platform.real_aperture
        if not 1.2196698912665045 * lam / D < 0.5:
            raise FieldProblem("platform.real_aperture", D, f"is too small for wavelength {lam:g} m: the beam's "
                               "first null 1.22 lambda/D must stay below 30 deg (paraxial Airy beam)")
        return self

    @property
    def kind(self) -> str:
        """``"sal"``, or the experiment's kind."""
        return self.experiment.kind if self.experiment is not None else "sal"

    @property
    def is_downlooking(self) -> bool:
        """False: see :class:`DownlookingScenario`."""
        return False


class DownlookingScenario(_ScenarioBase):
    """A self-interferometric down-looking SAL scenario (seeds 000/003): the scene and the
    ``experiment`` block (kind ``downlooking``), which holds the whole system."""

    experiment: DownlookingExperiment

    @property
    def kind(self) -> str:
        """``"downlooking"``."""
        return "downlooking"

    @property
    def is_downlooking(self) -> bool:
        """True."""
        return True


def _scenario_tag(v) -> str:
    exp = v.get("experiment") if isinstance(v, dict) else getattr(v, "experiment", None)
    kind = exp.get("kind") if isinstance(exp, dict) else getattr(exp, "kind", None)
    return "downlooking" if kind == "downlooking" else "sal"


#: Either scenario model, chosen by ``experiment.kind`` (a discriminated union).
AnyScenario = Annotated[Union[Annotated[Scenario, Tag("sal")], Annotated[DownlookingScenario, Tag("downlooking")]],
                        Discriminator(_scenario_tag)]
