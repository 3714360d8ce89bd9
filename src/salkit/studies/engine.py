"""Running a sweep: each (point, realisation) goes to a runner (what ``salkit run`` runs for the
scenario, :func:`salkit.systems.study.run_point`, or a system's own point function); finished runs
are stored one file each as they complete (the checkpoint), so an interrupted sweep resumes with
only what is missing; the results become one labelled dataset.

Runs go through Dask when a client is given (a local cluster by default from the command line,
or an existing scheduler's), in this process otherwise. The numbers do not depend on which: each
run's random fields come from its realisation's seeds alone.
"""
from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Callable, Mapping, Optional

import numpy as np
import xarray as xr
import yaml

from .. import __version__
from ..errors import SalkitError
from ..io.writing import write_dataset, write_json_atomic
from ..params.scenario import dump_scenario, parse_scenario
from ..resources import task_numba_threads
from ..units import theory_name, unit_of
from .plan import SweepPlan, make_plan, require_valid
from .spec import Axis, parse_vary
from .._lazy import load as _deferred

_dask_distributed = _deferred("dask.distributed")  # not lazy_loader: it imports dask itself at once

def select_metrics(metrics: dict, wanted) -> dict:
    """The numeric metrics a sweep keeps: ``wanted`` (all when empty) and each one's theory value.

    Parameters
    ----------
    metrics : dict
        A run's metrics.
    wanted : sequence of str

    Returns
    -------
    dict
        Name -> float.
    """
    def num(v):
        return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
    names = list(wanted) or [k for k, v in metrics.items() if num(v)]
    out = {}
    for n in names:
        for k in (n, theory_name(n)):
            if k in metrics and num(metrics[k]):
                out[k] = float(metrics[k])
    return out


class Checkpoint:
    """A folder holding one JSON file per finished (point, realisation) and the sweep's
    fingerprint; written atomically, read back on resume.

    Parameters
    ----------
    folder : Path
    plan : SweepPlan

    Raises
    ------
    SalkitError
        When the folder holds the checkpoint of another sweep.
    """

    def __init__(self, folder, plan: SweepPlan):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        head = self.folder / "sweep.json"
        fp = plan.fingerprint()
        if head.is_file():
            if json.loads(head.read_text()).get("fingerprint") != fp:
                raise SalkitError(f"{self.folder}: the checkpoint belongs to another sweep (scenario or "
                                  "definition differs); start again with --overwrite")
        else:
            write_json_atomic(head, {"fingerprint": fp, "sweep": plan.definition()})

    def path(self, i: int, r: int) -> Path:
        """File of point ``i``, realisation ``r``."""
        return self.folder / f"p{i:06d}_r{r:04d}.json"

    def done(self) -> dict:
        """Every stored run: (i, r) -> its record."""
        out = {}
        for p in sorted(self.folder.glob("p*_r*.json")):
            try:
                rec = json.loads(p.read_text())
            except (OSError, ValueError):
                continue  # a torn file cannot exist (atomic writes); skip anything unreadable
            out[(rec["point"], rec["realisation"])] = rec
        return out

    def store(self, i: int, r: int, rec: dict) -> None:
        """Store one run's record."""
        write_json_atomic(self.path(i, r), {"point": i, "realisation": r, **rec})


def plan_of(scenario, vary, zip=False, realisations=1, metrics=()) -> SweepPlan:
    """A :class:`SweepPlan` from the arguments of :func:`salkit.systems.study.sweep`.

    Parameters
    ----------
    scenario, vary, zip, realisations, metrics
        As :func:`salkit.systems.study.sweep`.

    Returns
    -------
    SweepPlan
    """
    if isinstance(vary, (str, Axis)):  # one axis, not its characters
        vary = [vary]
    if isinstance(vary, Mapping):
        axes = [parse_vary(f"{k}={v}") if isinstance(v, str) else
                parse_vary(f"{k}=" + ",".join(json.dumps(x) for x in v)) for k, v in vary.items()]
    else:
        axes = [a if isinstance(a, Axis) else parse_vary(a) for a in vary]
    return make_plan(scenario, axes, zipped=zip, realisations=realisations, metrics=metrics)


