"""What a scene is made of, declared once: kinds of scene object, their built-in patterns, and
materials (:data:`salkit.registry.OBJECT_KINDS`, :data:`~salkit.registry.PATTERNS`,
:data:`~salkit.registry.MATERIALS`).

An *object kind* turns the fields of ``scene.extended`` into a reflectivity map in [0, 1] over the
object's extent (``pattern``: a built-in pattern; ``image``: a picture file). A *material* turns
reflectivity on the scatterer lattice into scatterers: where they sit and their complex amplitudes
(``diffuse``: a rough surface, scatterers jittered in their cells with circular Gaussian
amplitudes, speckle; ``smooth``: amplitudes that add in phase in the image, the speckle-free
idealisation). The scenario models check ``scene.extended.kind``, ``pattern`` and ``material``
against these declarations, and :func:`salkit.simulate.scene.extended_scatterers` reads them; a
new kind, pattern or material is one declaration here or in any module of the user's
(docs/architecture.md has the recipe).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import lazy_loader as _lazy
import numpy as np

from ..errors import ScenarioError
from ..registry import MATERIALS, OBJECT_KINDS, PATTERNS

_scipy_ndimage = _lazy.load("scipy.ndimage", suppress_warning=True)


@dataclass(frozen=True)
class ObjectKind:
    """A kind of scene object (``scene.extended.kind``).

    Attributes
    ----------
    name : str
    summary : str
        One line.
    needs : tuple of str
        Fields of ``scene.extended`` it reads and that must be given.
    reflectivity : callable
        ``reflectivity(extended, u, v) -> float ndarray`` in [0, 1] at normalised coordinates
        u (azimuth), v (ground range) in [-0.5, 0.5].
    """

    name: str
    summary: str
    needs: tuple
    reflectivity: Callable


@dataclass(frozen=True)
class Pattern:
    """A built-in reflectivity pattern (``scene.extended.pattern``).

    Attributes
    ----------
    name : str
    summary : str
    mask : callable
        ``mask(u, v) -> float ndarray`` in [0, 1].
    """

    name: str
    summary: str
    mask: Callable


@dataclass(frozen=True)
class Material:
    """A material (``scene.extended.material``): how reflectivity becomes scatterers.

    Attributes
    ----------
    name : str
    summary : str
    speckle : bool
        Whether its image is speckled (``scene.extended.speckle`` names the two built-in ones).
    scatter : callable
        ``scatter(pos, t, spacing, cell_area, rng, smooth_phase) -> (pos, amp)``: scatterers of
        reflectivity ``t`` at lattice points ``pos`` (N, 3), m, spacing m, so that a resolution cell
        (ground area ``cell_area``, m^2) of reflectivity T has mean image power T^2 (or amplitude T).
    """

    name: str
    summary: str
    speckle: bool
    scatter: Callable


def declare_object_kind(name: str, **declaration) -> ObjectKind:
    """Declare a kind of scene object.

    Parameters
    ----------
    name : str
    **declaration
        The other fields of :class:`ObjectKind` (all required).

    Returns
    -------
    ObjectKind
    """
    return OBJECT_KINDS.declare(ObjectKind, name, **declaration)


def declare_pattern(name: str, **declaration) -> Pattern:
    """Declare a built-in pattern.

    Parameters
    ----------
    name : str
    **declaration
        The other fields of :class:`Pattern` (all required).

    Returns
    -------
    Pattern
    """
    return PATTERNS.declare(Pattern, name, **declaration)


def declare_material(name: str, **declaration) -> Material:
    """Declare a material.

    Parameters
    ----------
    name : str
    **declaration
        The other fields of :class:`Material` (all required).

    Returns
    -------
    Material
    """
    return MATERIALS.declare(Material, name, **declaration)


# ---------------------------------------------------------------- patterns
def _letter_i(u, v):  # an "I": a stem along range with serifs at both ends
    stem = (np.abs(u) <= 0.1) & (np.abs(v) <= 0.45)
    serif = (np.abs(u) <= 0.35) & (np.abs(v) >= 0.33) & (np.abs(v) <= 0.45)
    return (stem | serif).astype(float)


def _bars(u, v):  # groups of bars of decreasing period
    out = np.zeros_like(u)
    for k, (lo, hi) in enumerate([(-0.45, -0.15), (-0.1, 0.2), (0.25, 0.45)]):
        period = 0.12 / (k + 1)
        inside = (v >= lo) & (v < hi) & (np.abs(u) < 0.4)
        out[inside & (np.mod(u + 0.5, period) < period / 2)] = 1.0
    return out


def _satellite(u, v):  # body, two solar-panel wings on booms, a dish antenna
    body = (np.abs(u) <= 0.10) & (np.abs(v) <= 0.14)
    wings = (np.abs(u) >= 0.16) & (np.abs(u) <= 0.48) & (np.abs(v) <= 0.09)
    booms = (np.abs(u) < 0.16) & (np.abs(v) <= 0.012)
    dish = np.hypot(u, v - 0.27) <= 0.09
    return (body | wings | booms | dish).astype(float)


declare_pattern("letter_I", summary="a letter I: a stem along range, serifs at both ends (seed 004)", mask=_letter_i)
declare_pattern("bars", summary="three groups of bars along azimuth, periods 0.12, 0.06, 0.04 of the extent", mask=_bars)
declare_pattern("checker", summary="a 6 x 6 checkerboard",
                mask=lambda u, v: ((np.floor((u + 0.5) * 6) + np.floor((v + 0.5) * 6)) % 2 == 0).astype(float))
declare_pattern("disk", summary="a disk of diameter 0.8 of the extent", mask=lambda u, v: (np.hypot(u, v) <= 0.4).astype(float))
declare_pattern("uniform", summary="uniform reflectivity over the extent", mask=lambda u, v: np.ones_like(u))
declare_pattern("satellite", summary="a satellite: body, solar-panel wings on booms, a dish (seed 001)", mask=_satellite)


# ---------------------------------------------------------------- object kinds
def load_image(path: str) -> np.ndarray:
    """A picture file (PNG, NPY, any matplotlib reads) as a 2-D reflectivity map in [0, 1]
    (colour averaged, scaled by its maximum).

    Parameters
    ----------
    path : str

    Returns
    -------
    float64 ndarray

    Raises
    ------
    ScenarioError
        For a missing, unreadable, non-finite or not 2-D file (field ``scene.extended.file``).
    """
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


def _image_reflectivity(ext, u, v):
    img = load_image(ext.file)
    # image rows run from far range (top) to near range; columns along track
    rows = (0.5 - v) * (img.shape[0] - 1)
    cols = (u + 0.5) * (img.shape[1] - 1)
    return _scipy_ndimage.map_coordinates(img, [rows.ravel(), cols.ravel()], order=1).reshape(u.shape)


declare_object_kind("pattern", summary="a built-in pattern (scene.extended.pattern) over the extent", needs=("pattern",),
                    reflectivity=lambda ext, u, v: PATTERNS.get(ext.pattern).mask(u, v))
declare_object_kind("image", summary="a picture file (scene.extended.file) stretched over the extent", needs=("file",),
                    reflectivity=_image_reflectivity)


# ---------------------------------------------------------------- materials
def _diffuse(pos, t, spacing, cell_area, rng, smooth_phase):
    # random positions within each cell: a lattice has a periodic spectrum (period 2 pi/spacing),
    # so views whose wavenumbers differ by that period would see correlated speckle
    pos[:, :2] += rng.uniform(-0.5, 0.5, (pos.shape[0], 2)) * spacing
    sigma = t * math.sqrt(spacing ** 2 / cell_area)
    amp = sigma * (rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size)) / math.sqrt(2.0)
    return pos, amp


def _smooth(pos, t, spacing, cell_area, rng, smooth_phase):
    amp = (t * spacing ** 2 / cell_area).astype(np.complex128)
    if smooth_phase is not None:
        amp = amp * np.exp(1j * smooth_phase(pos))
    return pos, amp


declare_material("diffuse", summary="a rough surface: scatterers jittered in their cells, circular Gaussian "
                 "amplitudes (speckle; mean cell power T^2)", speckle=True, scatter=_diffuse)
declare_material("smooth", summary="the speckle-free idealisation: amplitudes that add in phase in the image "
                 "(cell amplitude T)", speckle=False, scatter=_smooth)
