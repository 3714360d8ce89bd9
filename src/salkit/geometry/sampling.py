"""Sampling checks made before any work: PRF, ADC rate, ADC gate and image grid."""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..constants import SPEED_OF_LIGHT
from ..errors import SamplingError, ScenarioError
from ..tolerances import GRID_SPACING_OF_RESOLUTION
from ..params.models import Scenario
from ..io.meshes import mesh_bounds
from ..registry import FORMERS
from .collection import (Collection, _unit, build_collection, rotation, first_null_sin, footprint, image_plane, plane_resolution,
                         processed_angle, scene_point_positions, support_resolution)


def scene_probe_points(scenario: Scenario) -> np.ndarray:
    """Points that bound the scene: point targets, the corners/edges of the extended scene and the
    corners of a box about each 3-D object that holds it (whatever its attitude; a spinning one's
    about its bounding sphere).

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    float64 (N, 3)
        m.
    """
    pts = [scene_point_positions(scenario)]
    ext = scenario.scene.extended
    if ext is not None:
        hx, hy = ext.extent[0] / 2, ext.extent[1] / 2
        xs, ys = np.meshgrid([-hx, 0.0, hx], [-hy, 0.0, hy])
        pts.append(np.stack([xs.ravel(), ys.ravel(), np.full(xs.size, ext.height)], axis=1))
    c = np.array(np.meshgrid([-1.0, 1.0], [-1.0, 1.0], [-1.0, 1.0])).reshape(3, -1).T
    for obj in scenario.scene.objects:
        if obj.shape is not None:  # the built-in shapes fit in their size ([x, y, z]; a margin for the models' parts)
            s = (list(obj.size) + [obj.size[-1]] * 3)[:3] if len(obj.size) > 1 else [obj.size[0]] * 3
            lo, hi = -0.55 * np.asarray(s, np.float64), 0.55 * np.asarray(s, np.float64)
        else:
            lo, hi = mesh_bounds(obj.mesh)
        box = (lo + hi) / 2 + c * (hi - lo) / 2
        if obj.spinning:  # any attitude it turns through: the cube about its bounding sphere
            box = c * float(np.max(np.linalg.norm(box, axis=1)))
        pts.append(np.asarray(obj.position, np.float64) + obj.scale * box @ rotation(obj.attitude_deg).T)
    return np.concatenate(pts, axis=0)


def _illuminated(col: Collection, pts: np.ndarray, sin_null: float) -> np.ndarray:
    """(P, N) mask of probe points inside the first null of the beam."""
    rel = pts[None, :, :] - col.positions[:, None, :]
    rel /= np.linalg.norm(rel, axis=2, keepdims=True)
    cosang = np.einsum("pnk,pk->pn", rel, col.boresight)
    return cosang >= math.sqrt(max(0.0, 1.0 - sin_null ** 2))


def delay_spread(scenario: Scenario, col: Collection | None = None) -> tuple[float, float]:
    """Min and max differential delay 2(R - R_ref)/c over the illuminated scene, s.

    Parameters
    ----------
    scenario : Scenario
    col : Collection

    Returns
    -------
    (float, float)
        s.
    """
    col = col if col is not None else build_collection(scenario)
    pts = scene_probe_points(scenario)
    sin_null = first_null_sin(scenario.waveform.wavelength, scenario.platform.real_aperture)
    mask = _illuminated(col, pts, sin_null)
    dr = np.linalg.norm(pts[None, :, :] - col.positions[:, None, :], axis=2) - col.reference_range[:, None]
    dr = np.where(mask, dr, np.nan)
    if np.all(np.isnan(dr)):
        return 0.0, 0.0
    return 2.0 * float(np.nanmin(dr)) / SPEED_OF_LIGHT, 2.0 * float(np.nanmax(dr)) / SPEED_OF_LIGHT


def adc_gate(scenario: Scenario, col: Collection | None = None) -> float:
    """ADC window, s: the receiver's, or the pulse width less the scene's delay spread.

    Parameters
    ----------
    scenario : Scenario
    col : Collection

    Returns
    -------
    float
        s.
    """
    g = scenario.receiver.gate
    if g is not None:
        return g
    d0, d1 = delay_spread(scenario, col)
    return scenario.waveform.pulse_width - 2.0 * max(abs(d0), abs(d1))


