"""A sweep's plan: the base scenario, the varied axes (a full grid, or zipped), the realisations
and their seeds (common random numbers), every point's scenario checked before any work."""
from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field

import numpy as np
import yaml

from ..errors import SalkitError, ScenarioError
from ..metrics.table import check_metric
from ..params.scenario import apply_overrides, dump_scenario, parse_scenario


#: Most (point, realisation) runs one sweep may hold.
MAX_RUNS = 1_000_000


def realisation_seed(seed: int, r: int) -> int:
    """The seed of realisation ``r`` of a random field whose scenario seed is ``seed``: ``seed``
    itself for realisation 0 (the scenario as written), else one drawn from (seed, r) alone, so
    that every point of a sweep sees the same realisations (common random numbers).

    Parameters
    ----------
    seed : int
        A scenario's seed (>= 0).
    r : int
        Realisation (>= 0).

    Returns
    -------
    int
        In [0, 2**32).

    Examples
    --------
    >>> realisation_seed(7, 0), realisation_seed(7, 1) == realisation_seed(7, 1) != realisation_seed(8, 1)
    (7, True)
    """
    if r == 0:
        return int(seed)
    return int(np.random.SeedSequence([int(seed), int(r)]).generate_state(1, dtype=np.uint32)[0])


def with_realisation(data, r: int):
    """A scenario mapping with every ``seed`` (the scene's speckle and noise, the screens, injected
    phase errors, disturbances) replaced by :func:`realisation_seed` of it.

    Parameters
    ----------
    data : dict
        A scenario as plain data.
    r : int

    Returns
    -------
    dict
        A new mapping.
    """
    if isinstance(data, dict):
        return {k: (realisation_seed(v, r) if k == "seed" and isinstance(v, int) and not isinstance(v, bool)
                    else with_realisation(v, r)) for k, v in data.items()}
    if isinstance(data, list):
        return [with_realisation(v, r) for v in data]
    return data


@dataclass(frozen=True)
class SweepPlan:
    """What a sweep runs.

    Parameters
    ----------
    base : dict
        The resolved base scenario as plain data (every default filled in).
    axes : tuple of Axis
    zipped : bool
        Pair the axes' values (equal lengths) instead of spanning the full grid.
    realisations : int
        Realisations per point (>= 1).
    metrics : tuple of str
        Metrics to keep (empty: every numeric metric of the runs).
    """

    base: dict
    axes: tuple
    zipped: bool = False
    realisations: int = 1
    metrics: tuple = field(default=())

    def __post_init__(self):
        if not self.axes:
            raise ScenarioError("--vary", None, "a sweep needs at least one varied field")
        fields = [a.field for a in self.axes]
        if len(set(fields)) != len(fields):
            raise ScenarioError("--vary", ", ".join(fields), "varies a field twice")
        if self.zipped and len({len(a.values) for a in self.axes}) != 1:
            raise ScenarioError("--zip", ", ".join(f"{a.field}: {len(a.values)}" for a in self.axes),
                                "zipped axes need the same number of values")
        if not (isinstance(self.realisations, int) and self.realisations >= 1):
            raise ScenarioError("--realisations", self.realisations, "must be an integer >= 1")
        if self.n_points * self.realisations > MAX_RUNS:
            raise ScenarioError("--vary", f"{self.n_points} points x {self.realisations} realisations",
                                f"exceeds {MAX_RUNS} runs")

    @property
    def shape(self) -> tuple:
        """Points along each dimension: one per axis, or one ``point`` dimension when zipped."""
        return (len(self.axes[0].values),) if self.zipped else tuple(len(a.values) for a in self.axes)

    @property
    def n_points(self) -> int:
        """Number of points."""
        return int(np.prod(self.shape))

    def point_values(self, i: int) -> tuple:
        """The varied fields' values at flat point index ``i`` (C order over :attr:`shape`)."""
        if self.zipped:
            return tuple(a.values[i] for a in self.axes)
        idx = np.unravel_index(i, self.shape)
        return tuple(a.values[k] for a, k in zip(self.axes, idx))

    def overrides(self, i: int) -> list[str]:
        """``--set`` strings of point ``i``."""
        return [f"{a.field}={json.dumps(v)}" for a, v in zip(self.axes, self.point_values(i))]

    def point_data(self, i: int, r: int = 0) -> dict:
        """Scenario of point ``i``, realisation ``r``, as plain data."""
        return with_realisation(apply_overrides(self.base, self.overrides(i)), r)

    def definition(self) -> dict:
        """The sweep as plain data (saved with the results and the checkpoint)."""
        return {"axes": [a.as_dict() for a in self.axes], "zip": self.zipped, "realisations": self.realisations,
                "metrics": list(self.metrics)}

    def fingerprint(self) -> str:
        """SHA-256 of the base scenario and the definition: a checkpoint resumes only the same sweep."""
        text = json.dumps({"base": self.base, "sweep": self.definition()}, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()


def make_plan(scenario, axes, *, zipped: bool = False, realisations: int = 1, metrics=()) -> SweepPlan:
    """A plan from a parsed scenario and its axes; every varied field must exist in the scenario (as
    ``--set`` addresses it) and take the first value of its axis.

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
    axes : sequence of Axis
    zipped : bool
    realisations : int
    metrics : sequence of str

    Returns
    -------
    SweepPlan

    Raises
    ------
    ScenarioError
        A misspelt field, or one that cannot take the values; a metric not in the table of metrics.
    """
    for m in metrics:  # each a metric salkit measures (salkit.metrics.table), before any work
        check_metric(m, "metrics")
    base = yaml.safe_load(dump_scenario(scenario))
    for a in axes:  # a misspelt field is refused before any work, naming it
        try:
            parse_scenario(apply_overrides(base, [f"{a.field}={json.dumps(a.values[0])}"]))
        except ScenarioError as e:
            if e.field == "--set" or ((e.field == a.field or a.field.startswith(e.field + "."))
                                      and "is not a field of" in e.constraint):  # the key, or its section
                raise ScenarioError("--vary", a.field, e.constraint.split(";")[0].replace(
                    f"'{a.field.split('.')[-1]}' ", "")) from None
            # a value the field refuses makes that point invalid (check_points), not the sweep
    return SweepPlan(base, tuple(axes), zipped, realisations, tuple(metrics))


def check_points(plan: SweepPlan, check=None) -> dict[int, str]:
    """Validate every point's scenario before any work: its model constraints, and what ``check``
    finds (:func:`salkit.systems.preflight.preflight`: aliasing, memory).

    Parameters
    ----------
    plan : SweepPlan
    check : callable, optional
        ``check(scenario)``, raising :class:`~salkit.errors.SalkitError` on a point that cannot run.

    Returns
    -------
    dict
        Point index -> the reason it cannot run (``field = value: constraint``), for invalid points.
    """
    bad = {}
    for i in range(plan.n_points):
        try:
            sc = parse_scenario(plan.point_data(i))
            if check is not None:
                check(sc)
        except SalkitError as e:
            bad[i] = str(e)
    return bad


def require_valid(plan: SweepPlan, invalid: dict) -> None:
    """Refuse a sweep none of whose points can run, naming the first reason.

    Parameters
    ----------
    plan : SweepPlan
    invalid : dict
        Point -> reason (:func:`check_points`).

    Raises
    ------
    ScenarioError
        When every point is invalid.
    """
    if len(invalid) == plan.n_points:
        first = next(iter(invalid.values()))
        raise ScenarioError("--vary", f"all {plan.n_points} points", f"none can run; the first: {first}")
