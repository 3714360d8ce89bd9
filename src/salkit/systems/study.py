"""Workflows as sweep points: what ``salkit sweep`` and :func:`salkit.sweep` run.

The engine (:mod:`salkit.studies`: axes, plans, seeds, execution, checkpoints, the dataset) knows
nothing of workflows; here a point is a scenario run by its workflow up to its metrics
(:func:`run_point`), every point checked by :func:`~salkit.systems.preflight.preflight` before any
work. The systems' own loops (turbulence classes, chirp tables, squint studies) use the same engine
with their own point functions.
"""
from __future__ import annotations

import tempfile
import time
from typing import Callable, Optional

import numpy as np
import xarray as xr

from ..errors import SalkitError
from ..params.scenario import load_scenario, parse_scenario, require_scenario
from ..studies.engine import execute, measured_metrics, plan_of, select_metrics, summary, table
from ..studies.plan import check_points, make_plan, require_valid
from ..studies.spec import parse_vary
from .preflight import preflight
from .registry import run_workflow
from .result import RunResult


def run_point(data: dict, metrics=(), keep_images: bool = False) -> dict:
    """Run one (point, realisation): its workflow up to the metrics (no files kept).

    Parameters
    ----------
    data : dict
        The scenario as plain data.
    metrics : sequence of str
        Metrics to keep (empty: all numeric ones).
    keep_images : bool
        Also return the run's image datasets (``image*.nc``).

    Returns
    -------
    dict
        ``status`` ("ok" or the reason it could not run), ``metrics`` (name -> float),
        ``seconds``, and with ``keep_images`` ``images`` (file name -> dataset).
    """
    t0 = time.perf_counter()
    try:
        sc = parse_scenario(data)
        with tempfile.TemporaryDirectory(prefix="salkit-sweep-") as tmp:
            result = run_workflow(sc, tmp)
        rec = {"status": "ok", "metrics": select_metrics(result.metrics, metrics), "seconds": time.perf_counter() - t0}
        why = dict((result.figures or {}).get("details", {}).get("_unmeasured", {}))
        for name in metrics:  # a metric asked for that the run has no number for: say why
            v = rec["metrics"].get(name)
            if v is None or not np.isfinite(v):
                why.setdefault(name, "this run measures no such figure" if v is None else "not measured (NaN)")
        if why:
            rec["unmeasured"] = why
        if keep_images:
            rec["images"] = {k: v for k, v in result.datasets.items() if k.startswith("image")}
        return rec
    except SalkitError as e:
        return {"status": f"failed: {e}", "metrics": {}, "seconds": time.perf_counter() - t0}


def sweep(scenario, vary, *, zip: bool = False, realisations: int = 1, metrics=(), client=None,
          checkpoint=None, progress: Optional[Callable[[int, int], None]] = None) -> xr.Dataset:
    """Run a parameter sweep with realisations: each point's metrics against the varied fields.

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
        The base scenario.
    vary : mapping, sequence or str
        Field -> SPEC string (``"lin:1e9:7.5e9:7"``, ``"log:1e-15:1e-13:5"``, ``"bp,pfa"``) or a
        sequence of values; or a sequence of ``"FIELD=SPEC"`` strings or
        :class:`~salkit.studies.spec.Axis`; one such string alone is one axis.
    zip : bool
        Pair the axes' values instead of spanning the full grid.
    realisations : int
        Realisations per point; realisation 0 is the scenario's own seeds, every point sees the
        same realisations.
    metrics : sequence of str
        Metrics to keep (and their theory values); empty: every numeric metric.
    client : dask.distributed.Client, optional
        Where the runs go; default: this process, one after another.
    checkpoint : path, optional
        Folder of the checkpoint: finished runs are stored there and not run again.
    progress : callable, optional
        ``progress(done, total)`` in runs.

    Returns
    -------
    xarray.Dataset
        See :func:`salkit.studies.engine.assemble`.

    Raises
    ------
    ScenarioError
        A bad axis, a misspelt field, or every point invalid.
    """
    require_scenario(scenario)
    plan = plan_of(scenario, vary, zip, realisations, metrics)
    bad = check_points(plan, preflight)
    return execute(plan, bad, run_point, client=client, checkpoint=checkpoint, progress=progress)


def prepare(request) -> tuple:
    """Load a sweep request's scenario, plan it and check every point, before any work.

    Parameters
    ----------
    request : SweepFile
        :func:`salkit.studies.spec.resolve_request`.

    Returns
    -------
    (Scenario, SweepPlan, dict)
        The base scenario, the plan and the invalid points (index -> reason).

    Raises
    ------
    ScenarioError
        A bad scenario, axis or field, or no valid point.
    """
    sc = load_scenario(request.scenario, list(request.sets))
    plan = make_plan(sc, [parse_vary(v) for v in request.vary], zipped=request.zipped,
                     realisations=request.realisations, metrics=request.metrics)
    invalid = check_points(plan, preflight)
    require_valid(plan, invalid)
    return sc, plan, invalid


def as_result(ds: xr.Dataset, name: str, description: str = "") -> RunResult:
    """A sweep as a :class:`~salkit.systems.result.RunResult` for the report layer: ``sweep.nc``,
    ``sweep.csv`` and the summary metrics.

    Parameters
    ----------
    ds : xarray.Dataset
    name, description : str

    Returns
    -------
    RunResult
    """
    return RunResult("sweep", name, description, ds.attrs["scenario"], summary(ds), datasets={"sweep.nc": ds},
                     tables={"sweep.csv": table(ds)}, figures={"metrics": measured_metrics(ds)})
