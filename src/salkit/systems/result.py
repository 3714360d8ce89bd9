"""What a workflow returns: everything it computed, for the report layer to write."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np

#: ``progress(stage, done, total)``: the stage names the unit of the work (pulses, sub-images, ...).
Progress = Optional[Callable[[str, int, int], None]]


@dataclass
class RunResult:
    """The outcome of one workflow, before anything is drawn or written.

    Attributes
    ----------
    system : str
        Which workflow: ``airborne`` (a plain scenario or an outside file), ``turbulence_pga``,
        ``nonlinear_chirp``, ``spaceborne_geo``, ``downlooking``; it selects the report writer.
    name, description : str
        Of the scenario (or of the outside data).
    scenario_text : str
        The resolved scenario as YAML (saved as ``scenario.yaml``).
    metrics : dict
        Flat numbers, saved as ``metrics.json``.
    datasets : dict
        File name -> xarray.Dataset, saved as NetCDF.
    tables : dict
        File name -> CSV text.
    figures : dict
        The data each figure of the report needs (by the report writer's names).
    """

    system: str
    name: str
    description: str
    scenario_text: str
    metrics: dict
    datasets: dict = field(default_factory=dict)
    tables: dict = field(default_factory=dict)
    figures: dict = field(default_factory=dict)


def flat_numbers(d: dict) -> dict:
    """The plain numbers of a dict (bools as 0/1), without private ``_`` keys.

    Parameters
    ----------
    d : dict

    Returns
    -------
    dict
        str -> int or float.

    Examples
    --------
    >>> flat_numbers({"a": 1.5, "b": True, "_c": 2, "d": "x"})
    {'a': 1.5, 'b': 1}
    """
    out = {}
    for k, v in d.items():
        if k.startswith("_"):
            continue
        if isinstance(v, (bool, np.bool_)):
            out[k] = int(v)
        elif isinstance(v, (int, float, np.integer, np.floating)):
            out[k] = float(v) if isinstance(v, (float, np.floating)) else int(v)
    return out


class Stage:
    """``progress(done, total)`` for one stage of a ``progress(stage, done, total)`` callback; a
    processor whose unit of work changes (image formation in tiles) takes :meth:`renamed`.

    Parameters
    ----------
    progress : callable
    name : str
    """

    def __init__(self, progress, name: str):
        self.progress, self.name = progress, name

    def __call__(self, done: int, total: int) -> None:
        self.progress(self.name, done, total)

    def renamed(self, name: str) -> "Stage":
        """The same callback under another stage name (unit of work)."""
        return Stage(self.progress, name)


def stage(progress: Progress, name: str):
    """``progress(done, total)`` for one stage of a ``progress(stage, done, total)`` callback.

    Parameters
    ----------
    progress : callable or None
    name : str
        The stage, in the unit of the work (``pulses``, ``sub-images``, ...).

    Returns
    -------
    Stage or None
    """
    return Stage(progress, name) if progress else None
