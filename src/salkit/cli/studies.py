"""``salkit sweep``: a parameter sweep with realisations on Dask, checkpointed, into a folder with
``sweep.nc``, figures, ``metrics.json`` and ``report.html``."""
from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from ..errors import ScenarioError, require_scenario_file
from .app import _Bar, _command_line, _guard, out


@_guard
def sweep(scenario: Path = typer.Argument(..., metavar="SCENARIO.yaml", help="base scenario file, or a sweep file (examples/sweeps/)"),
          vary: List[str] = typer.Option([], "--vary", metavar="FIELD=SPEC", help="a field as --set names it and its values: v1,v2,... | lin:START:STOP:N | log:START:STOP:N (SI units); repeatable: the full grid"),
          zip_: bool = typer.Option(False, "--zip", help="pair the --vary axes (equal lengths) instead of spanning the grid"),
          realisations: Optional[int] = typer.Option(None, "--realisations", metavar="N", help="realisations per point (common random numbers: every point sees the same ones); default 1 or the sweep file's"),
          metric: List[str] = typer.Option([], "--metric", metavar="NAME", help="keep this metric (and its theory); repeatable; default: every numeric metric"),
          out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder (complete or absent after the run)"),
          set_: List[str] = typer.Option([], "--set", metavar="KEY=VALUE", help="override a field of the base scenario in its SI unit; repeatable"),
          workers: Optional[int] = typer.Option(None, metavar="N", help="Dask worker processes of a local cluster (default: one per core; 0: in this process)"),
          scheduler: Optional[str] = typer.Option(None, metavar="ADDRESS", help="address of an existing Dask scheduler, e.g. tcp://host:8786"),
          resume: bool = typer.Option(False, "--resume", help="continue an interrupted sweep into --out: only what is missing runs"),
          overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new sweep is complete"),
          keep_images: bool = typer.Option(False, "--keep-images", help="also keep every run's image in DIR/images/ (p<point>_r<realisation>_image.nc)")):
    """Sweep scenario fields (a grid or zipped axes) with realisations: every metric against them,
    median and spread, theory beside it, in sweep.nc and report.html."""
    require_scenario_file(scenario)  # before the library loads (3 s of imports on a slow core)
    from ..io.runfolder import RunFolder
    from ..report.sweeps import CHECKPOINT, IMAGES, run_sweep
    from ..systems.study import prepare
    from ..studies.spec import resolve_request
    if realisations is not None and realisations < 1:
        raise ScenarioError("--realisations", realisations, "must be >= 1")
    if workers is not None and workers < 0:
        raise ScenarioError("--workers", workers, "must be >= 0")
    request = resolve_request(scenario, vary, set_, zip_, realisations, metric)
    sc, plan, invalid = prepare(request)  # every point checked before any work
    for i, why in invalid.items():
        out.print(f"[yellow]invalid point {i}[/] ({', '.join(plan.overrides(i))}): {why}", highlight=False,
                  soft_wrap=True)
    if resume and not overwrite and (Path(out_dir) / "sweep.nc").is_file():
        raise ScenarioError("--resume", str(out_dir), "the sweep there is complete (sweep.nc): nothing to resume; "
                            "choose a new folder, or --overwrite to run it again")
    folder = RunFolder(out_dir, overwrite=overwrite, keep_on_failure=(CHECKPOINT, IMAGES))
    folder._check_target()
    if not resume:  # an old interrupted sweep: only --resume continues it
        folder.discard_resume()
    with folder as tmp:
        if resume:
            folder.adopt_stale(CHECKPOINT)
        with _Bar() as bar:
            m = run_sweep(sc, plan, invalid, tmp, workers=workers, scheduler=scheduler, progress=bar,
                          command=_command_line(), keep_images=keep_images, name=request.name,
                          description=request.description or None)
    n = m["sweep_realisations"]
    out.print(f"{m['sweep_points_ok']} of {m['sweep_points']} points x {n} realisation{'s' if n != 1 else ''} in "
              f"{m['sweep_seconds']:.1f} s; report: {Path(out_dir) / 'report.html'}", highlight=False)
