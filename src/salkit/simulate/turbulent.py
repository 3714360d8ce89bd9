"""The atmosphere of a SAL scenario: the frozen-screen path (screens sized for every ray) and the
wave-optics beam plan."""
from __future__ import annotations

import math

import numpy as np

from ..atmosphere.beam import layered_r0_spherical, plan_beam, screen_need
from ..atmosphere.path import build_path, path_frame, ray_crossings, screens_memory
from ..atmosphere.turbulence import r0_from_cn2
from ..errors import ScenarioError
from ..geometry.collection import Collection
from ..geometry.sampling import scene_probe_points
from ..params.models import Scenario
from ..resources import check_memory


def screen_size(scenario: Scenario, col: Collection) -> int:
    """Side of the scenario's phase screens: ``atmosphere.screen_n`` if given, else large enough for
    every ray (and, for ``wave_optics``, for the propagation grid on every layer).

    Parameters
    ----------
    scenario : Scenario
        With an atmosphere.
    col : Collection

    Returns
    -------
    int

    Raises
    ------
    ScenarioError
        When an explicit ``atmosphere.screen_n`` is smaller than what the rays (or the grids) cross.
    """
    atm = scenario.atmosphere
    R, u0, a, b = _los_frame(col)
    probe = scene_probe_points(scenario)
    # extent the rays cover on the layers: scene extent near the target, aperture near the platform
    ends = np.stack([col.positions[0], col.positions[-1], col.positions[col.n_pulses // 2]])
    need = 0.0
    for frac in (0.0, 0.5, 1.0 - 0.5 / atm.layers):
        q = ray_crossings(ends, probe, frac * R, u0)
        need = max(need, float(np.ptp(q @ a)), float(np.ptp(q @ b)))
    what = "the rays cross"
    if atm.model == "wave_optics":  # the propagation grids must lie on the screens on every layer
        plan, _ = wave_optics_plan(scenario, col)
        grids = screen_need(plan, R, _swath(col, a, b))
        if grids > need:
            need, what = grids, "the wave-optics grids cover"
    n_need = int(math.ceil(need / atm.screen_dx)) + 8
    if atm.screen_n is not None and atm.screen_n < n_need:
        raise ScenarioError("atmosphere.screen_n", atm.screen_n,
                            f"{what} {need:.4g} m of a layer; at screen_dx = {atm.screen_dx:g} m the "
                            f"screen needs >= {n_need} samples")
    return atm.screen_n or max(32, n_need)


def turbulent_path(scenario: Scenario, col: Collection):
    """The scenario's frozen-screen path, with screens of :func:`screen_size`.

    Parameters
    ----------
    scenario : Scenario
    col : Collection

    Returns
    -------
    TurbulentPath

    Raises
    ------
    ScenarioError
        When an explicit ``atmosphere.screen_n`` is too small (:func:`screen_size`), or the screens
        need more memory than the machine has.
    """
    atm = scenario.atmosphere
    R = float(np.linalg.norm(col.center_position))
    n = screen_size(scenario, col)
    check_memory(screens_memory(atm.layers, n), f"{atm.layers} phase screens of {n} x {n}",
                 "use fewer atmosphere.layers or a coarser atmosphere.screen_dx")
    return build_path(atm.cn2, R, scenario.waveform.wavelength, atm.layers, n, atm.screen_dx,
                      col.center_position / R, col.track, seed=atm.seed, outer_scale=atm.outer_scale,
                      inner_scale=atm.inner_scale)


def _los_frame(col: Collection):
    """Slant range R (m), the line of sight u0 (scene centre to aperture centre) and the layer
    planes' axes: a along track (orthogonal to u0), b = u0 x a (the frame of build_path)."""
    u0, a, b = path_frame(col.center_position, col.track)
    return float(np.linalg.norm(col.center_position)), u0, a, b


def _swath(col: Collection, a: np.ndarray, b: np.ndarray) -> float:
    """Largest extent of the antenna positions across the line of sight (along a or b), m."""
    return float(max(np.ptp(col.positions @ a), np.ptp(col.positions @ b)))


def wave_optics_plan(scenario: Scenario, col: Collection):
    """Sampling of the wave-optics transmit beam (:func:`salkit.atmosphere.beam.plan_beam`) for a
    scenario: the path's length, layers and spherical-wave r0; the scene region the larger of the
    scatterers' extent across the line of sight (plus 10 %) and the beam's first-null diameter
    2.44 lambda R / D.

    Parameters
    ----------
    scenario : Scenario
        With an atmosphere.
    col : Collection

    Returns
    -------
    (BeamSampling, float)
        The sampling and the region's diameter, m.

    Raises
    ------
    SamplingError
        When the beam cannot be sampled on a grid of at most 4096^2.
    ScenarioError
        For a stripmap collection.
    """
    atm, lam = scenario.atmosphere, scenario.waveform.wavelength
    if scenario.platform.mode != "spotlight":  # each beam is propagated towards the scene centre
        raise ScenarioError("atmosphere.model", "wave_optics",
                            f"needs a spotlight collection (the beam points at the scene centre), "
                            f"not platform.mode = {scenario.platform.mode}")
    R, _, a, b = _los_frame(col)
    probe = scene_probe_points(scenario)
    radius = float(np.max(np.hypot(probe @ a, probe @ b)))
    region = max(2.2 * radius, 2.44 * lam * R / scenario.platform.real_aperture)
    dz = R / atm.layers
    z = (np.arange(atm.layers) + 0.5) * dz
    r0 = np.broadcast_to(np.asarray(r0_from_cn2(np.asarray(atm.cn2, float), dz, lam), float), (atm.layers,))
    return plan_beam(lam, R, scenario.platform.real_aperture, region, layered_r0_spherical(r0, z, R), z), region
