"""Space-borne SAL of a GEO target (seed 001): near-closest-approach geometry of two coplanar
circular orbits (SAL at radius R1 inside the target's R2, same direction), in the inertial frame.

The seed treats the relative motion near closest approach as a straight line at speed
V = sqrt(GM) (1/sqrt(R1) - 1/sqrt(R2)) at the closest distance L0 = R2 - R1;
:func:`relative_trajectory` gives the true relative positions so the difference can be reported.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ScenarioError

GM_EARTH = 3.986004418e14  #: m^3 / s^2


def relative_speed(r1: float, r2: float) -> float:
    """V = sqrt(GM) (1/sqrt(R1) - 1/sqrt(R2)), m/s: the difference of the two orbital speeds.

    Parameters
    ----------
    r1, r2 : float
        Orbit radii, m.

    Returns
    -------
    float
        m/s.
    """
    if not (0 < r1 < r2):
        raise ScenarioError("orbit", (r1, r2), "needs 0 < R1 < R2 (the SAL inside the target's orbit)")
    return math.sqrt(GM_EARTH) * (1 / math.sqrt(r1) - 1 / math.sqrt(r2))


def collection_span(closest: float, squint_max_deg: float) -> float:
    """D = 2 L0 tan(theta_max), m, for squints from -theta_max to +theta_max.

    Parameters
    ----------
    closest : float
        L0, m.
    squint_max_deg : float
        deg.

    Returns
    -------
    float
        m.
    """
    if not (0 < squint_max_deg < 90):
        raise ScenarioError("squint_max_deg", squint_max_deg, "must be in (0, 90) degrees: the geometry "
                            "cannot reach 90 degrees of squint from a straight pass")
    return 2 * closest * math.tan(math.radians(squint_max_deg))


def subaperture_length(wavelength: float, closest: float, resolution: float) -> float:
    """L_sa = lambda L0 / (2 rho), m (zero squint).

    Parameters
    ----------
    wavelength : float
        m.
    closest : float
        L0, m.
    resolution : float
        m.

    Returns
    -------
    float
        m.

    Examples
    --------
    >>> round(subaperture_length(1.55e-6, 200e3, 0.05), 6)
    3.1
    """
    return wavelength * closest / (2 * resolution)


def n_subimages(span: float, sub_length: float) -> int:
    """P = floor(D / L_sa): sub-apertures in the collection.

    Parameters
    ----------
    span : float
        m.
    sub_length : float
        m.

    Returns
    -------
    int
    """
    if sub_length > span:
        raise ScenarioError("subaperture_length", sub_length, f"is longer than the collection span {span:.4g} m")
    return int(math.floor(span / sub_length))


def resolution_vs_squint(wavelength: float, closest: float, sub_length: float, squint_deg):
    """Seed 001 eq 12: along-track resolution rho_x = lambda L0 / (2 L_sa cos^3 theta), m.

    Parameters
    ----------
    wavelength : float
        m.
    closest : float
        L0, m.
    sub_length : float
        m.
    squint_deg : float or array
        deg.

    Returns
    -------
    float or ndarray
        m.
    """
    c = np.cos(np.radians(squint_deg))
    return wavelength * closest / (2 * sub_length * c ** 3)


def max_squint_for(factor: float = 1.1) -> float:
    """Largest squint (deg) keeping the along-track resolution within ``factor`` of its best:
    cos^3 theta = 1 / factor.

    Parameters
    ----------
    factor : float
        > 1.

    Returns
    -------
    float
        deg.
    """
    return math.degrees(math.acos(factor ** (-1 / 3)))


def relative_trajectory(r1: float, r2: float, t: np.ndarray) -> np.ndarray:
    """SAL position relative to the target (inertial frame), (len(t), 2) m, t = 0 at closest approach.

    x: along the target's velocity at t = 0; z: radial (the SAL is at z = -(R2 - R1) at t = 0).

    Parameters
    ----------
    r1, r2 : float
        Orbit radii, m.
    t : float64 array
        s.

    Returns
    -------
    float64 (len(t), 2)
        m.
    """
    w1, w2 = math.sqrt(GM_EARTH / r1 ** 3), math.sqrt(GM_EARTH / r2 ** 3)
    t = np.asarray(t, dtype=np.float64)
    sal = r1 * np.stack([np.sin(w1 * t), np.cos(w1 * t)], axis=1)
    tgt = r2 * np.stack([np.sin(w2 * t), np.cos(w2 * t)], axis=1)
    return sal - tgt


def straight_line_error(r1: float, r2: float, squint_max_deg: float, n: int = 2001) -> dict:
    """How far the true relative motion departs from the straight line over the collection.

    Returns the largest range difference (m) over the whole collection and over one sub-aperture
    centred at closest approach, for the seed's sub-aperture (passed in via ``sub_length``).

    Parameters
    ----------
    r1, r2 : float
        m.
    squint_max_deg : float
        deg.
    n : int
        Time samples.

    Returns
    -------
    dict
        Times (s) and range differences (m).
    """
    V = relative_speed(r1, r2)
    L0 = r2 - r1
    T = collection_span(L0, squint_max_deg) / (2 * V)
    t = np.linspace(-T, T, n)
    rel = relative_trajectory(r1, r2, t)
    true_range = np.linalg.norm(rel, axis=1)
    line_range = np.hypot(L0, V * t)
    return {"collection_time_s": 2 * T, "max_range_difference_m": float(np.max(np.abs(true_range - line_range))),
            "range_difference_at_edges_m": float(true_range[-1] - line_range[-1])}


#: Attitudes of the target that fix the frame its scatterers are fixed in.
ATTITUDES = ("inertial", "earth_pointing")


def relative_positions(r1: float, r2: float, t: np.ndarray, attitude: str = "inertial") -> np.ndarray:
    """The SAL's position relative to the target on the true (two-body) circular coplanar orbits,
    in the frame the target's scatterers are fixed in, (len(t), 2) m: x along the relative motion
    at closest approach (t = 0), z radial outward, the SAL at z = -(r2 - r1) at t = 0.

    ``inertial``: a target that holds its attitude in inertial space (the frame of
    :func:`relative_trajectory`); differential gravity curves the path 2 GM (r2 - r1) / r^3 off
    the line. ``earth_pointing``: a target that turns with its orbit (a 3-axis stabilised
    satellite facing the Earth): the path is an arc of radius r1 about the Earth's centre, at
    r1 (w1 - w2), about 3 times the inertial relative speed at GEO.

    Parameters
    ----------
    r1, r2 : float
        Orbit radii of the SAL and the target, m.
    t : float64 array
        Time from closest approach, s.
    attitude : {"inertial", "earth_pointing"}

    Returns
    -------
    float64 (len(t), 2)
        m.
    """
    t = np.asarray(t, dtype=np.float64)
    if attitude == "inertial":
        rel = relative_trajectory(r1, r2, t)
        # relative_trajectory's x is the target's velocity direction; the SAL moves along +x relative to it
        return np.stack([rel[:, 0], rel[:, 1]], axis=1)
    if attitude == "earth_pointing":
        dw = math.sqrt(GM_EARTH / r1 ** 3) - math.sqrt(GM_EARTH / r2 ** 3)
        return np.stack([r1 * np.sin(dw * t), r1 * np.cos(dw * t) - r2], axis=1)
    raise ScenarioError("experiment.target_attitude", attitude, f"must be one of {', '.join(ATTITUDES)}")


def keplerian_positions(straight: np.ndarray, closest: np.ndarray, track: np.ndarray, speed: float, r1: float,
                        r2: float, attitude: str = "inertial") -> np.ndarray:
    """Per-pulse antenna positions on the true relative orbit, in the scene frame of a straight-line
    collection: the pulse at along-track coordinate u (time u / speed from closest approach) is moved
    to the true relative position at that time (float64 throughout).

    Parameters
    ----------
    straight : float64 (P, 3)
        Straight-line positions of the pulses, m (scene centre at the origin).
    closest : float64 (3,)
        The line's point of closest approach, m.
    track : float64 (3,)
        Unit track direction.
    speed : float
        The line's speed, m/s.
    r1, r2 : float
        Orbit radii, m.
    attitude : {"inertial", "earth_pointing"}

    Returns
    -------
    float64 (P, 3)
        m.
    """
    e_r = closest / np.linalg.norm(closest)
    u = (straight - closest) @ track
    rel = relative_positions(r1, r2, u / speed, attitude)
    return rel[:, :1] * track[None, :] - rel[:, 1:] * e_r[None, :]
