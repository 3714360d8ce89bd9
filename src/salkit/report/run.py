"""Writing a run: :func:`write_run` takes a :class:`~salkit.systems.result.RunResult` and writes
every file (datasets, tables, figures, ``metrics.json``, ``scenario.yaml``, ``report.html``);
:func:`run_scenario` runs a scenario's workflow and writes it."""
from __future__ import annotations

from pathlib import Path

from ..io.writing import write_dataset, write_json_atomic, write_text_atomic
from ..params.scenario import dump_scenario
from ..systems import run_workflow
from ..systems.result import Progress, RunResult
from .writers import WRITERS


def write_run(result: RunResult, out_dir: str | Path, *, command: str | None = None,
              index: str | None = None) -> dict:
    """Write everything a workflow computed into ``out_dir``: ``scenario.yaml``, the datasets
    (NetCDF) and tables (CSV), ``metrics.json``, the figures and ``report.html``, each atomically.

    Parameters
    ----------
    result : RunResult
    out_dir : path
    command : str, optional
        The command line shown on the report (default: the Python API).
    index : str, optional
        Relative link from the report to an index page of several runs.

    Returns
    -------
    dict
        The metrics written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    scen = out / "scenario.yaml"
    if not (scen.is_file() and scen.read_text() == result.scenario_text):  # run_scenario wrote it first
        write_text_atomic(scen, result.scenario_text)
    for name, ds in result.datasets.items():
        src = ds.encoding.get("source")
        if src and Path(src).resolve() == (out / name).resolve():
            continue  # written tile by tile where it belongs (an image larger than memory)
        write_dataset(ds, out / name)
    for name, text in result.tables.items():
        write_text_atomic(out / name, text)
    write_json_atomic(out / "metrics.json", result.metrics)
    WRITERS[result.system](result, out, {"command": command, "index": index})
    return result.metrics


def run_scenario(scenario, out_dir: str | Path, progress: Progress = None, *, command: str | None = None,
                 index: str | None = None) -> dict:
    """Run a scenario's workflow (:func:`salkit.systems.run_workflow`) and write it into
    ``out_dir`` (:func:`write_run`).

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
    out_dir : path
        Also the place of a workflow's checkpoints (the space-borne ``stack.zarr``).
    progress : callable, optional
        ``progress(stage, done, total)``.
    command, index : str, optional
        As :func:`write_run`.

    Returns
    -------
    dict
        The metrics.
    """
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    write_text_atomic(Path(out_dir) / "scenario.yaml", dump_scenario(scenario))  # what is running, first
    return write_run(run_workflow(scenario, out_dir, progress), out_dir, command=command, index=index)
