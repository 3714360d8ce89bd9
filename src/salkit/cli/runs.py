"""``salkit run`` (a scenario into a complete report folder) and ``salkit simulate`` (raw data only)."""
from __future__ import annotations

import logging
from pathlib import Path
from typing import List, Optional

import typer

from ..errors import require_scenario_file
from .app import _Bar, _command_line, _guard, out
from .options import _check_dask_options, _check_out_file, _preflight, _summary, apply_memory_limit


@_guard
def run(scenario: Path = typer.Argument(..., metavar="SCENARIO.yaml", help="scenario file (salkit examples lists the shipped ones)"),
        out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder (complete or absent after the run)"),
        set_: List[str] = typer.Option([], "--set", metavar="KEY=VALUE", help="override a field in its SI unit, e.g. waveform.prf=2000 (Hz); repeatable"),
        algorithm: Optional[str] = typer.Option(None, metavar="NAME", help="override processing.algorithm: {formers}"),
        workers: Optional[int] = typer.Option(None, metavar="N", help="worker processes of the local Dask cluster a stacking run starts (default: the scenario's stack.workers, 2 if unset); 0: the sub-images in this process, no cluster"),
        scheduler: Optional[str] = typer.Option(None, metavar="ADDRESS", help="address of an existing Dask scheduler, e.g. tcp://host:8786"),
        overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new run is complete"),
        dry_run: bool = typer.Option(False, "--dry-run", help="validate the scenario, sampling and memory; write nothing"),
        memory_limit: Optional[str] = typer.Option(None, "--memory-limit", metavar="SIZE", help="memory budget, e.g. 512MiB or 4GiB (default: what is available): focusing beyond it runs in tiles of the image (bp, ffbp)")):
    """Simulate, focus, measure, draw and report one scenario (into a folder that is complete or absent)."""
    require_scenario_file(scenario)  # before the library loads (3 s of imports on a slow core)
    from ..io.runfolder import RunFolder
    from ..params import load_scenario
    from ..report import run_scenario
    sets = list(set_) + ([f"processing.algorithm={algorithm}"] if algorithm else [])
    sets += [f"stack.workers={workers}"] if workers is not None else []
    sets += [f"stack.scheduler={scheduler}"] if scheduler is not None else []
    sc = load_scenario(scenario, sets)
    apply_memory_limit(memory_limit)
    _preflight(sc)
    if dry_run:
        out.print(f"{scenario}: valid; sampling and memory checks passed; nothing written", highlight=False)
        return
    with RunFolder(out_dir, overwrite=overwrite, keep_on_failure=("stack.zarr",)) as tmp:
        with _Bar() as bar:
            m = run_scenario(sc, tmp, progress=bar, command=_command_line())
    _summary(m, out_dir)


@_guard
def simulate(scenario: Path = typer.Argument(..., metavar="SCENARIO.yaml", help="scenario file"),
             out: Path = typer.Option(..., "--out", metavar="FILE.nc", help="raw NetCDF file to write (complex echoes, slow time x fast time, s)"),
             set_: List[str] = typer.Option([], "--set", metavar="KEY=VALUE", help="override a field in its SI unit, e.g. waveform.prf=2000 (Hz); repeatable"),
             overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file"),
             memory_limit: Optional[str] = typer.Option(None, "--memory-limit", metavar="SIZE", help="memory budget, e.g. 4GiB (default: what is available): a history bigger than it is simulated and written a block of pulses at a time (the same numbers)"),
             workers: Optional[int] = typer.Option(None, metavar="N", help="compute the blocks of pulses on a local Dask cluster of N worker processes (the same numbers; each worker holds the scene)"),
             scheduler: Optional[str] = typer.Option(None, metavar="ADDRESS", help="compute the blocks on an existing Dask cluster, e.g. tcp://host:8786 (mesh files at paths the workers reach)")):
    """Simulate raw dechirped data and write it to a NetCDF file."""
    require_scenario_file(scenario)  # before the library loads (3 s of imports on a slow core)
    from ..focus.pipeline import memory_budget
    from ..io import write_dataset
    from ..params import load_scenario
    from ..resources import size_text
    from ..simulate import simulate as sim
    from ..simulate.echoes import memory_estimate, signal_shape
    from ..simulate.sal import simulate_to_file
    from ..io.formats import NETCDF_SUFFIXES
    _check_out_file(out, overwrite, suffixes=NETCDF_SUFFIXES)
    sc = load_scenario(scenario, list(set_))
    apply_memory_limit(memory_limit)
    if workers is not None or scheduler is not None:
        _check_dask_options(workers, scheduler)
        if sc.is_downlooking:
            from ..errors import ScenarioError
            raise ScenarioError("--workers" if workers is not None else "--scheduler", workers or scheduler,
                                "down-looking data are simulated on this machine (no Dask)")
        _preflight(sc)
        from .data import _dask_or_not
        with _dask_or_not(workers, scheduler) as client, _Bar() as bar:
            simulate_to_file(sc, out, memory_limit=memory_budget(), client=client,
                             progress=lambda d, n: bar("pulses simulated", d, n))
        globals()["out"].print(f"wrote {out} (blocks of pulses on Dask workers)")
        return
    if not sc.is_downlooking:
        need, what = memory_estimate(sc)
        P, N = signal_shape(sc)
        budget = memory_budget()
        if need + 8.0 * P * N > budget:  # the history and the file's image in memory: in blocks instead
            logging.getLogger("salkit").info(
                "%s: about %s with the file written at once, more than the %s budget: simulated and "
                "written in blocks of pulses", what, size_text(need + 8.0 * P * N), size_text(budget))
            with _Bar() as bar:
                simulate_to_file(sc, out, memory_limit=budget, progress=lambda d, n: bar("pulses simulated", d, n))
            globals()["out"].print(f"wrote {out} (in blocks of pulses)")
            return
    _preflight(sc)
    with _Bar() as bar:
        raw = sim(sc, progress=lambda d, n: bar("pulses simulated", d, n))
    write_dataset(raw, out)
    if sc.is_downlooking:
        globals()["out"].print(f"wrote {out} ({raw.sizes['scan']} scans x {raw.sizes['fast_time']} samples)")
    else:
        globals()["out"].print(f"wrote {out} ({raw.sizes['slow_time']} pulses x {raw.sizes['fast_time']} samples)")
