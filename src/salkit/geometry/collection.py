"""Collection geometry: per-pulse positions, beam pointing and the image plane.

Frame: the scene centre is the origin; x, y horizontal, z up. Every coordinate is float64.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import lazy_loader as _lazy
import numpy as np

from ..constants import SPEED_OF_LIGHT
from ..params.models import Grid, Scenario
from ..params.scenario import require_scenario
from .orbit import keplerian_positions

_special = _lazy.load("scipy.special", suppress_warning=True)  # on first use: 0.3 s of a process's start


@dataclass(frozen=True)
class Collection:
    """Per-pulse geometry of a collection.

    Attributes
    ----------
    slow_time : ndarray, shape (P,)
        Pulse times, s (0 at the aperture centre).
    positions : ndarray, shape (P, 3)
        Antenna phase centre per pulse, m.
    velocity : ndarray, shape (P, 3)
        Platform velocity per pulse, m/s.
    reference_range : ndarray, shape (P,)
        Dechirp reference range per pulse, m.
    boresight : ndarray, shape (P, 3)
        Unit vector of the beam axis per pulse.
    track : ndarray, shape (3,)
        Unit vector of the mean track direction.
    center_position : ndarray, shape (3,)
        Antenna position at the aperture centre, m.
    """

    slow_time: np.ndarray
    positions: np.ndarray
    velocity: np.ndarray
    reference_range: np.ndarray
    boresight: np.ndarray
    track: np.ndarray
    center_position: np.ndarray

    @property
    def n_pulses(self) -> int:
        """Number of pulses."""
        return self.positions.shape[0]


@dataclass(frozen=True)
class ImagePlane:
    """A plane through ``origin`` spanned by orthonormal ``azimuth`` and ``range`` vectors.

    The axes are checked on construction (unit length and orthogonal to 1e-9): pixel coordinates
    are distances only in an orthonormal frame, and the formers that work in polar coordinates
    (FFBP) rely on it.
    """

    origin: np.ndarray
    azimuth: np.ndarray
    range: np.ndarray

    def __post_init__(self):
        a, r = np.asarray(self.azimuth, np.float64), np.asarray(self.range, np.float64)
        bad = max(abs(float(a @ a) - 1.0), abs(float(r @ r) - 1.0), abs(float(a @ r)))
        if not bad <= 1e-9:
            raise ValueError(f"image plane axes must be orthonormal: |a|^2 - 1, |r|^2 - 1, a.r reach {bad:.3g} "
                             f"(azimuth {a.tolist()}, range {r.tolist()})")

    def points(self, az: np.ndarray, rg: np.ndarray) -> np.ndarray:
        """3-D points (..., 3) of plane coordinates ``az``, ``rg`` (m), broadcast together."""
        az = np.asarray(az, dtype=np.float64)[..., None]
        rg = np.asarray(rg, dtype=np.float64)[..., None]
        return self.origin + az * self.azimuth + rg * self.range


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def beam_gain_table(wavelength: float, diameter: float, n: int = 8192, u_max: float = 60.0):
    """Tabulated two-way amplitude pattern of a circular aperture, ``(2 J1(u)/u)**2``.

    Parameters
    ----------
    wavelength : float
        m.
    diameter : float
        Aperture diameter, m.

    Returns
    -------
    table : ndarray (n,)
        Two-way amplitude gain at ``sin(theta) = i * dsin``.
    dsin : float
        Step in sin(off-boresight angle).
    """
    u = np.linspace(0.0, u_max, n)
    one_way = np.ones_like(u)
    nz = u > 0
    one_way[nz] = 2.0 * _special.j1(u[nz]) / u[nz]
    dsin = (u_max / (n - 1)) * wavelength / (math.pi * diameter)
    return (one_way ** 2).astype(np.float64), dsin


def beam_gain(table: np.ndarray, dsin: float, sin_off) -> np.ndarray:
    """Two-way amplitude gain at off-boresight sines ``sin_off``, linearly interpolated in the
    :func:`beam_gain_table` (0 beyond it). The simulator's numba kernel does the same lookup per
    echo (``salkit.simulate.kernels._beam``; a test holds the two equal).

    Parameters
    ----------
    table : float64 (n,)
        :func:`beam_gain_table`.
    dsin : float
        Its step in sin(angle).
    sin_off : float array
        sin of the off-boresight angle (its magnitude is used).

    Returns
    -------
    float64 ndarray

    Examples
    --------
    >>> t, ds = beam_gain_table(1.55e-6, 0.1)
    >>> float(beam_gain(t, ds, [0.0])[0])
    1.0
    """
    gi = np.abs(np.asarray(sin_off, np.float64)) / dsin
    i0 = np.clip(gi.astype(np.int64), 0, table.size - 2)
    fr = gi - i0
    return np.where(gi < table.size - 1, table[i0] * (1 - fr) + table[i0 + 1] * fr, 0.0)


def angle_between(u: np.ndarray, v: np.ndarray) -> float:
    """Angle between two vectors, rad, accurate at any size (atan2 of the cross and dot products;
    acos of the dot product loses everything below ~1e-8 rad, a 0.2 m aperture at 13,000 km).

    Parameters
    ----------
    u, v : (3,) array_like

    Returns
    -------
    float
        rad, in [0, pi].

    Examples
    --------
    >>> angle_between([1.0, 0, 0], [1.0, 1.5e-8, 0])
    1.5e-08
    """
    u = np.asarray(u, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    return float(math.atan2(np.linalg.norm(np.cross(u, v)), float(np.dot(u, v))))


def first_null_sin(wavelength: float, diameter: float) -> float:
    """sin of the half-angle of the first null of a circular aperture's (Airy) pattern.

    Parameters
    ----------
    wavelength : float
        m.
    diameter : float
        Aperture diameter, m.

    Returns
    -------
    float
        1.2197 wavelength / diameter (dimensionless).
    """
    return 1.2196698912665045 * wavelength / diameter





def two_way_3db_sin(wavelength: float, diameter: float) -> float:
    """sin of the half-angle where the two-way power pattern is -3 dB.

    Parameters
    ----------
    wavelength : float
        m.
    diameter : float
        Aperture, m.

    Returns
    -------
    float
    """
    # (2 J1(u)/u)^4 = 1/2 -> 2 J1(u)/u = 2**-0.25 ; u = 1.1264...
    u = 1.126396
    return u * wavelength / (math.pi * diameter)


def footprint(scenario: Scenario) -> float:
    """Null-to-null azimuth footprint of the beam at the scene centre, m.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    float
        m.
    """
    p = scenario.platform
    return 2.0 * first_null_sin(scenario.waveform.wavelength, p.real_aperture) * _centre_range(scenario)


def _centre_range(scenario: Scenario) -> float:
    p = scenario.platform
    return p.slant_range / math.cos(math.radians(p.squint_deg))


def _track_frame(scenario: Scenario):
    p = scenario.platform
    h = math.radians(p.heading_deg)
    d = np.array([math.cos(h), math.sin(h), 0.0])
    left = np.array([-math.sin(h), math.cos(h), 0.0])
    sgn = 1.0 if p.side == "left" else -1.0
    closest = -sgn * p.standoff * left + np.array([0.0, 0.0, p.altitude])
    return d, closest


def scene_extent_x(scenario: Scenario) -> tuple[float, float]:
    """Along-track (x) extent of the scene's scatterers, m.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (float, float)
        m.
    """
    xs = [t.x for t in scenario.scene.points]
    ext = scenario.scene.extended
    if ext is not None:
        xs += [-ext.extent[0] / 2, ext.extent[0] / 2]
    return (min(xs), max(xs)) if xs else (0.0, 0.0)


def pulse_count(scenario: Scenario) -> int:
    """Number of pulses :func:`build_collection` makes, computed without building anything (so a
    memory guard can run first).

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    int
    """
    p, w = scenario.platform, scenario.waveform
    if p.positions is not None:
        return len(p.positions)
    L = _aperture_length(scenario)
    return max(int(math.floor(L / (p.speed / w.prf))) + 1, 2)


def _aperture_length(scenario: Scenario) -> float:
    p, w = scenario.platform, scenario.waveform
    L = p.aperture_length
    if L is None and p.mode == "spotlight":  # square resolution cell by default
        L = w.wavelength * _centre_range(scenario) / (2.0 * w.range_resolution)
    elif L is None:
        x0, x1 = scene_extent_x(scenario)
        L = (x1 - x0) + 1.2 * footprint(scenario)
    return float(L)


def build_collection(scenario: Scenario) -> Collection:
    """Per-pulse positions, reference ranges and beam pointing of a scenario.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    Collection
    """
    p, w = scenario.platform, scenario.waveform
    centre = np.zeros(3)
    if p.positions is not None:
        pos = np.asarray(p.positions, dtype=np.float64)
        n = pos.shape[0]
        t = (np.arange(n) - (n - 1) / 2.0) / w.prf
        vel = np.gradient(pos, t, axis=0)
        track = _unit(pos[-1] - pos[0])
        cpos = pos[n // 2]
    else:
        d, closest = _track_frame(scenario)
        R0 = p.slant_range
        u_c = -R0 * math.tan(math.radians(p.squint_deg))
        du = p.speed / w.prf
        n = pulse_count(scenario)
        u = u_c + (np.arange(n) - (n - 1) / 2.0) * du
        t = (u - u_c) / p.speed
        pos = closest[None, :] + u[:, None] * d[None, :]
        vel = np.broadcast_to(d * p.speed, pos.shape).copy()
        track = d
        cpos = closest + u_c * d
        if p.trajectory == "keplerian" and p.orbit is not None:  # each pulse onto the true relative orbit
            o = p.orbit
            pos = keplerian_positions(pos, closest, d, p.speed, o.r1, o.r2, o.attitude)
            vel = np.gradient(pos, t, axis=0) if n > 1 else vel
            cpos = pos[n // 2]
    if p.mode == "spotlight":
        bore = _unit(centre[None, :] - pos)
    else:
        bore = np.broadcast_to(_unit(centre - cpos), pos.shape).copy()
    rr = scenario.receiver.reference_range
    if rr is not None:
        ref = np.full(pos.shape[0], float(rr))
    elif p.mode == "spotlight":
        ref = np.linalg.norm(pos - centre, axis=1)
    else:
        ref = np.full(pos.shape[0], float(np.linalg.norm(cpos - centre)))
    return Collection(t, pos, vel, ref, bore, track, cpos)


def image_plane(collection: Collection, grid: Grid) -> ImagePlane:
    """The image plane of ``grid`` for ``collection`` (see :func:`plane_from`).

    Parameters
    ----------
    collection : Collection
    grid : Grid

    Returns
    -------
    ImagePlane
    """
    return plane_from(collection.track, collection.center_position, grid.plane)


def plane_from(track: np.ndarray, center_position: np.ndarray, plane: str = "slant") -> ImagePlane:
    """Image plane through the scene centre (origin).

    Slant plane: the azimuth axis is the track direction, the range axis is perpendicular to it
    in the plane through the track and the scene centre. Ground plane (horizontal, z up): the
    azimuth axis is the track's horizontal projection and the range axis the horizontal
    perpendicular to it. Both frames are orthonormal and the range axis points away from the
    platform. (Before 0.10 the ground plane's azimuth axis was the track itself: a climbing track
    tilted that "ground" plane and skewed its axes by the climb angle, which broke FFBP.)
    The origin is the scene centre; pixel coordinates are measured from it.

    Parameters
    ----------
    track : float64 (3,)
        Along-track direction.
    center_position : float64 (3,)
        Aperture centre relative to the scene centre, m.
    plane : {"slant", "ground"}

    Returns
    -------
    ImagePlane
    """
    a = np.asarray(track, dtype=np.float64)
    look = -np.asarray(center_position, dtype=np.float64)  # aperture centre -> scene centre
    if plane == "ground":
        a = a - a[2] * np.array([0.0, 0.0, 1.0])
        look = look - look[2] * np.array([0.0, 0.0, 1.0])
    a = a / np.linalg.norm(a)
    perp = look - np.dot(look, a) * a
    r = perp / np.linalg.norm(perp)
    r = r - np.dot(r, a) * a  # once more: orthogonal to rounding
    r = r / np.linalg.norm(r)
    return ImagePlane(origin=np.zeros(3), azimuth=a, range=r)


def grid_axes(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth and range coordinates (m) of the grid pixels, from the scene centre.

    Pixel i sits at ``center[0] + (i - nx//2) * dx`` (likewise range), so the grid centre is a pixel.

    Parameters
    ----------
    grid : Grid

    Returns
    -------
    (float64 (nx,), float64 (ny,))
        m.

    Examples
    --------
    >>> from salkit.params import Grid
    >>> az, rg = grid_axes(Grid(nx=4, ny=3, dx=0.5, dy=1.0))
    >>> az.tolist(), rg.tolist()
    ([-1.0, -0.5, 0.0, 0.5], [-1.0, 0.0, 1.0])
    """
    az = grid.center[0] + (np.arange(grid.nx) - grid.nx // 2) * grid.dx
    rg = grid.center[1] + (np.arange(grid.ny) - grid.ny // 2) * grid.dy
    return az, rg


def scene_point_positions(scenario: Scenario) -> np.ndarray:
    """Ground positions (N, 3) of the scenario's point targets, m.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    float64 (N, 3)
    """
    pts = scenario.scene.points
    return np.array([[t.x, t.y, t.z] for t in pts], dtype=np.float64).reshape(-1, 3)


def truth_positions(scenario: Scenario, collection: Collection | None = None) -> np.ndarray:
    """Where each point target should appear in the image: (N, 2) azimuth, range (m).

    Coordinates are measured from the scene centre in the image plane. A target appears at the plane point with the same
    closest-approach position along the track and the same distance from the (straight) track.

    Parameters
    ----------
    scenario : Scenario
    collection : Collection, optional

    Returns
    -------
    float64 (N, 2)
        m.
    """
    require_scenario(scenario)
    col = collection if collection is not None else build_collection(scenario)
    grid = scenario.processing.grid
    plane = image_plane(col, grid)
    pts = scene_point_positions(scenario)
    a, r = plane.azimuth, plane.range
    pc = col.center_position
    out = np.zeros((pts.shape[0], 2))
    c_rel = plane.origin - pc
    c_perp = c_rel - np.dot(c_rel, a) * a
    b = np.dot(c_perp, r)
    for i, t in enumerate(pts):
        rel = t - pc
        az = np.dot(t - plane.origin, a)
        dist2 = np.dot(rel, rel) - np.dot(rel, a) ** 2
        rg = -b + math.sqrt(max(b * b - np.dot(c_perp, c_perp) + dist2, 0.0))
        out[i] = az, rg
    return out


def processed_angle(positions: np.ndarray, wavelength: float, mode: str = "spotlight",
                    real_aperture: float = 0.0) -> float:
    """Angular span of the processed aperture, rad, seen from the scene centre.

    Spotlight: all pulses, N/(N-1) times the angle the pulses sweep (each pulse stands for one
    angular step): the length of their path on the unit sphere, summed over at most
    ``ANGLE_CHECKPOINTS`` steps (a straight track sweeps a great circle, so this is its end-to-end
    angle; a circular arc gives its full angle, a full circle 2 pi, where the end-to-end angle would
    be one step). Stripmap: the two-way 3 dB beam width, 2 asin(s3) (:func:`two_way_3db_sin`).

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre, m.
    wavelength : float
        m.
    mode : {"spotlight", "stripmap"}
    real_aperture : float
        Aperture diameter, m (stripmap).

    Returns
    -------
    float
        rad.

    Examples
    --------
    >>> pos = np.array([[-1.0, 0, 1000.0], [0, 0, 1000.0], [1.0, 0, 1000.0]])
    >>> round(processed_angle(pos, 1.55e-6) * 1e3, 4)  # 2 mrad end to end, 3 pulses
    3.0
    """
    if mode == "stripmap" and real_aperture > 0:
        return 2.0 * math.asin(min(two_way_3db_sin(wavelength, real_aperture), 1.0))
    n = positions.shape[0]
    at = np.unique(np.round(np.linspace(0, n - 1, min(n, ANGLE_CHECKPOINTS + 1))).astype(np.int64))
    u = positions[at] / np.linalg.norm(positions[at], axis=1)[:, None]
    # each step's angle as angle_between gives it (atan2 of the cross and dot products), all steps at once
    cross = np.linalg.norm(np.cross(u[:-1], u[1:]), axis=1)
    dot = np.einsum("ij,ij->i", u[:-1], u[1:])
    swept = float(np.sum(np.arctan2(cross, dot)))
    return swept * n / (n - 1)


#: Steps over which :func:`processed_angle` sums the angle the pulses sweep (a coarse path: the
#: pulses' jitter does not add to it, and a 360-degree circle loses 0.04 % to the chords).
ANGLE_CHECKPOINTS = 64


def support_resolution(positions: np.ndarray, bandwidth: float, wavelength: float, center_position: np.ndarray,
                       azimuth: np.ndarray, range_axis: np.ndarray) -> tuple[float, float]:
    """Unweighted spotlight resolutions in an image plane from the extent of the collection's
    K-space support along each axis: 2 pi / dK (Jakowatz et al. 1996, ch. 2).

    The support holds a wavenumber 4 pi f / c along each pulse's direction u (from the scene
    centre to the antenna). Along an image axis e its extent is taken as the band's, B |u_c . e|
    (u_c the aperture centre's direction), plus the spread of the directions at the reference
    frequency, f_ref (max u . e - min u . e), the latter N/(N-1) times in azimuth (each pulse
    stands for one step). For a narrow aperture this is c/(2B) projected in range and
    lambda/(2 dtheta) in azimuth (:func:`plane_resolution`); a wide one's support is an annular
    sector, wider than the band in range too, and a full circle's is a disc, the same along both
    axes.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre, m.
    bandwidth : float
        Processed bandwidth, Hz.
    wavelength : float
        At the reference frequency, m.
    center_position : float64 (3,)
        Aperture centre relative to the scene centre, m.
    azimuth, range_axis : float64 (3,)
        Unit axes of the image plane.

    Returns
    -------
    (float, float)
        Range and azimuth resolution in the plane, m.

    Examples
    --------
    >>> x = np.linspace(-10.0, 10.0, 201)  # a straight track 1 km away, 20 mrad
    >>> pos = np.stack([x, np.zeros_like(x), np.full_like(x, 1000.0)], axis=1)
    >>> a, r = np.array([1.0, 0, 0]), np.array([0, 0, -1.0])
    >>> [round(v, 4) for v in support_resolution(pos, 1e9, 0.03, pos[100], a, r)]
    [0.1498, 0.7463]
    >>> [round(v, 4) for v in plane_resolution(1e9, 0.03, processed_angle(pos, 0.03), -r, r)[:2]]
    [0.1499, 0.7463]
    """
    u = positions / np.linalg.norm(positions, axis=1)[:, None]
    uc = _unit(np.asarray(center_position, dtype=np.float64))
    f_ref = SPEED_OF_LIGHT / wavelength
    P = positions.shape[0]
    out = []
    for e, steps in ((np.asarray(range_axis, np.float64), 1.0), (np.asarray(azimuth, np.float64), P / max(P - 1, 1))):
        s = u @ e
        extent = bandwidth * abs(float(uc @ e)) + f_ref * float(s.max() - s.min()) * steps
        out.append(SPEED_OF_LIGHT / (2.0 * max(extent, 1e-300)))
    return out[0], out[1]


def plane_resolution(bandwidth: float, wavelength: float, angle: float, look: np.ndarray,
                     plane_range: np.ndarray) -> tuple[float, float, float]:
    """Unweighted resolutions in an image plane: c/(2B) projected on the plane's range axis, and
    lambda/(2 dtheta) in azimuth.

    Parameters
    ----------
    bandwidth : float
        Effective bandwidth, Hz.
    wavelength : float
        m.
    angle : float
        Processed aperture angle, rad (:func:`processed_angle`).
    look : (3,) float64
        Unit vector from the aperture centre to the scene centre.
    plane_range : (3,) float64
        Unit range axis of the image plane.

    Returns
    -------
    (float, float, float)
        Range resolution in the plane, azimuth resolution, slant-range resolution, m.

    Examples
    --------
    >>> look = np.array([0.0, 0.0, -1.0])
    >>> [round(v, 4) for v in plane_resolution(7.5e9, 1.5e-6, 1e-4, look, look)]
    [0.02, 0.0075, 0.02]
    """
    rho_slant = SPEED_OF_LIGHT / (2.0 * bandwidth)
    cos_proj = abs(float(np.dot(look, plane_range)))
    return rho_slant / max(cos_proj, 1e-12), wavelength / (2.0 * angle), rho_slant


def equalisation_efficiency(scenario: Scenario, collection: Collection | None = None) -> float:
    """CNR factor of the processor's beam equalisation, 1 / mean(1/g^2) over the processed aperture.

    Spotlight keeps the scene centre on the beam axis (factor 1). Stripmap processing equalises
    the two-way pattern g over the 3 dB aperture, which amplifies noise at the aperture edges:
    the focused carrier-to-noise ratio is eta*N_s times this factor (about 0.79).

    Parameters
    ----------
    scenario : Scenario
    collection : Collection, optional

    Returns
    -------
    float
    """
    p, w = scenario.platform, scenario.waveform
    if p.mode != "stripmap":
        return 1.0
    col = collection if collection is not None else build_collection(scenario)
    R = float(np.linalg.norm(col.center_position))
    s3 = two_way_3db_sin(w.wavelength, p.real_aperture)
    half = R * math.tan(math.asin(s3))
    du = p.speed / w.prf
    k = np.arange(-int(half / du), int(half / du) + 1)
    sin_off = np.abs(k * du) / np.hypot(k * du, R)
    uu = math.pi * p.real_aperture * sin_off / w.wavelength
    g = np.ones_like(uu)
    nz = uu > 0
    g[nz] = (2 * _special.j1(uu[nz]) / uu[nz]) ** 2
    return float(1.0 / np.mean(1.0 / g ** 2))


def rotation(attitude_deg) -> np.ndarray:
    """Rotation matrix of yaw (about z), pitch (about y), roll (about x), applied roll first.

    Parameters
    ----------
    attitude_deg : (float, float, float)

    Returns
    -------
    float64 (3, 3)
    """
    y, p, r = np.radians(np.asarray(attitude_deg, np.float64))
    Rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    Ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    Rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    return Rz @ Ry @ Rx
