"""Geometries users bring, for judging image formers against the exact truth.

Each :class:`Testbed` is a collection (antenna positions, frequencies) with an image grid, from
which point-target and speckled scenes are simulated exactly (:mod:`salkit.simulate.analytic`):

* ``wide_angle``: an airborne X-band collection like the ones users bring (9.29 GHz, 424
  frequencies in 1.47 MHz steps, 469 pulses over a 4-degree arc of a 7 km radius circle at 7.3 km
  height, about 46 degrees depression, slant range about 10 km, starting at azimuth 0), level or
  climbing (``climb`` metres over the pass), ground or slant plane, and arcs of up to a full circle;
* ``seed``: the seed papers' 1.55 um spotlight geometries at 5 km, 200 km and 560 km (straight
  tracks, the apertures and bandwidths of the tests' scenarios);
* ``curved``: an X-band straight pass that bows ``deviation`` metres sideways and vertically.

Reference ranges are |p_n| (motion compensation to the scene centre).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..constants import SPEED_OF_LIGHT
from ..errors import ScenarioError
from ..geometry.collection import ImagePlane, plane_from
from ..params.models import Grid
from .analytic import phase_history_dataset


@dataclass(frozen=True)
class Testbed:
    """A collection and an image grid.

    Attributes
    ----------
    name : str
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre, m.
    frequency : float64 (M,)
        Hz.
    plane : {"slant", "ground"}
    dx, dy : float
        Pixel spacing along the plane's azimuth and range axes, m.
    """

    name: str
    positions: np.ndarray
    frequency: np.ndarray
    plane: str
    dx: float
    dy: float

    @property
    def track(self) -> np.ndarray:
        """Unit vector from the first to the last position."""
        t = self.positions[-1] - self.positions[0]
        return t / np.linalg.norm(t)

    @property
    def center_position(self) -> np.ndarray:
        """The middle pulse's position, m."""
        return self.positions[self.positions.shape[0] // 2]

    def image_plane(self) -> ImagePlane:
        """The image plane salkit's formers use for these data (:func:`salkit.geometry.plane_from`)."""
        return plane_from(self.track, self.center_position, self.plane)

    def grid(self, n: int, m: int | None = None):
        """A :class:`salkit.params.Grid` of n x m pixels (m = n) centred on the scene centre."""
        return Grid(nx=n, ny=m or n, dx=self.dx, dy=self.dy, plane=self.plane)

    def point_targets(self, n: int, count: int = 5, fill: float = 0.8) -> tuple[np.ndarray, np.ndarray]:
        """``count`` x ``count`` unit point targets on a lattice over ``fill`` of an n x n grid,
        off the pixel centres, in the image plane, with amplitudes 1 .. 0.3 and varied phases."""
        pl = self.image_plane()
        a = (np.linspace(-0.5, 0.5, count) * fill * n + 0.37) * self.dx
        g = (np.linspace(-0.5, 0.5, count) * fill * n - 0.21) * self.dy
        A, G = np.meshgrid(a, g, indexing="ij")
        pts = pl.points(A.ravel(), G.ravel())
        k = np.arange(pts.shape[0])
        amp = np.linspace(1.0, 0.3, pts.shape[0]) * np.exp(1j * 0.7 * k)
        return pts, amp

    def speckle(self, n: int, extent: float = 1.0, density: float = 0.1, bright: float = 0.01,
                seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Random scatterers over ``extent`` times an n x n grid's area in the image plane:
        ``density`` a pixel, circular Gaussian amplitudes, a fraction ``bright`` of them 30 times
        brighter."""
        rng = np.random.default_rng(seed)
        half_a, half_g = 0.5 * extent * n * self.dx, 0.5 * extent * n * self.dy
        K = max(int(density * (extent * n) ** 2), 1)
        A = rng.uniform(-half_a, half_a, K)
        G = rng.uniform(-half_g, half_g, K)
        amp = (rng.standard_normal(K) + 1j * rng.standard_normal(K)) / math.sqrt(2.0)
        amp[rng.random(K) < bright] *= 30.0
        return self.image_plane().points(A, G), amp

    def dataset(self, points: np.ndarray, amplitudes: np.ndarray | None = None) -> xr.Dataset:
        """The exact phase history of ``points`` (:func:`salkit.simulate.analytic.phase_history_dataset`)."""
        return phase_history_dataset(self.positions, self.frequency, points, amplitudes,
                                     attrs={"testbed": self.name})


def wide_angle(arc_deg: float = 4.0, climb: float = 0.0, plane: str = "ground", pulses: int | None = None,
               radius: float = 7000.0, height: float = 7300.0, f0: float = 9.29e9, df: float = 1.47e6,
               n_freq: int = 424, n: int | None = None) -> Testbed:
    """Airborne X-band circular arc (see the module docstring).

    Parameters
    ----------
    arc_deg : float
        Arc, degrees, up to 360 (a full circle; 469 pulses for 4, the same angular step for others).
    climb : float
        Height gained over the pass, m (0: level).
    plane : {"ground", "slant"}
    pulses : int, optional
        Pulses over the arc (default 469 per 4 degrees, more for a large ``n``; given, kept).
    radius, height : float
        m.
    f0, df : float
        First frequency and step, Hz.
    n_freq : int
    n : int, optional
        Grid size to sample for: where an n x n grid would exceed what 469 pulses (per 4 degrees)
        and 424 frequencies hold without ambiguity, more pulses over the same arc and more,
        finer frequency steps over the same band are used (range with a 25 % margin, so that
        sidelobes do not wrap: the exact matched filter is periodic in range, backprojection reads
        one period).

    Returns
    -------
    Testbed
        Pixel spacing 0.2 m in range; in azimuth 0.2 m where the arc resolves it (4 degrees:
        0.224 m), else 0.8 x the azimuth resolution.
    """
    if arc_deg <= 0 or arc_deg > 360:
        raise ScenarioError("arc_deg", arc_deg, "must be in (0, 360] degrees")
    P = pulses or int(round(469 * arc_deg / 4.0))
    lam = SPEED_OF_LIGHT / (f0 + df * (n_freq // 2))
    arc = np.deg2rad(arc_deg)
    rho_a = lam / (2.0 * arc)
    dx = 0.2 if rho_a >= 0.2 else round(0.8 * rho_a, 3)  # the users' 0.2 m where it resolves
    if n is not None:
        if pulses is None:
            P = max(P, int(math.ceil(1.0 + 2.0 * n * dx * arc / lam)))
        dep = math.atan2(height, radius)
        extent_r = 1.25 * n * 0.2 * (1.0 if plane == "slant" else math.cos(dep))
        B = n_freq * df
        m = int(math.ceil(2.0 * B * extent_r / SPEED_OF_LIGHT))
        if m > n_freq:
            n_freq, df = m, B / m
    phi = np.deg2rad(np.linspace(0.0, arc_deg, P, endpoint=arc_deg < 360))  # a full circle: no pulse twice
    z = height + climb * np.linspace(0.0, 1.0, P)
    pos = np.stack([radius * np.cos(phi), radius * np.sin(phi), z], axis=1)
    f = f0 + df * np.arange(n_freq)
    name = f"wide_angle_{arc_deg:g}deg_{'climb' if climb else 'level'}_{plane}"
    return Testbed(name, pos, f, plane, dx, 0.2)


#: The seed geometries: (slant range m, height m, aperture m, bandwidth Hz, pixel m).
SEED_GEOMETRIES = {
    "5km": (5000.0, 3000.0, 0.19375, 7.5e9, 0.015),
    "200km": (200000.0, 0.0, 3.1, 3e9, 0.04),
    "560km": (560000.0, 0.0, 8.68, 3e9, 0.04),
}


def seed(which: str = "5km", n: int = 128, plane: str = "slant") -> Testbed:
    """A seed paper's 1.55 um spotlight geometry, a straight track, sampled for an n x n grid.

    Parameters
    ----------
    which : {"5km", "200km", "560km"}
    n : int
        Grid size the sampling is chosen for (pulses and frequencies cover twice its extent).
    plane : {"slant", "ground"}

    Returns
    -------
    Testbed
    """
    if which not in SEED_GEOMETRIES:
        raise ScenarioError("which", which, f"must be one of {', '.join(SEED_GEOMETRIES)}")
    R, h, L, B, px = SEED_GEOMETRIES[which]
    fc = SPEED_OF_LIGHT / 1.55e-6
    lam = 1.55e-6
    extent = n * px
    P = int(math.ceil(4.0 * extent * L / (lam * R) / 32.0)) * 32
    M = int(math.ceil(4.0 * extent * B / SPEED_OF_LIGHT / 32.0)) * 32
    ground = math.sqrt(R * R - h * h)
    s = np.linspace(-0.5, 0.5, P) * L
    pos = np.stack([s, np.full(P, -ground), np.full(P, h)], axis=1)
    f = fc - B / 2 + (B / M) * np.arange(M)
    return Testbed(f"seed_{which}_{plane}", pos, f, plane, px, px)


def curved(deviation: float = 0.5, plane: str = "ground", pulses: int = 469) -> Testbed:
    """An X-band pass along 489 m (a 4-degree arc's length) at 10 km slant range, 46 degrees
    depression, that bows ``deviation`` metres sideways (a parabola) and vertically (a sine).

    Parameters
    ----------
    deviation : float
        m.
    plane : {"ground", "slant"}
    pulses : int

    Returns
    -------
    Testbed
    """
    s = np.linspace(-1.0, 1.0, pulses)
    L = 7000.0 * np.deg2rad(4.0)
    pos = np.stack([0.5 * L * s, -7000.0 + deviation * (1.0 - s ** 2), 7300.0 + deviation * np.sin(np.pi * s)],
                   axis=1)
    base = wide_angle(4.0)
    return Testbed(f"curved_{deviation:g}m_{plane}", pos, base.frequency, plane, 0.2, 0.2)


__all__ = ["SEED_GEOMETRIES", "Testbed", "curved", "seed", "wide_angle"]
