"""Turn a Scene into scatterers: positions (N, 3) float64 and complex reflectivities (N,)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import ScenarioError
from ..params.models import ExtendedScene, Scenario
import lazy_loader as _lazy
_scipy_ndimage = _lazy.load("scipy.ndimage", suppress_warning=True)


def pattern_mask(pattern: str, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Built-in reflectivity patterns on normalised coordinates u, v in [-0.5, 0.5].

    ``u`` runs along track (azimuth), ``v`` along ground range. Returns reflectivity in [0, 1].

    Parameters
    ----------
    pattern : str
        ``uniform``, ``disk``, ``checker``, ``letter_I``, ...
    u, v : float arrays
        Normalised coordinates.

    Returns
    -------
    float ndarray
    """
    if pattern == "uniform":
        return np.ones_like(u)
    if pattern == "letter_I":  # an "I": a stem along range with serifs at both ends
        stem = (np.abs(u) <= 0.1) & (np.abs(v) <= 0.45)
        serif = (np.abs(u) <= 0.35) & (np.abs(v) >= 0.33) & (np.abs(v) <= 0.45)
        return (stem | serif).astype(float)
    if pattern == "bars":  # groups of bars of decreasing period
        out = np.zeros_like(u)
        for k, (lo, hi) in enumerate([(-0.45, -0.15), (-0.1, 0.2), (0.25, 0.45)]):
            period = 0.12 / (k + 1)
            inside = (v >= lo) & (v < hi) & (np.abs(u) < 0.4)
            out[inside & (np.mod(u + 0.5, period) < period / 2)] = 1.0
        return out
    if pattern == "satellite":  # body, two solar-panel wings on booms, a dish antenna
        body = (np.abs(u) <= 0.10) & (np.abs(v) <= 0.14)
        wings = (np.abs(u) >= 0.16) & (np.abs(u) <= 0.48) & (np.abs(v) <= 0.09)
        booms = (np.abs(u) < 0.16) & (np.abs(v) <= 0.012)
        dish = np.hypot(u, v - 0.27) <= 0.09
        return (body | wings | booms | dish).astype(float)
    if pattern == "checker":
        return ((np.floor((u + 0.5) * 6) + np.floor((v + 0.5) * 6)) % 2 == 0).astype(float)
    if pattern == "disk":
        return (np.hypot(u, v) <= 0.4).astype(float)
    raise ScenarioError("scene.extended.pattern", pattern, "unknown pattern")


def _load_image(path: str) -> np.ndarray:
    p = Path(path)
    if not p.is_file():
        raise ScenarioError("scene.extended.file", path, "file does not exist")
    try:
        if p.suffix.lower() == ".npy":
            img = np.load(p)
        else:
            import matplotlib.image as mpimg
            img = mpimg.imread(p)
    except Exception as err:  # noqa: BLE001 - any reader failure is a bad file
        raise ScenarioError("scene.extended.file", path, f"cannot be read as an image ({err})") from None
    img = np.asarray(img, dtype=np.float64)
    if img.ndim == 3:
        img = img[..., :3].mean(axis=2)
    if img.ndim != 2 or not np.all(np.isfinite(img)):
        raise ScenarioError("scene.extended.file", path, "must be a finite 2-D (or RGB) image")
    mx = img.max()
    return img / mx if mx > 0 else img


def extended_scatterers(ext: ExtendedScene, cell_area: float, rng: np.random.Generator,
                        smooth_phase=None):
    """Scatterers of an extended scene.

    The per-scatterer amplitude is scaled so that a resolution cell (ground area ``cell_area``, m^2)
    of reflectivity T has mean image power T^2 (speckle) or image amplitude T (no speckle), the
    same as a point target of amplitude T.

    With speckle, scatterers sit at random positions within their cells (a diffuse surface, not a
    lattice). Without speckle, ``smooth_phase(pos) -> rad`` gives each scatterer the phase that makes it add
    in phase in the focused image (the usual speckle-free idealisation; a surface of truly constant
    reflectivity phase would be a specular mirror and return almost nothing).

    Parameters
    ----------
    ext : ExtendedScene
    cell_area : float
        m^2.
    rng : numpy.random.Generator
    smooth_phase : callable, optional

    Returns
    -------
    (float64 (N, 3), complex128 (N,))
    """
    nx = max(int(round(ext.extent[0] / ext.spacing)), 1)
    ny = max(int(round(ext.extent[1] / ext.spacing)), 1)
    x = (np.arange(nx) - (nx - 1) / 2) * ext.spacing
    y = (np.arange(ny) - (ny - 1) / 2) * ext.spacing
    X, Y = np.meshgrid(x, y, indexing="ij")
    u, v = X / ext.extent[0], Y / ext.extent[1]
    if ext.kind == "image":
        img = _load_image(ext.file)
        # image rows run from far range (top) to near range; columns along track
        rows = (0.5 - v) * (img.shape[0] - 1)
        cols = (u + 0.5) * (img.shape[1] - 1)
        refl = _scipy_ndimage.map_coordinates(img, [rows.ravel(), cols.ravel()], order=1).reshape(X.shape)
    else:
        refl = pattern_mask(ext.pattern, u, v)
    refl = refl * ext.amplitude
    keep = refl > 0
    pos = np.stack([X[keep], Y[keep], np.full(keep.sum(), ext.height)], axis=1)
    t = refl[keep]
    d2 = ext.spacing ** 2
    if ext.speckle:
        # random positions within each cell: a lattice has a periodic spectrum (period 2 pi/spacing),
        # so views whose wavenumbers differ by that period would see correlated speckle
        pos[:, :2] += rng.uniform(-0.5, 0.5, (pos.shape[0], 2)) * ext.spacing
        sigma = t * math.sqrt(d2 / cell_area)
        amp = sigma * (rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size)) / math.sqrt(2.0)
    else:
        amp = (t * d2 / cell_area).astype(np.complex128)
        if smooth_phase is not None:
            amp = amp * np.exp(1j * smooth_phase(pos))
    return pos, amp


def build_scatterers(scenario: Scenario, cell_area: float, rng: np.random.Generator, smooth_phase=None):
    """All scatterers of a scenario: positions (N, 3) m and complex reflectivities (N,).

    Parameters
    ----------
    scenario : Scenario
    cell_area : float
        m^2.
    rng : numpy.random.Generator
    smooth_phase : callable, optional

    Returns
    -------
    (float64 (N, 3), complex128 (N,))
    """
    pts = scenario.scene.points
    pos = [np.array([[t.x, t.y, t.z] for t in pts], dtype=np.float64).reshape(-1, 3)]
    amp = [np.array([t.amplitude * np.exp(1j * t.phase) for t in pts], dtype=np.complex128)]
    if scenario.scene.extended is not None:
        p, a = extended_scatterers(scenario.scene.extended, cell_area, rng, smooth_phase)
        pos.append(p)
        amp.append(a)
    return np.concatenate(pos), np.concatenate(amp)