def execute(plan: SweepPlan, invalid: dict, runner: Callable[..., dict], *, client=None, checkpoint=None,
            progress: Optional[Callable[[int, int], None]] = None, images=None,
            collect: Optional[dict] = None) -> xr.Dataset:
    """Run every (point, realisation) not in the checkpoint and not invalid; assemble the results.

    Parameters
    ----------
    plan : SweepPlan
    invalid : dict
        Point -> reason (:func:`~salkit.studies.plan.check_points`).
    runner : callable
        What runs one (point, realisation): ``runner(data, metrics, keep_images) -> record``, with
        ``data`` the point's scenario as plain data and the record ``{"status": "ok" or why not,
        "metrics": {name: float}, "seconds": float}`` (optionally ``images`` and ``payload``);
        importable on the workers. :func:`salkit.systems.study.run_point` runs a scenario's
        workflow; a system's own loop passes its point function.
    client : dask.distributed.Client, optional
    checkpoint : path, optional
    progress : callable, optional
    images : path, optional
        Keep each run's images there, as ``p<point>_r<realisation>_<name>.nc``.
    collect : dict, optional
        Receives each run's ``payload`` (what a runner returns beside its metrics: images, curves),
        by (point, realisation); payloads are neither checkpointed nor assembled.

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    ScenarioError
        When every point is invalid.
    """
    require_valid(plan, invalid)
    store = Checkpoint(checkpoint, plan) if checkpoint is not None else None
    records = store.done() if store is not None else {}
    todo = [(i, r) for i in range(plan.n_points) if i not in invalid for r in range(plan.realisations)
            if (i, r) not in records]
    total, done = plan.n_points * plan.realisations - len(invalid) * plan.realisations, len(records)
    t0 = time.perf_counter()

    def keep(i, r, rec):
        nonlocal done
        for name, ds in rec.pop("images", {}).items():
            write_dataset(ds, Path(images) / f"p{i:06d}_r{r:04d}_{name}")
        payload = rec.pop("payload", None)
        if collect is not None:
            collect[(i, r)] = payload
        records[(i, r)] = rec
        if store is not None:
            store.store(i, r, rec)
        done += 1
        if progress is not None:
            progress(done, total)

    if progress is not None:
        progress(done, total)
    if client is None:
        for i, r in todo:
            keep(i, r, runner(plan.point_data(i, r), plan.metrics, images is not None))
    else:
        futures = {client.submit(_point_task, runner, plan.point_data(i, r), plan.metrics, images is not None, pure=False,
                                 key=f"salkit-sweep-{plan.fingerprint()[:12]}-{i}-{r}"): (i, r) for i, r in todo}
        for fut in _dask_distributed.as_completed(futures):
            i, r = futures[fut]
            keep(i, r, fut.result())
            fut.release()
    ds = assemble(plan, invalid, records)
    ds.attrs["sweep_seconds"] = float(time.perf_counter() - t0)
    return ds


def _point_task(runner, *args):
    """Dask task: one point of a sweep, its kernels on the worker's numba threads."""
    task_numba_threads()
    return runner(*args)


def require_ok(ds: xr.Dataset, what: str) -> xr.Dataset:
    """A system's own loop needs every point: the first failure's reason raised, naming the loop.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`execute`.
    what : str
        The loop, for the message.

    Returns
    -------
    xarray.Dataset
        ``ds``.

    Raises
    ------
    SalkitError
        When a point is not "ok".
    """
    bad = sorted({str(v) for v in ds["status"].values if v != "ok"})
    if bad:
        raise SalkitError(f"{what}: {bad[0]}")
    return ds


