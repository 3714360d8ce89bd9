"""Turn a Scene into scatterers: positions (N, 3) float64 and complex reflectivities (N,), through
the declared object kinds, patterns and materials (:mod:`salkit.simulate.objects`)."""
from __future__ import annotations

import numpy as np

from ..params.models import ExtendedScene, Scenario
from ..registry import MATERIALS, OBJECT_KINDS, PATTERNS
from . import objects  # noqa: F401  (the built-in kinds, patterns and materials declare themselves)


def pattern_mask(pattern: str, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A declared pattern (:data:`salkit.registry.PATTERNS`) on normalised coordinates u, v in
    [-0.5, 0.5].

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

    Raises
    ------
    ScenarioError
        For an undeclared pattern (field ``scene.extended.pattern``).
    """
    return PATTERNS.get(pattern).mask(u, v)


def material_of(ext: ExtendedScene) -> str:
    """The material of an extended scene: ``material`` if given, else ``diffuse`` with speckle and
    ``smooth`` without.

    Parameters
    ----------
    ext : ExtendedScene

    Returns
    -------
    str
    """
    return ext.material or ("diffuse" if ext.speckle else "smooth")


def extended_scatterers(ext: ExtendedScene, cell_area: float, rng: np.random.Generator,
                        smooth_phase=None):
    """Scatterers of an extended scene.

    The object's kind (:class:`salkit.simulate.objects.ObjectKind`) gives its reflectivity on the
    lattice, its material (:class:`salkit.simulate.objects.Material`, :func:`material_of`) the
    scatterers: amplitudes scaled so that a resolution cell (ground area ``cell_area``, m^2) of
    reflectivity T has mean image power T^2 (``diffuse``: speckle, scatterers at random positions
    within their cells) or image amplitude T (``smooth``: ``smooth_phase(pos) -> rad`` gives each
    scatterer the phase that makes it add in phase in the focused image, the usual speckle-free
    idealisation; a surface of truly constant reflectivity phase would be a specular mirror and
    return almost nothing), the same as a point target of amplitude T.

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
    refl = OBJECT_KINDS.get(ext.kind).reflectivity(ext, u, v) * ext.amplitude
    keep = refl > 0
    pos = np.stack([X[keep], Y[keep], np.full(keep.sum(), ext.height)], axis=1)
    return MATERIALS.get(material_of(ext)).scatter(pos, refl[keep], ext.spacing, cell_area, rng, smooth_phase)


def build_scatterers(scenario: Scenario, cell_area: float, rng: np.random.Generator, smooth_phase=None):
    """The scatterers of a scenario's point targets and extended scene: positions (N, 3) m and
    complex reflectivities (N,). (Its 3-D objects are seen look by look:
    :class:`salkit.simulate.views.ObjectScene`.)

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
