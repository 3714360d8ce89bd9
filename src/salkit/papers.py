"""The seed papers' published numbers (``salkit/papers.yaml``), for comparison only."""
from __future__ import annotations

from functools import lru_cache
from importlib import resources

import yaml


@lru_cache(maxsize=1)
def published() -> dict:
    """The published numbers of the seed papers, by seed (``seed000``, ``seed002``).

    Returns
    -------
    dict
        As in ``salkit/papers.yaml``; lengths in m, spectral widths in MHz.

    Examples
    --------
    >>> published()["seed000"]["fringe_period_m"]
    0.18
    >>> published()["seed002"]["table3"]["rows"][50][4]  # R2 = 50, R1 = 50
    3.667
    """
    return yaml.safe_load(resources.files("salkit").joinpath("papers.yaml").read_text(encoding="utf-8"))
