"""``salkit run`` (a scenario into a complete report folder) and ``salkit simulate`` (raw data only)."""
from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from .app import _Bar, _command_line, _guard, out
from .options import _check_out_file, _preflight, _summary, apply_memory_limit


@_guard
def run(scenario: Path = typer.Argument(..., metavar="SCENARIO.yaml", help="scenario file (salkit examples lists the shipped ones)"),
        out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder (complete or absent after the run)"),
        set_: List[str] = typer.Option([], "--set", metavar="KEY=VALUE", help="override a field in its SI unit, e.g. waveform.prf=2000 (Hz); repeatable"),
        algorithm: Optional[str] = typer.Option(None, metavar="NAME", help="override processing.algorithm: bp | pfa | omegak | ffbp | exact"),
        workers: Optional[int] = typer.Option(None, metavar="N", help="Dask worker processes of a local cluster (stacking runs; default: one per core)"),
        scheduler: Optional[str] = typer.Option(None, metavar="ADDRESS", help="address of an existing Dask scheduler, e.g. tcp://host:8786"),
        overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new run is complete"),
        dry_run: bool = typer.Option(False, "--dry-run", help="validate the scenario, sampling and memory; write nothing"),
        memory_limit: Optional[str] = typer.Option(None, "--memory-limit", metavar="SIZE", help="memory budget, e.g. 512MiB or 4GiB (default: what is available): focusing beyond it runs in tiles of the image (bp, ffbp)")):
    """Simulate, focus, measure, draw and report one scenario (into a folder that is complete or absent)."""
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
             overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Simulate raw dechirped data and write it to a NetCDF file."""
    from ..io import write_dataset
    from ..params import load_scenario
    from ..simulate import simulate as sim
    _check_out_file(out, overwrite)
    sc = load_scenario(scenario, list(set_))
    _preflight(sc)
    with _Bar() as bar:
        raw = sim(sc, progress=lambda d, n: bar("pulses simulated", d, n))
    write_dataset(raw, out)
    if sc.is_downlooking:
        globals()["out"].print(f"wrote {out} ({raw.sizes['scan']} scans x {raw.sizes['fast_time']} samples)")
    else:
        globals()["out"].print(f"wrote {out} ({raw.sizes['slow_time']} pulses x {raw.sizes['fast_time']} samples)")
