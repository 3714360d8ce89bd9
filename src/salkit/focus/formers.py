"""Image formers: one signature, one normalisation, one declaration each.

Every former is a function::

    form(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
        accuracy: str = "standard", progress=None) -> ImageResult

whose image is normalised so that a unit-reflectance point at the beam centre peaks near 1
(the window's coherent gain divided out), declared once with :func:`register_former`: the
collection modes and tracks it accepts, whether it forms tiles of the grid and blocks of pulses,
its memory, its accuracy settings and the error each promises against the exact former. The
declaration (:class:`FormerSpec`, in :data:`salkit.registry.FORMERS`) is what the rest of salkit
reads: the scenario check of ``processing.algorithm``, the sampling preflight, the memory plan and
the tiles (:mod:`salkit.focus.tiles`), the pipeline, the command line's help and the README's table
of formers. A new former is one module that declares it (a module of ``salkit/focus``, which
:mod:`salkit.focus.pipeline` imports every one of, for a built-in former; any module of the
user's for others) and its test; docs/architecture.md has the recipe.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Callable, Mapping, NamedTuple, Optional, Protocol

import numpy as np

from ..choices import ACCURACY
from ..geometry.collection import ImagePlane, grid_axes, plane_from
from ..params.models import Grid, Processing
from ..registry import FORMERS
from ..signals.windows import Window
from .phasehistory import PhaseHistory
from ..tolerances import BP_UPSAMPLE, HIGH_ACCURACY_UPSAMPLE


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


class Sizes(NamedTuple):
    """The sizes a former's memory estimate reads.

    Attributes
    ----------
    pulses, samples : int
        The signal's shape.
    nx, ny : int
        The output grid, pixels.
    cover : int
        Pixels of a formed grid larger than the output (PFA's cover), else nx * ny.
    upsample : int
        Range-profile upsampling of backprojection (the processing's, or the high-accuracy one).
    """

    pulses: int
    samples: int
    nx: int
    ny: int
    cover: int
    upsample: int = BP_UPSAMPLE


@dataclass(frozen=True)
class Accuracy:
    """One accuracy setting of a former and what it promises.

    Attributes
    ----------
    settings : str
        What the setting does, in words (for the help and the README).
    error_db : float or None
        Promised image error energy sum |I - T|^2 / sum |T|^2 against the exact former, dB, on the
        geometries of :mod:`salkit.simulate.testbeds` (the test of accuracy holds every former to
        it); None where the former promises none there (``note`` says why).
    note : str
        Where the promise holds, or why there is none.
    """

    settings: str
    error_db: Optional[float]
    note: str = ""


#: Collection modes a former may accept, and the tracks.
MODES = ("spotlight", "stripmap")
TRACKS = ("any", "straight")
#: Where the deterministic phase of an image is referred (:func:`salkit.metrics.measure.image_phase_model`).
PHASE_REFERENCES = ("aperture_centre", "track")
#: What K-space support a spotlight image holds: the collection's own (backprojection, the exact
#: filter: its point-target theory is :func:`salkit.metrics.pointtarget.support_ipr`), or a rectangle
#: resampled inside it (polar format: the window's figures times the resolutions).
SUPPORTS = ("collection", "rectangle")


#: Range-profile upsampling of a former that declares none (``FormerSpec.upsample``), and of a
#: processor that is no former.
DEFAULT_UPSAMPLE = MappingProxyType({"standard": BP_UPSAMPLE, "high": HIGH_ACCURACY_UPSAMPLE})


def upsample_bounds() -> tuple[int, int]:
    """The range-profile upsampling allowed, as ``processing.range_upsample`` declares it (its
    field's ge and le): the bounds of a former's declaration, of ``focus(upsample=)`` and of
    ``--range-upsample``.

    Returns
    -------
    (int, int)

    Examples
    --------
    >>> upsample_bounds()
    (2, 64)
    """
    meta = Processing.model_fields["range_upsample"].metadata
    return (next(int(m.ge) for m in meta if hasattr(m, "ge")), next(int(m.le) for m in meta if hasattr(m, "le")))


@dataclass(frozen=True)
class FormerSpec:
    """What the house knows of an image former, declared once (:func:`register_former`).

    Attributes
    ----------
    name : str
        The ``processing.algorithm`` value (and ``--algorithm``).
    form : Former
        The former.
    summary : str
        One line: what it is (the help, the README).
    modes : tuple of {"spotlight", "stripmap"}
        Collection modes it forms.
    tracks : {"any", "straight"}
        Trajectories it forms (omega-k needs a straight track).
    phase_reference : {"aperture_centre", "track"}
        Where its image's deterministic phase is referred (stripmap images always follow the track).
    tiles : bool
        Whether it forms any sub-grid of the image on its own (so a job too big for memory runs
        in tiles of the grid, :mod:`salkit.focus.tiles`).
    tile_overlap : int
        Pixels each side by which a tile is formed larger than it is kept (its edge error cropped
        off; 0 when a tile is the image's pixels exactly).
    blocks : callable or None
        ``blocks(pulses, grid, window, ranges, upsample, accuracy) -> (image, info)``: a spotlight
        tile formed a block of pulses at a time (``pulses.block(a, b)`` for each (a, b) in
        ``ranges``), normalised over all the pulses; None when the former needs every pulse at once.
    memory : callable
        ``memory(sizes: Sizes) -> bytes`` the former needs beyond what every former holds (the
        signal, the range compression's buffers, the image's accumulators and output).
    accuracy : mapping
        Every level of :data:`salkit.choices.ACCURACY` -> :class:`Accuracy`.
    upsample : mapping
        Range-profile upsampling (backprojection) at each level of :data:`salkit.choices.ACCURACY`:
        the default at "standard", the least at "high" (others ignore it). Default
        :data:`salkit.tolerances.BP_UPSAMPLE` and :data:`salkit.tolerances.HIGH_ACCURACY_UPSAMPLE`.
    footprint : callable or None
        ``footprint(positions, freq, grid, accuracy) -> bytes``: what ``memory`` counts, from the
        collection's geometry where the sizes alone do not tell it (FFBP's polar grids and range
        profiles grow with the aperture's angle); the tiling planner weighs tiles and pulse blocks
        by it when the geometry is known. None: ``memory`` is exact enough.
    support : {"collection", "rectangle"}
        The K-space support its spotlight image holds (:data:`SUPPORTS`), which fixes the theory
        its point targets are judged against.
    """

    name: str
    form: Former
    summary: str
    modes: tuple
    tracks: str
    phase_reference: str
    tiles: bool
    tile_overlap: int
    blocks: Optional[Callable]
    memory: Callable[[Sizes], float]
    accuracy: Mapping[str, Accuracy] = field(default_factory=dict)
    upsample: Mapping[str, int] = field(default_factory=lambda: dict(DEFAULT_UPSAMPLE))
    footprint: Optional[Callable] = None
    support: str = "collection"

    def __post_init__(self):
        what = f"image former {self.name!r}"
        bad = [m for m in self.modes if m not in MODES]
        if not self.modes or bad:
            raise ValueError(f"{what}: modes {self.modes!r} must be a non-empty tuple of {MODES}")
        if self.tracks not in TRACKS:
            raise ValueError(f"{what}: tracks {self.tracks!r} must be one of {TRACKS}")
        if self.phase_reference not in PHASE_REFERENCES:
            raise ValueError(f"{what}: phase_reference {self.phase_reference!r} must be one of {PHASE_REFERENCES}")
        if sorted(self.accuracy) != sorted(ACCURACY) or not all(isinstance(a, Accuracy) for a in self.accuracy.values()):
            raise ValueError(f"{what}: accuracy must map each of {ACCURACY} to an Accuracy (undeclared: "
                             f"{', '.join(a for a in ACCURACY if a not in self.accuracy) or 'none'})")
        lo, hi = upsample_bounds()
        if sorted(self.upsample) != sorted(ACCURACY) or not all(
                isinstance(u, int) and lo <= u <= hi for u in self.upsample.values()):
            raise ValueError(f"{what}: upsample {dict(self.upsample)!r} must map each of {ACCURACY} to an int in "
                             f"{lo}..{hi}")
        if self.tile_overlap < 0 or (self.tile_overlap and not self.tiles):
            raise ValueError(f"{what}: tile_overlap {self.tile_overlap} needs tiles=True and must be >= 0")
        if self.blocks is not None and not self.tiles:
            raise ValueError(f"{what}: pulse blocks (blocks) are formed tile by tile: declare tiles=True")
        if not callable(self.form) or not callable(self.memory):
            raise ValueError(f"{what}: form and memory must be callables")
        if self.support not in SUPPORTS:
            raise ValueError(f"{what}: support {self.support!r} must be one of {SUPPORTS}")
        if self.footprint is not None and not callable(self.footprint):
            raise ValueError(f"{what}: footprint must be a callable or None")

    def accepts(self, mode: str, straight: bool) -> bool:
        """Whether it forms a collection of ``mode`` (straight track or not).

        Parameters
        ----------
        mode : str
        straight : bool

        Returns
        -------
        bool
        """
        return mode in self.modes and (self.tracks == "any" or straight)

    def refusal(self, mode: str, straight: bool) -> str:
        """Why it does not form such a collection, and which formers do.

        Parameters
        ----------
        mode : str
        straight : bool

        Returns
        -------
        str
        """
        track = " on a straight track" if self.tracks == "straight" else ""
        others = [n for n, s in FORMERS.items() if s.accepts(mode, straight)]
        return (f"{self.name} forms {' and '.join(self.modes)} collections{track}; this one is {mode}"
                f"{'' if straight else ' on a curved track'}: use {', '.join(others) or 'another former'}")

    def pulse_blocks(self, stripmap: bool) -> bool:
        """Whether it forms the pulses in blocks for such a collection (spotlight only: a stripmap
        image equalises the beam over every pulse).

        Parameters
        ----------
        stripmap : bool

        Returns
        -------
        bool
        """
        return self.blocks is not None and not stripmap


def register_former(name: str, **declaration) -> Callable[[Former], Former]:
    """Decorator declaring an image former: ``@register_former("name", summary=..., modes=...,
    ...)`` on the former function.

    Parameters
    ----------
    name : str
        The ``processing.algorithm`` value that selects it.
    **declaration
        Every other field of :class:`FormerSpec` (all required).

    Returns
    -------
    callable
        The decorator (it returns the former unchanged, its declaration at ``.spec``).

    Raises
    ------
    TypeError
        For a property :class:`FormerSpec` does not have, or one not declared.
    ValueError
        For a name already declared, or a property out of its range.
    """
    def deco(fn: Former) -> Former:
        spec = FORMERS.declare(FormerSpec, name, form=fn, **declaration)
        fn.spec = spec
        return fn
    return deco


def former_spec(name: str, field: str = "processing.algorithm") -> FormerSpec:
    """The declaration of the former ``name``.

    Parameters
    ----------
    name : str
    field : str
        The field or option that named it, for the message.

    Returns
    -------
    FormerSpec

    Raises
    ------
    ScenarioError
        For an undeclared name: the nearest name and the declared ones.
    """
    return FORMERS.get(name, field)


def get_former(name: str) -> Former:
    """The image former declared under ``name``.

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
    return FORMERS.get(name).form


def former_table() -> str:
    """The README's table of formers (Markdown), from their declarations.

    Returns
    -------
    str
    """
    def promise(a: Accuracy) -> str:
        p = f"better than {a.error_db:g} dB" if a.error_db is not None else "no promise"
        return f"{a.settings}: {p}" + (f" ({a.note})" if a.note else "")

    rows = ["| former | what | collections | tiles / pulse blocks | `standard` | `high` |", "|---|---|---|---|---|---|"]
    for n, s in FORMERS.items():
        coll = " and ".join(s.modes) + (", straight track" if s.tracks == "straight" else "")
        cut = ("yes" if s.tiles else "no") + " / " + ("yes (spotlight)" if s.blocks is not None else "no")
        rows.append(f"| `{n}` | {s.summary} | {coll} | {cut} | {promise(s.accuracy['standard'])} | "
                    f"{promise(s.accuracy['high'])} |")
    return "\n".join(rows) + "\n"


def former_help() -> str:
    """The command line's help for ``--algorithm``, from the declarations.

    Returns
    -------
    str
    """
    return "; ".join(f"{n}: {s.summary}" for n, s in FORMERS.items())