def n_fast_samples(scenario: Scenario, col: Collection | None = None) -> int:
    """Number of fast-time samples per pulse, all strictly inside the ADC gate.

    Samples sit at (i - N//2)/adc_rate, so N is the largest count with N//2 samples before the
    gate centre and N - N//2 - 1 after it, both inside +-gate/2.

    Parameters
    ----------
    scenario : Scenario
    col : Collection

    Returns
    -------
    int
    """
    gate = adc_gate(scenario, col)
    fs = scenario.receiver.adc_rate
    n = int(math.floor(gate * fs)) + 1
    while n > 2 and ((n // 2) / fs >= 0.5 * gate * (1 - 1e-12) or (n - n // 2 - 1) / fs >= 0.5 * gate):
        n -= 1
    return max(n, 2)


def effective_bandwidth(scenario: Scenario, col: Collection | None = None) -> float:
    """Processed bandwidth chirp_rate * (samples / adc_rate), Hz.

    Parameters
    ----------
    scenario : Scenario
    col : Collection

    Returns
    -------
    float
        Hz.
    """
    return scenario.waveform.rate * n_fast_samples(scenario, col) / scenario.receiver.adc_rate


def resolution_theory(scenario: Scenario, collection: Collection | None = None) -> dict:
    """Theoretical resolutions (m) of a scenario in its image plane (:func:`plane_resolution`).

    Spotlight: from the extent of the K-space support along each axis
    (:func:`salkit.geometry.collection.support_resolution`); for a narrow aperture c/(2 B_eff) with
    B_eff = chirp_rate * gate, projected onto the image plane, and wavelength / (2 * dtheta_eff).
    Stripmap: the same two with dtheta_eff the beam's (:func:`processed_angle`).

    Parameters
    ----------
    scenario : Scenario
    collection : Collection, optional
        Built from the scenario when not given.

    Returns
    -------
    dict
        ``range``, ``azimuth``, ``slant_range`` (m), ``bandwidth_eff`` (Hz),
        ``aperture_length`` (m), ``angle`` (rad).
    """
    col = collection if collection is not None else build_collection(scenario)
    w, p = scenario.waveform, scenario.platform
    B = effective_bandwidth(scenario, col)
    plane = image_plane(col, scenario.processing.grid)
    ang_eff = processed_angle(col.positions, w.wavelength, p.mode, p.real_aperture)
    rho_r_plane, rho_a, rho_r = plane_resolution(B, w.wavelength, ang_eff, _unit(-col.center_position),
                                                 plane.range)
    if not (p.mode == "stripmap" and p.real_aperture > 0):  # spotlight: from the K-space support's extent
        rho_r_plane, rho_a = support_resolution(col.positions, B, w.wavelength, col.center_position, plane.azimuth,
                                                plane.range)
    aperture = ang_eff * float(np.linalg.norm(col.center_position))
    return {"range": rho_r_plane, "azimuth": rho_a, "slant_range": rho_r,
            "bandwidth_eff": B, "aperture_length": aperture, "angle": ang_eff}


GRID_TOLERANCE = GRID_SPACING_OF_RESOLUTION  # grid spacing may exceed the resolution by 1 %


@dataclass(frozen=True)
class SamplingReport:
    """Numbers behind the sampling checks (all SI)."""

    doppler_bandwidth: float
    prf: float
    beat_bandwidth: float
    adc_rate: float
    gate: float
    delay_min: float
    delay_max: float
    resolution_range: float
    resolution_azimuth: float
    footprint: float

    def as_dict(self) -> dict:
        """Plain dict of the numbers."""
        return dict(self.__dict__)


def check_sampling(scenario: Scenario, col: Collection | None = None) -> SamplingReport:
    """Check that nothing aliases, before any work is done.

    Checks: the PRF against the Doppler bandwidth of the illuminated scene; the ADC rate against
    the beat bandwidth of the scene's delay spread; the ADC gate against the pulse width; the image
    grid spacing against the resolution; the algorithm against the mode.

    Raises
    ------
    SamplingError
        With the numbers that failed.

    Parameters
    ----------
    scenario : Scenario
    col : Collection

    Returns
    -------
    SamplingReport
        The rates and their margins.
    """
    col = col if col is not None else build_collection(scenario)
    w, p, rx, proc = scenario.waveform, scenario.platform, scenario.receiver, scenario.processing
    lam = w.wavelength
    pts = scene_probe_points(scenario)
    sin_null = first_null_sin(lam, p.real_aperture)
    # Doppler spread of the illuminated scene, at the worst pulse.
    mask = _illuminated(col, pts, sin_null)
    rel = pts[None, :, :] - col.positions[:, None, :]
    rel /= np.linalg.norm(rel, axis=2, keepdims=True)
    fd = -2.0 / lam * np.einsum("pnk,pk->pn", rel, col.velocity)
    fd = np.where(mask, fd, np.nan)
    lit = np.any(mask, axis=1)
    if np.any(lit):
        f_lit = fd[lit]
        spread = np.nanmax(f_lit, axis=1) - np.nanmin(f_lit, axis=1)
        bw = float(np.max(spread))
    else:
        bw = 0.0
    if p.mode == "stripmap":  # the whole beam is filled with scene
        speed = float(np.linalg.norm(col.velocity[col.n_pulses // 2]))
        bw = max(bw, 4.0 * speed * sin_null / lam)
    if w.prf < bw * (1 - 1e-9):
        raise SamplingError("waveform.prf", w.prf,
                            f"must be >= the Doppler bandwidth of the illuminated scene, {bw:.6g} Hz "
                            f"(footprint {footprint(scenario):.4g} m)")
    d0, d1 = delay_spread(scenario, col)
    gate = adc_gate(scenario, col)
    if gate <= 0 or gate > w.pulse_width * (1 + 1e-12):
        raise SamplingError("receiver.gate", gate,
                            f"must be in (0, pulse_width = {w.pulse_width:.6g} s]; the scene's delay spread "
                            f"is {d0:.4g} .. {d1:.4g} s")
    if 2.0 * max(abs(d0), abs(d1)) >= w.pulse_width:
        raise SamplingError("receiver.reference_range", rx.reference_range,
                            f"scene delays {d0:.4g} .. {d1:.4g} s relative to the reference exceed the pulse")
    # the beat frequency is the delay times the instantaneous chirp rate k + sum n c_n t^(n-1)
    tt = np.linspace(-w.pulse_width / 2, w.pulse_width / 2, 201)
    rate = w.rate + np.zeros_like(tt) + sum((i + 2) * c * tt ** (i + 1) for i, c in enumerate(w.nonlinearity))
    if np.any(rate <= 0):
        raise SamplingError("waveform.nonlinearity", list(w.nonlinearity),
                            f"makes the sweep non-monotonic: the chirp rate falls to {rate.min():.4g} Hz/s "
                            "within the pulse")
    rate_max = float(rate.max())
    beat_max = rate_max * max(abs(d0), abs(d1))
    if rx.iq:
        need = 2.0 * beat_max
        if rx.adc_rate < need * (1 - 1e-9):
            raise SamplingError("receiver.adc_rate", rx.adc_rate,
                                f"must be >= the beat bandwidth {need:.6g} Hz (I/Q) of the scene's delay "
                                f"spread {d0:.4g} .. {d1:.4g} s at chirp rate up to {rate_max:.6g} Hz/s")
    else:
        if d0 < 0 < d1:
            raise SamplingError("receiver.reference_range", rx.reference_range,
                                "real (non-I/Q) sampling needs the whole scene on one side of the reference "
                                f"range; delays span {d0:.4g} .. {d1:.4g} s")
        need = 2.0 * beat_max
        if rx.adc_rate < need * (1 - 1e-9):
            raise SamplingError("receiver.adc_rate", rx.adc_rate,
                                f"must be >= twice the highest beat frequency, {need:.6g} Hz (real sampling)")
    former = FORMERS.get(proc.algorithm)  # what it forms, as it declares (salkit.focus.formers.FormerSpec)
    if not former.accepts(p.mode, p.positions is None):
        raise ScenarioError("processing.algorithm", proc.algorithm, former.refusal(p.mode, p.positions is None))
    res = resolution_theory(scenario, col)
    g = proc.grid
    # the line of sight turns at v_perp / R: the velocity across it sets the azimuth ambiguity (a
    # radial part, as on a curved orbit, only moves the range)
    v_c = col.velocity[col.n_pulses // 2]
    los = col.center_position / max(float(np.linalg.norm(col.center_position)), 1e-30)
    speed = max(float(np.linalg.norm(v_c - (v_c @ los) * los)), 1e-30)
    r_c = float(np.linalg.norm(col.center_position))
    unamb = lam * r_c * w.prf / (2.0 * speed)
    if p.mode == "spotlight" and g.nx * g.dx > unamb * (1 + 1e-9):
        warnings.warn(f"processing.grid spans {g.nx * g.dx:.4g} m in azimuth, more than the unambiguous "
                      f"azimuth extent lambda R PRF / 2v (v across the line of sight) = {unamb:.4g} m: targets would repeat in the image",
                      UserWarning, stacklevel=2)
    # complex Nyquist: spacing <= resolution; 1 % over loses <= 1 % of the band edge (seed 004's
    # 0.01 m grid is 0.04 % coarser than its c/2B) and the algorithms keep the support that fits
    if g.dx > res["azimuth"] * GRID_TOLERANCE:
        raise SamplingError("processing.grid.dx", g.dx,
                            f"must be <= the azimuth resolution {res['azimuth']:.6g} m (complex Nyquist)")
    if g.dy > res["range"] * GRID_TOLERANCE:
        raise SamplingError("processing.grid.dy", g.dy,
                            f"must be <= the range resolution in the image plane {res['range']:.6g} m")
    return SamplingReport(doppler_bandwidth=bw, prf=w.prf, beat_bandwidth=need, adc_rate=rx.adc_rate,
                          gate=gate, delay_min=d0, delay_max=d1, resolution_range=res["range"],
                          resolution_azimuth=res["azimuth"], footprint=footprint(scenario))
