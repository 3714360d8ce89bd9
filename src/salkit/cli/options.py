"""Helpers the commands share: the output-file and grid options, the scene origin, the checks
before any work, the headline printed after a run, sarkit's checks reported."""
from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

import typer

from .app import err, out


def _examples_dir() -> Path:
    from ..params.scenario import examples_dir
    return examples_dir()


def _grid(nx, ny, dx, dy, plane):
    from pydantic import ValidationError

    from ..errors import ScenarioError
    from ..params.models import Grid
    if nx is None and ny is None and dx is None and dy is None:
        return None
    if None in (nx, ny, dx, dy):
        given = ", ".join(f"--{k}={v}" for k, v in zip(("nx", "ny", "dx", "dy"), (nx, ny, dx, dy)) if v is not None)
        missing = ", ".join(f"--{k}" for k, v in zip(("nx", "ny", "dx", "dy"), (nx, ny, dx, dy)) if v is None)
        raise ScenarioError("--nx/--ny/--dx/--dy", given,
                            f"a grid needs all four options or none; missing {missing}")
    try:
        return Grid(nx=nx, ny=ny, dx=dx, dy=dy, plane=plane)
    except ValidationError as e:
        f = e.errors()[0]
        raise ScenarioError(f"--{f['loc'][0]}", f.get("input"), f["msg"]) from None


def _check_out_file(path: Path, overwrite: bool, field: str = "--out", suffixes: tuple = ()) -> None:
    from ..errors import ScenarioError
    if str(path).strip() in ("", "."):
        raise ScenarioError(field, str(path), "must name a file")
    if path.is_dir():
        raise ScenarioError(field, str(path), "is a folder; give a file name")
    if path.exists() and not overwrite:
        raise ScenarioError(field, str(path), "exists; pass --overwrite to replace it")
    if suffixes and path.suffix.lower() not in suffixes:  # a file salkit could not read back
        raise ScenarioError(field, str(path), f"must end in {', '.join(suffixes)} (the file is NetCDF; salkit reads "
                                              f"it back by its suffix): e.g. {path.with_suffix('.nc').name}")


def _origin(origin: Optional[str]):
    from ..errors import ScenarioError
    if origin is None:
        return None
    try:
        llh = [float(v) for v in origin.split(",")]
        assert len(llh) == 3 and abs(llh[0]) <= 90 and -180 <= llh[1] <= 360 and all(map(math.isfinite, llh))
    except (ValueError, AssertionError):
        raise ScenarioError("--origin", origin, "must be LAT,LON,HAE (deg, deg, m) with |LAT| <= 90") from None
    return llh


def apply_memory_limit(text: Optional[str]) -> None:
    """``--memory-limit SIZE``: the memory budget of this command (the smaller of it and
    ``--max-memory``); jobs beyond it run in tiles where they can, and are refused where they cannot.

    Parameters
    ----------
    text : str or None
        The size as given (``512MiB``, ``4GiB``, bytes); None leaves the budget as it is.
    """
    if text is None:
        return
    from ..resources import parse_size, set_limit, user_limit
    b = parse_size(text, "--memory-limit")
    cap = user_limit()
    set_limit(b if cap is None else min(b, cap))


def _preflight(sc) -> None:
    """Every check that needs no work (:func:`salkit.systems.preflight.preflight`), its warnings printed."""
    from ..systems.preflight import preflight
    for w in preflight(sc):  # sampling errors stop here, before any work
        out.print(f"[yellow]warning:[/] {w}", highlight=False)


def print_headline(m: dict) -> None:
    """Print a run's headline figures of merit against theory (:func:`salkit.report.index.headline`),
    coloured by whether each is within the test suite's tolerance.

    Parameters
    ----------
    m : dict
        The run's metrics.
    """
    from ..report.judge import headline, verdict
    for i in headline(m):
        v = verdict(i["ok"])
        mark = f"[{v['colour']}]{v['word']}[/]" + (f" ({i['why']})" if i["ok"] is None else "")
        out.print(f"  {i['label']:<34} {i['measured']:>10}  {i['reference']:<26} {i['delta']:<13} {mark}",
                  highlight=False, soft_wrap=True)


def _summary(m: dict, out_dir: Path):
    print_headline(m)
    out.print(f"report: {Path(out_dir) / 'report.html'}", highlight=False)


def _report_check(res: dict) -> None:
    """Print a sarkit consistency check's warnings; its errors exit 1 (salkit wrote a bad file)."""
    for w in res["warnings"]:
        out.print(f"[yellow]sarkit warning:[/] {w}", highlight=False)
    if res["errors"]:
        for e in res["errors"]:
            err.print(f"[red]sarkit error:[/] {e}", highlight=False)
        raise typer.Exit(code=1)


#: The refusal of an export that would place data on the earth without knowing where.
NO_ORIGIN = ("the data have no geographic reference (no scene.origin in their scenario, no origin_llh in the file): "
             "give --origin LAT,LON,HAE (WGS84 deg, deg, m) for the scene centre; salkit does not place them at "
             "latitude 0, longitude 0")


def _export_sicd(src: Path, dst: Path, origin: Optional[str]) -> None:
    from ..errors import ScenarioError
    from ..io import check_sicd, read_image, write_sicd
    img = read_image(src)
    if origin is None and "origin_llh" not in img.attrs:
        raise ScenarioError("--origin", None, NO_ORIGIN)
    write_sicd(img, dst, origin=_origin(origin))
    _report_check(check_sicd(dst))
    out.print(f"wrote {dst} (SICD 1.3.0; sarkit consistency check: 0 errors)", highlight=False)


def _check_dask_options(workers: Optional[int], scheduler: Optional[str]) -> None:
    """``--workers`` and ``--scheduler`` checked before any work (the address's form: the stack's
    rule)."""
    from ..errors import ScenarioError
    from ..params.models import StackSettings
    if workers is not None and workers < 1:
        raise ScenarioError("--workers", workers, "must be >= 1")
    if scheduler is not None:
        try:
            StackSettings(scheduler=scheduler)
        except ValueError as e:
            raise ScenarioError("--scheduler", scheduler, "must look like tcp://HOST:PORT (or HOST:PORT)") from e