def assemble(plan: SweepPlan, invalid: dict, records: dict) -> xr.Dataset:
    """The sweep's dataset: one variable per metric (float64, NaN where a run has none), dims the
    varied fields (``point`` when zipped) and ``realisation``; ``status`` per point ("ok", or why
    it could not run); ``unmeasured`` per point (the metrics it could not measure, each with why, or
    ""); the base scenario and the definition in the attributes.

    Parameters
    ----------
    plan : SweepPlan
    invalid : dict
        Point -> reason.
    records : dict
        (point, realisation) -> a runner's record (:func:`execute`).

    Returns
    -------
    xarray.Dataset
    """
    names = sorted({k for rec in records.values() for k in rec["metrics"]})
    shape = plan.shape + (plan.realisations,)
    data = {n: np.full(shape, np.nan) for n in names}
    status = np.full(plan.shape, "ok", dtype=object)
    unmeasured = np.full(plan.shape, "", dtype=object)
    seconds = np.full(shape, np.nan)
    for i in range(plan.n_points):
        idx = (i,) if plan.zipped else np.unravel_index(i, plan.shape)
        if i in invalid:
            status[idx] = f"invalid: {invalid[i]}"
            continue
        for r in range(plan.realisations):
            rec = records.get((i, r))
            if rec is None:
                status[idx] = "missing"
                continue
            if rec["status"] != "ok":
                status[idx] = rec["status"]
            seconds[idx + (r,)] = rec.get("seconds", np.nan)
            if rec.get("unmeasured") and not unmeasured[idx]:
                by_reason: dict = {}
                for k, v in sorted(rec["unmeasured"].items()):
                    by_reason.setdefault(v, []).append(k)
                unmeasured[idx] = "; ".join(f"{', '.join(ks)}: {why}" for why, ks in by_reason.items())
            for k, v in rec["metrics"].items():
                data[k][idx + (r,)] = v
    if plan.zipped:
        dims = ("point",)
        coords = {"point": np.arange(plan.n_points)}
        for a in plan.axes:
            coords[a.field] = ("point", np.asarray(a.values), _axis_attrs(a))
    else:
        dims = tuple(a.field for a in plan.axes)
        coords = {a.field: (a.field, np.asarray(a.values), _axis_attrs(a)) for a in plan.axes}
    coords["realisation"] = np.arange(plan.realisations)
    vars_ = {n: (dims + ("realisation",), data[n], {"units": unit_of(n) or "1"}) for n in names}
    vars_["status"] = (dims, status.astype(str))
    vars_["unmeasured"] = (dims, unmeasured.astype(str), {"long_name": "metrics a point could not measure, and why"})
    vars_["run_seconds"] = (dims + ("realisation",), seconds, {"units": "s"})
    attrs = {"salkit_kind": "sweep", "salkit_version": __version__, "scenario": dump_scenario(parse_scenario(plan.base)),
             "sweep": json.dumps(plan.definition()), "points": plan.n_points, "points_invalid": len(invalid),
             "realisations": plan.realisations}
    return xr.Dataset(vars_, coords=coords, attrs=attrs)


def _axis_attrs(a) -> dict:
    unit = unit_of(a.field.split(".")[-1]) if a.numeric else ""
    return {"units": unit or "1", "scale": a.scale, "spec": a.spec}


#: Metrics whose theory is an ensemble mean (a random quantity's expectation): a sweep compares the
#: mean over the realisations with it, within its standard error; the others compare the median.
THEORY_IS_MEAN = ("strehl_at_target", "peak_power_loss")


