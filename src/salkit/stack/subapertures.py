"""Sub-apertures of the space-borne collection (seed 001) and their images: squints, the GEO base
scenario, one sub-aperture's scenario and complex sub-image on the common target grid, the
coherent resolution study.

Sub-aperture p of the collection is centred at along-track offset u_p = L0 tan(theta_p) on the
straight-line model, has length L_sa and forms one sub-image by backprojection onto the common
target-frame grid: exact for any squint, so the sub-image is already geometrically corrected.
Each sub-aperture has its own photon noise; the scene's scatterers are the same physical target,
so its speckle decorrelates between sub-apertures through the change of aspect alone.
"""
from __future__ import annotations

import math

import lazy_loader as _lazy
import numpy as np

from ..focus import form_image, phase_history
from ..geometry.orbit import relative_speed, subaperture_length
from ..params.models import PointTarget, RelativeOrbit, Scenario, Scene
from ..simulate import photon_noise, simulate

_scipy_ndimage = _lazy.load("scipy.ndimage", suppress_warning=True)


def squint_of(index: int, count: int, squint_max_deg: float) -> float:
    """Squint (deg) of sub-aperture ``index`` of ``count`` spread evenly over +-squint_max.

    Parameters
    ----------
    index, count : int
    squint_max_deg : float
        deg.

    Returns
    -------
    float
        deg.

    Examples
    --------
    >>> [squint_of(i, 4, 5.0) for i in range(4)]
    [-3.75, -1.25, 1.25, 3.75]
    """
    if count == 1:
        return 0.0
    return -squint_max_deg + 2 * squint_max_deg * (index + 0.5) / count


def geo_base(scenario: Scenario) -> Scenario:
    """The sub-aperture scenario implied by the experiment: straight-line pass at V and L0, one
    sub-aperture L_sa long, spotlight on the target, no experiment block.

    Parameters
    ----------
    scenario : Scenario
        With ``experiment.kind = spaceborne_geo``.

    Returns
    -------
    Scenario
    """
    exp = scenario.experiment
    L0 = exp.r2 - exp.r1
    V = relative_speed(exp.r1, exp.r2)
    L = subaperture_length(scenario.waveform.wavelength, L0, exp.resolution)
    orbit = (RelativeOrbit(r1=exp.r1, r2=exp.r2, attitude=exp.target_attitude)
             if scenario.platform.trajectory == "keplerian" else None)
    p = scenario.platform.model_copy(update={"mode": "spotlight", "speed": V, "standoff": L0, "altitude": 0.0,
                                             "aperture_length": L, "squint_deg": 0.0, "positions": None,
                                             "orbit": orbit})
    return scenario.model_copy(update={"platform": p, "experiment": None})


def nearest_squints(count: int, sub_length: float, closest: float) -> list[float]:
    """Squints (deg) of the ``count`` consecutive sub-apertures nearest closest approach.

    Parameters
    ----------
    count : int
    sub_length : float
        m.
    closest : float
        L0, m.

    Returns
    -------
    list of float
        deg.
    """
    k = np.arange(count) - (count - 1) / 2
    return [float(v) for v in np.degrees(np.arctan(k * sub_length / closest))]


def uncorrect(img: np.ndarray, az: np.ndarray, rg: np.ndarray, squint_deg: float) -> np.ndarray:
    """|image| resampled into the squinted frame of eq 11 (X = -x0 - z0 tan th, Y = z0 cos th +
    x0 sin th): the sub-image as a squinted processor delivers it, before geometric correction.

    Parameters
    ----------
    img : complex (nx, ny)
    az, rg : float64
        m.
    squint_deg : float
        deg.

    Returns
    -------
    float ndarray
    """
    th = math.radians(squint_deg)
    X, Y = np.meshgrid(-az, rg, indexing="ij")
    # invert eq 11 for (x0, z0)
    A = np.array([[-1.0, -math.tan(th)], [math.sin(th), math.cos(th)]])
    inv = np.linalg.inv(A)
    x0 = inv[0, 0] * X + inv[0, 1] * Y
    z0 = inv[1, 0] * X + inv[1, 1] * Y
    ia = (x0 - az[0]) / (az[1] - az[0])
    ir = (z0 - rg[0]) / (rg[1] - rg[0])
    return _scipy_ndimage.map_coordinates(np.abs(img), [ia, ir], order=1, cval=0.0)


def subaperture(base: Scenario, squint_deg: float, noise_seed: int) -> Scenario:
    """The scenario of one sub-aperture: same target and grid, its squint, its own noise seed.

    Parameters
    ----------
    base : Scenario
    squint_deg : float
        deg.
    noise_seed : int

    Returns
    -------
    Scenario
    """
    p = base.platform.model_copy(update={"squint_deg": squint_deg})
    return base.model_copy(update={"platform": p, "seed": noise_seed})


def subimage(base: Scenario, squint_deg: float, noise_seed: int, noise: bool = True) -> np.ndarray:
    """Complex sub-image on the common target grid. The scene (speckle) uses ``base.seed``; the
    photon noise uses ``noise_seed``.

    Parameters
    ----------
    base : Scenario
    squint_deg : float
        deg.
    noise_seed : int
    noise : bool

    Returns
    -------
    complex64 (nx, ny)
    """
    sc = subaperture(base, squint_deg, base.seed)
    rng = np.random.default_rng(base.seed)  # the scene (speckle) draws first: the same target every time
    raw = simulate(sc, noise=False, rng=rng)
    if noise and base.receiver.noise.enabled:
        sig = raw["signal"].values.copy()
        photon_noise(sig, base.receiver.noise, np.random.default_rng(10_000_019 + noise_seed))
        raw["signal"].values[...] = sig
    # the former alone: a sub-image needs no dataset, no truth positions, no collection record
    p = sc.processing
    res, _, _, _ = form_image(phase_history(raw, p.chirp_correction, p.phase_noise_correction), p, p.grid)
    return res.image


def point_target(base: Scenario, grid=None) -> Scenario:
    """``base`` with one point scatterer at the scene centre, photon noise off, and optionally
    another image grid: the scenario the resolution studies measure.

    Parameters
    ----------
    base : Scenario
    grid : Grid, optional

    Returns
    -------
    Scenario
    """
    nz = base.receiver.noise
    update = {"scene": Scene(points=(PointTarget(),)),
              "receiver": base.receiver.model_copy(update={"noise": nz.model_copy(update={"enabled": False})})}
    if grid is not None:
        update["processing"] = base.processing.model_copy(update={"grid": grid})
    return base.model_copy(update=update)
