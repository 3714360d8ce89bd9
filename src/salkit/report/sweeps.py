"""Running a sweep into a run folder: the points on Dask (or in this process), checkpointed in
``checkpoint/`` while it runs, then ``sweep.nc``, ``sweep.csv``, the figures, ``metrics.json`` and
``report.html`` (:func:`salkit.report.writers.write_sweep`)."""
from __future__ import annotations

import shutil
from pathlib import Path

from ..resources import dask_client
from ..studies.engine import execute
from ..systems.study import as_result, run_point
from .run import write_run

#: The folder of the checkpoint inside a sweep's run folder (removed once the sweep is written).
CHECKPOINT = "checkpoint"
#: The folder of every run's images with ``--keep-images``.
IMAGES = "images"


def run_sweep(scenario, plan, invalid: dict, out_dir, *, workers: int | None = None, scheduler: str | None = None,
              progress=None, command: str | None = None, index: str | None = None, keep_images: bool = False,
              name: str | None = None, description: str | None = None) -> dict:
    """Run a prepared sweep (:func:`salkit.systems.study.prepare`) and write it into ``out_dir``.

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
        The base scenario (its name and description head the report).
    plan : SweepPlan
    invalid : dict
        Point -> reason.
    out_dir : path
        The (temporary) run folder; a ``checkpoint`` folder already there is resumed.
    workers : int, optional
        Local Dask workers (default one per core; 0: this process).
    scheduler : str, optional
        An existing Dask scheduler's address.
    progress : callable, optional
        ``progress(stage, done, total)``.
    command, index : str, optional
        As :func:`salkit.report.write_run`.
    keep_images : bool
        Keep every run's images in ``images/`` (``p<point>_r<realisation>_image.nc``).
    name, description : str, optional
        The study's name and description (a sweep file's; default "sweep of SCENARIO over FIELDS"
        and the scenario's description): the report's title.

    Returns
    -------
    dict
        The sweep's metrics.

    A space-borne stacking scenario's sub-images run on the sweep's cluster too (nested tasks).
    """
    out = Path(out_dir)
    images = out / IMAGES if keep_images else None
    if images is not None:
        images.mkdir(exist_ok=True)
    tick = (lambda d, n: progress("runs", d, n)) if progress is not None else None
    if scheduler is None and workers == 0:
        ds = execute(plan, invalid, run_point, checkpoint=out / CHECKPOINT, progress=tick, images=images)
    else:
        with dask_client(scheduler, workers) as client:
            ds = execute(plan, invalid, run_point, client=client, checkpoint=out / CHECKPOINT, progress=tick, images=images)
    shutil.rmtree(out / CHECKPOINT)
    fields = ", ".join(a.field for a in plan.axes)
    title = f"study {name} (sweep of {scenario.name})" if name else f"sweep of {scenario.name} over {fields}"
    return write_run(as_result(ds, title, description or scenario.description), out, command=command, index=index)
