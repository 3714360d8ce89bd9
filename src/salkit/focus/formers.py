"""Image formers: one signature, one normalisation, registered by name.

Every former is a function::

    form(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
        accuracy: str = "standard", progress=None) -> ImageResult

whose image is normalised so that a unit-reflectance point at the beam centre peaks near 1
(the window's coherent gain divided out). A new algorithm is one file in ``salkit/focus`` with
``@register_former("name")`` on its former, its module imported in ``salkit/focus/pipeline.py``
(where the formers register), and its name in :data:`salkit.choices.ALGORITHMS` (a test checks the
two lists agree).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional, Protocol

import numpy as np

from ..choices import ALGORITHMS
from ..errors import ScenarioError
from ..geometry.collection import ImagePlane, grid_axes, plane_from
from ..params.models import Grid
from ..signals.windows import Window
from .phasehistory import PhaseHistory
from ..tolerances import BP_UPSAMPLE


@dataclass(frozen=True)
class ImageGrid:
    """Where the pixels are: an image plane and the pixel axes in it.

    Attributes
    ----------
    plane : ImagePlane
        Origin (scene centre) and unit azimuth/range axes, float64.
    azimuth, range : float64 ndarray
        Pixel coordinates along the plane's axes, m.
    spec : Grid
        The grid parameters the axes were made from.
    """

    plane: ImagePlane
    azimuth: np.ndarray
    range: np.ndarray
    spec: Grid

    @classmethod
    def of(cls, ph: PhaseHistory, grid: Grid) -> "ImageGrid":
        """The grid ``grid`` in the image plane of the collection ``ph``.

        Parameters
        ----------
        ph : PhaseHistory
        grid : Grid

        Returns
        -------
        ImageGrid
        """
        az, rg = grid_axes(grid)
        return cls(plane_from(ph.track, ph.center_position, grid.plane), az, rg, grid)

    @property
    def shape(self) -> tuple[int, int]:
        """(azimuth pixels, range pixels)."""
        return self.azimuth.size, self.range.size


@dataclass(frozen=True)
class ImageResult:
    """A former's output.

    Attributes
    ----------
    image : complex64 (azimuth, range)
        Normalised so that a unit-reflectance point at the beam centre peaks near 1.
    info : dict
        Support of the data in the image (``support_azimuth``, ``support_range``, samples) and
        former-specific figures (``cover_*``, ``illuminated_*`` for PFA).
    """

    image: np.ndarray
    info: dict = field(default_factory=dict)


class Former(Protocol):
    """The signature every image former has."""

    def __call__(self, ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
                 accuracy: str = "standard", progress: Optional[Callable[[int, int], None]] = None) -> ImageResult: ...


#: name -> former, filled by :func:`register_former`.
FORMERS: dict[str, Former] = {}


def register_former(name: str) -> Callable[[Former], Former]:
    """Decorator registering an image former under ``name``.

    Parameters
    ----------
    name : str
        The ``processing.algorithm`` value that selects it; it must be in
        :data:`salkit.choices.ALGORITHMS`.

    Returns
    -------
    callable
        The decorator (it returns the former unchanged).

    Raises
    ------
    ValueError
        For a name already registered or not among the allowed choices.
    """
    def deco(fn: Former) -> Former:
        if name in FORMERS:
            raise ValueError(f"image former {name!r} is already registered")
        if name not in ALGORITHMS:
            raise ValueError(f"image former {name!r} is not in salkit.choices.ALGORITHMS {ALGORITHMS}")
        FORMERS[name] = fn
        return fn
    return deco


def get_former(name: str) -> Former:
    """The image former registered under ``name``.

    Parameters
    ----------
    name : str

    Returns
    -------
    Former

    Raises
    ------
    ScenarioError
        For an unknown name (field ``processing.algorithm``).
    """
    try:
        return FORMERS[name]
    except KeyError:
        raise ScenarioError("processing.algorithm", name, f"must be one of {', '.join(sorted(FORMERS))}") from None