def summary(ds: xr.Dataset) -> dict:
    """Flat numbers of a sweep for ``metrics.json``: counts, time, and for each metric with a
    theory the largest deviation from it of the statistic theory predicts, ``|stat / theory - 1|``
    (``*_over_theory_max_deviation``; for a level in dB the difference, ``*_minus_theory_max_db``):
    the mean over the realisations for :data:`THEORY_IS_MEAN` (with the standard error of that mean
    at the worst point, ``*_over_theory_max_deviation_se``), the median for the others;
    ``*_theory_statistic`` says which.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`assemble`.

    Returns
    -------
    dict
    """
    ok = ds["status"].values == "ok"
    out = {"sweep_points": int(ds.attrs["points"]), "sweep_points_ok": int(ok.sum()),
           "sweep_points_invalid": int(ds.attrs["points_invalid"]), "sweep_realisations": int(ds.attrs["realisations"]),
           "sweep_seconds": float(ds.attrs.get("sweep_seconds", np.nan)),
           "sweep_run_seconds_median": float(np.nanmedian(ds["run_seconds"].values))
           if np.isfinite(ds["run_seconds"].values).any() else float("nan")}
    base = parse_scenario(yaml.safe_load(ds.attrs["scenario"]))
    # theory is the unperturbed limit where turbulence or a phase error perturbs the image: no verdict
    out["sweep_perturbed"] = int(not base.is_downlooking and (base.atmosphere is not None
                                                             or base.platform.phase_error is not None))
    # a target in a scene: its sidelobes hold the scene (salkit.report.judge.CLUTTER_WHY)
    out["sweep_in_clutter"] = int(not base.is_downlooking and base.scene.extended is not None)
    for name in measured_metrics(ds):
        t = theory_name(name)
        if t in ds.data_vars:
            mean = name in THEORY_IS_MEAN
            v = ds[name]
            stat = (v.mean("realisation", skipna=True) if mean else v.median("realisation", skipna=True)).values
            th = (ds[t].mean("realisation", skipna=True) if mean else ds[t].median("realisation", skipna=True)).values
            if name.endswith("_db"):  # levels in dB differ from theory by dB, not by a ratio
                dev = np.abs(stat - th)
                if np.isfinite(dev).any():
                    out[f"{name}_minus_theory_max_db"] = float(np.nanmax(dev))
                continue
            with np.errstate(divide="ignore", invalid="ignore"):
                dev = np.abs(stat / th - 1)
            if np.isfinite(dev).any():
                k = int(np.nanargmax(dev))
                out[f"{name}_over_theory_max_deviation"] = float(dev.flat[k])
                out[f"{name}_theory_statistic"] = "mean" if mean else "median"
                if mean:
                    n = v.count("realisation").values.flat[k]
                    sd = v.std("realisation", ddof=1, skipna=True).values.flat[k] if n > 1 else np.nan
                    out[f"{name}_over_theory_max_deviation_se"] = float(sd / np.sqrt(n) / abs(th.flat[k]))
    return out


def measured_metrics(ds: xr.Dataset) -> list[str]:
    """The measured metrics of a sweep (not theory values, not the status or run times).

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    list of str
    """
    theories = {theory_name(n) for n in ds.data_vars}
    return [n for n in ds.data_vars if n not in ("status", "run_seconds", "unmeasured") and n not in theories
            and "_theory" not in n]


def table(ds: xr.Dataset) -> str:
    """The sweep as CSV: one row per point, its varied values, status, and each metric's median.

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    str
    """
    axes = json.loads(ds.attrs["sweep"])["axes"]
    fields = [a["field"] for a in axes]
    names = [n for n in ds.data_vars if n not in ("status", "run_seconds", "unmeasured")]
    med = {n: ds[n].median("realisation", skipna=True) for n in names}
    lines = [",".join(fields + ["status"] + names)]
    st = ds["status"]
    for idx in np.ndindex(st.shape):
        sel = dict(zip(st.dims, idx))
        vals = [str(ds[f].isel({k: v for k, v in sel.items() if k in ds[f].dims}).item()) for f in fields]
        row = vals + ['"' + str(st.values[idx]).replace('"', "'") + '"'] + [f"{float(med[n].isel(sel)):.6g}" for n in names]
        lines.append(",".join(row))
    return "\n".join(lines) + "\n"
