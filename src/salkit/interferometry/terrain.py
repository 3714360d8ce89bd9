"""Synthetic 3-D terrain: a smooth height map with reflectivity and speckle."""
from __future__ import annotations

import math

import numpy as np
from scipy.ndimage import gaussian_filter
import lazy_loader as _lazy
_scipy_interpolate = _lazy.load("scipy.interpolate", suppress_warning=True)


def terrain_height(terrain, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Height (m) of a :class:`~salkit.params.downlooking.Terrain` at ground positions x (along track)
    and y (across track), m. Seeded, so the same terrain comes back every time.

    Parameters
    ----------
    terrain : Terrain
    x, y : float array
        m.

    Returns
    -------
    ndarray
        m.
    """
    rng = np.random.default_rng(terrain.seed)
    ex, ey = terrain.extent
    x = np.asarray(x, np.float64)
    y = np.asarray(y, np.float64)
    if terrain.kind == "hills":
        h = np.zeros(np.broadcast(x, y).shape)
        n = 5
        cx = rng.uniform(-0.35, 0.35, n) * ex
        cy = rng.uniform(-0.35, 0.35, n) * ey
        amp = terrain.peak_height * np.concatenate([[1.0], rng.uniform(0.3, 0.8, n - 1)])
        w = terrain.correlation_length * rng.uniform(0.6, 1.0, n)
        for a, u, v, s in zip(amp, cx, cy, w):
            h = h + a * np.exp(-((x - u) ** 2 + (y - v) ** 2) / (2 * s * s))
        return h
    # random: Gaussian-correlated field on a fine grid, interpolated
    step = terrain.correlation_length / 8
    gx = np.arange(-0.5 * ex - step, 0.5 * ex + 2 * step, step)
    gy = np.arange(-0.5 * ey - step, 0.5 * ey + 2 * step, step)
    f = gaussian_filter(rng.standard_normal((gx.size, gy.size)), sigma=8 / math.sqrt(2), mode="wrap")
    f *= terrain.peak_height / f.std()
    itp = _scipy_interpolate.RegularGridInterpolator((gx, gy), f, bounds_error=False, fill_value=0.0)
    return itp(np.stack(np.broadcast_arrays(x, y), axis=-1))


def terrain_scatterers(terrain, cell_area: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Scatterers on the surface: ground positions (N, 3) m (x along, y across, z up) and complex
    reflectivities, normalised so a resolution cell (ground area ``cell_area``) has mean power 1.

    Parameters
    ----------
    terrain : Terrain
    cell_area : float
        m^2.
    rng : numpy.random.Generator

    Returns
    -------
    (float64 (N, 3), complex128 (N,))
        Positions, m, and reflectivities.
    """
    ex, ey = terrain.extent
    d = terrain.spacing
    nx, ny = max(int(round(ex / d)), 1), max(int(round(ey / d)), 1)
    x = (np.arange(nx) - (nx - 1) / 2) * d
    y = (np.arange(ny) - (ny - 1) / 2) * d
    X, Y = np.meshgrid(x, y, indexing="ij")
    X = X.ravel() + rng.uniform(-0.5, 0.5, X.size) * d
    Y = Y.ravel() + rng.uniform(-0.5, 0.5, Y.size) * d
    Z = terrain_height(terrain, X, Y)
    scale = math.sqrt(d * d / cell_area)
    if terrain.speckle:
        amp = scale * (rng.standard_normal(X.size) + 1j * rng.standard_normal(X.size)) / math.sqrt(2)
    else:
        amp = np.full(X.size, scale, np.complex128)
    return np.stack([X, Y, Z], axis=1), amp
