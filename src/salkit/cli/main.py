"""The ``salkit`` command: a thin layer over the library.

Bad input (scenario fields, data files, sampling) prints one clear line naming the field, the
value and the constraint, and exits with status 2, never a traceback.
"""
from __future__ import annotations

import functools
import json
import math
import sys
from pathlib import Path
from typing import List, Optional

import typer
from rich.console import Console
from rich.markup import escape as rich_escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from ..errors import SalkitError

app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False, rich_markup_mode=None,
                  help="salkit: synthetic aperture ladar simulation, imaging and metrics.")
err = Console(stderr=True)
out = Console()


def _plain_argument_help() -> None:
    """Typer 0.2x writes required arguments as ``{NAME}`` in the usage line and appends the Python
    type (``<path>``) to each; salkit's metavars already say what to give (``SCENARIO.yaml``), so
    the usage reads as click's convention. Skipped if a typer version lacks the hooks."""
    try:
        from typer.core import TyperArgument
    except ImportError:  # pragma: no cover
        return
    if hasattr(TyperArgument, "_usage_display_name") and hasattr(TyperArgument, "display_type_rich"):
        TyperArgument._usage_display_name = lambda self: self.display_name_raw + ("..." if self.nargs != 1 else "")
        TyperArgument.display_type_rich = lambda self, ctx: None


_plain_argument_help()

def _examples_dir() -> Path:
    from ..params.scenario import examples_dir
    return examples_dir()


_STATE = {"debug": False}


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """Every warning through one formatter on stderr: ``warning: <message>``, without the Python
    source line (installed as :func:`warnings.showwarning` by the command line).

    Parameters
    ----------
    message : Warning or str
    category : type
    filename : str
    lineno : int
    file, line : optional
        Unused (the signature of :func:`warnings.showwarning`).
    """
    err.print(f"[yellow]warning:[/] {rich_escape(str(message))}", highlight=False, soft_wrap=True)


def _say(msg: str) -> None:
    err.print(f"[bold red]error:[/] {rich_escape(msg)}", highlight=False, markup=True, soft_wrap=True)


def _guard(fn):
    """Exit 2 for bad input and usage, 1 for the environment (permissions, a full disk, memory, a
    busy folder), 130 when interrupted, each with one line; ``--debug`` shows the traceback."""
    @functools.wraps(fn)
    def wrapper(*a, **k):
        try:
            return fn(*a, **k)
        except (typer.Exit, typer.Abort, SystemExit):
            raise
        except SalkitError as e:
            if _STATE["debug"]:
                raise
            _say(str(e))
            raise typer.Exit(code=e.exit_code)
        except KeyboardInterrupt:
            err.print("interrupted: nothing was left behind")
            raise typer.Exit(code=130)
        except MemoryError:
            if _STATE["debug"]:
                raise
            _say("out of memory (the estimate before the work was too low); set --max-memory lower or reduce the job")
            raise typer.Exit(code=1)
        except OSError as e:
            if _STATE["debug"]:
                raise
            import errno as _errno
            why = "no space left on the device" if e.errno == _errno.ENOSPC else (e.strerror or str(e))
            _say(f"{why}{': ' + str(e.filename) if getattr(e, 'filename', None) else ''}")
            raise typer.Exit(code=1)
        except Exception as e:  # noqa: BLE001 - the promise: no traceback without --debug
            if _STATE["debug"]:
                raise
            _say(f"internal error ({type(e).__name__}: {e}); please report it; --debug shows the traceback")
            raise typer.Exit(code=1)
    return wrapper


def _version(value: bool):
    if value:
        from .. import __version__
        out.print(f"salkit {__version__}")
        raise typer.Exit()


@app.callback()
def _main(debug: bool = typer.Option(False, "--debug", help="show tracebacks"),
          max_memory: Optional[str] = typer.Option(None, "--max-memory", metavar="SIZE", help="refuse jobs whose estimated peak "
                                                   "memory exceeds this (e.g. 8GiB); default: what is available"),
          version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                       help="print the version and exit")):
    """salkit: synthetic aperture ladar simulation, imaging and metrics."""
    import warnings
    _STATE["debug"] = debug
    if not debug:
        warnings.showwarning = show_warning
    from ..resources import parse_size, set_limit
    try:
        set_limit(parse_size(max_memory) if max_memory is not None else None)
    except SalkitError as e:
        _say(str(e))
        raise typer.Exit(code=2)


class _Bar:
    """Rich progress bar driven by ``progress(stage, done, total)`` callbacks: one bar per stage,
    the stage named in the unit of its work (``pulses simulated``, ``sub-images``, ...), whose first
    word is the rate's unit (pulses/s). Bars of a run that completed end at 100 %."""

    def __init__(self):
        self.p = Progress(TextColumn("{task.description:<18}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                          TextColumn("[progress.percentage]{task.percentage:>3.0f}%"),
                          TextColumn("{task.fields[rate]}"), TimeElapsedColumn(), TimeRemainingColumn(),
                          console=err, transient=False)
        self.tasks = {}

    def __enter__(self):
        self.p.__enter__()
        return self

    def __exit__(self, *exc):
        if exc[0] is None:  # the work finished: stages that report only their start end full
            for tid in self.tasks.values():
                task = next(t for t in self.p.tasks if t.id == tid)
                if task.total is not None:
                    self.p.update(tid, completed=task.total)
        self.p.__exit__(*exc)

    def __call__(self, stage: str, done: int, total: int):
        from ..io.runfolder import INTERRUPTED
        if INTERRUPTED["signal"] is not None:
            raise KeyboardInterrupt(f"signal {INTERRUPTED['signal']}")
        if stage not in self.tasks:
            self.tasks[stage] = self.p.add_task(stage, total=total, rate="")
        elapsed = next(t.elapsed for t in self.p.tasks if t.id == self.tasks[stage]) or 0.0
        unit = stage.split()[0]
        rate = f"{done / elapsed:.3g} {unit}/s" if elapsed > 0 and done else ""
        self.p.update(self.tasks[stage], completed=done, total=total, rate=rate)


def _command_line() -> str:
    """The command as typed (program name ``salkit``), quoted for a shell; inside a test runner,
    where :func:`main` did not run, the command's path alone."""
    import shlex
    import click
    if _STATE.get("argv") is not None:
        return shlex.join(["salkit", *_STATE["argv"]])
    ctx = click.get_current_context(silent=True)
    path = ctx.command_path.split(" ", 1)[-1] if ctx is not None else "command"
    return f"salkit {path} (arguments not recorded)"


def _grid(nx, ny, dx, dy, plane):
    from ..params.models import Grid
    from pydantic import ValidationError
    from ..errors import ScenarioError
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


@app.command()
@_guard
def run(scenario: Path = typer.Argument(..., metavar="SCENARIO.yaml", help="scenario file (salkit examples lists the shipped ones)"),
        out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder (complete or absent after the run)"),
        set_: List[str] = typer.Option([], "--set", metavar="KEY=VALUE", help="override a field in its SI unit, e.g. waveform.prf=2000 (Hz); repeatable"),
        algorithm: Optional[str] = typer.Option(None, metavar="NAME", help="override processing.algorithm: bp | pfa | omegak | ffbp | exact"),
        workers: Optional[int] = typer.Option(None, metavar="N", help="Dask worker processes of a local cluster (stacking runs; default: one per core)"),
        scheduler: Optional[str] = typer.Option(None, metavar="ADDRESS", help="address of an existing Dask scheduler, e.g. tcp://host:8786"),
        overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new run is complete"),
        dry_run: bool = typer.Option(False, "--dry-run", help="validate the scenario, sampling and memory; write nothing")):
    """Simulate, focus, measure, draw and report one scenario (into a folder that is complete or absent)."""
    from ..io.runfolder import RunFolder
    from ..params import load_scenario
    from ..report import run_scenario
    sets = list(set_) + ([f"processing.algorithm={algorithm}"] if algorithm else [])
    sets += [f"stack.workers={workers}"] if workers is not None else []
    sets += [f"stack.scheduler={scheduler}"] if scheduler is not None else []
    sc = load_scenario(scenario, sets)
    _preflight(sc)
    if dry_run:
        out.print(f"{scenario}: valid; sampling and memory checks passed; nothing written", highlight=False)
        return
    with RunFolder(out_dir, overwrite=overwrite, keep_on_failure=("stack.zarr",)) as tmp:
        with _Bar() as bar:
            m = run_scenario(sc, tmp, progress=bar, command=_command_line())
    _summary(m, out_dir)


def _preflight(sc) -> None:
    """Every check that needs no work: sampling (and the down-looking design), memory."""
    if sc.is_downlooking:
        from ..geometry.downlooking import design
        for w in design(sc.experiment).warnings:  # sampling errors stop here, before any work
            out.print(f"[yellow]warning:[/] {w}", highlight=False)
        return
    from ..resources import check_memory
    from ..focus import run_memory_estimate
    need, what = run_memory_estimate(sc)
    check_memory(need, what, "reduce receiver.adc_rate, platform.aperture_length, waveform.prf or the grid "
                 "(processing.grid.nx, ny)")
    if sc.experiment is None:
        from ..geometry import build_collection, check_sampling
        check_sampling(sc, build_collection(sc))
    atm = sc.atmosphere
    if atm is not None and atm.model == "wave_optics":  # plan every class's beam and screens before any work
        from ..geometry import build_collection
        from ..simulate import screen_size
        col = build_collection(sc)
        classes = getattr(sc.experiment, "classes", None) or {"atmosphere.cn2": atm.cn2}
        for cn2 in (c for c in classes.values() if c):
            n = screen_size(sc.model_copy(update={"atmosphere": atm.model_copy(update={"cn2": cn2})}), col)
            check_memory(atm.layers * n * n * 4.0, f"{atm.layers} phase screens of {n} x {n} (Cn2 = {cn2})",
                         "use fewer atmosphere.layers or a coarser atmosphere.screen_dx")


def print_headline(m: dict) -> None:
    """Print a run's headline figures of merit against theory (:func:`salkit.report.index.headline`),
    coloured by whether each is within the test suite's tolerance.

    Parameters
    ----------
    m : dict
        The run's metrics.
    """
    from ..report.index import headline
    for i in headline(m):
        mark = {True: "[green]ok[/]", False: "[red]outside tolerance[/]", None: ""}[i["ok"]]
        out.print(f"  {i['label']:<34} {i['measured']:>10}  {i['reference']:<26} {i['delta']:<13} {mark}",
                  highlight=False, soft_wrap=True)


def _summary(m: dict, out_dir: Path):
    print_headline(m)
    out.print(f"report: {Path(out_dir) / 'report.html'}", highlight=False)


@app.command()
@_guard
def simulate(scenario: Path = typer.Argument(..., metavar="SCENARIO.yaml", help="scenario file"),
             out: Path = typer.Option(..., "--out", metavar="FILE.nc", help="raw NetCDF file to write (complex echoes, slow time x fast time, s)"),
             set_: List[str] = typer.Option([], "--set", metavar="KEY=VALUE", help="override a field in its SI unit, e.g. waveform.prf=2000 (Hz); repeatable"),
             overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Simulate raw dechirped data and write it to a NetCDF file."""
    from ..params import load_scenario
    from ..simulate import simulate as sim
    from ..io import write_dataset
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


def _check_out_file(path: Path, overwrite: bool, field: str = "--out") -> None:
    from ..errors import ScenarioError
    if str(path).strip() in ("", "."):
        raise ScenarioError(field, str(path), "must name a file")
    if path.is_dir():
        raise ScenarioError(field, str(path), "is a folder; give a file name")
    if path.exists() and not overwrite:
        raise ScenarioError(field, str(path), "exists; pass --overwrite to replace it")


@app.command()
@_guard
def focus(raw: Path = typer.Argument(..., metavar="RAW", help="raw or phase-history file: .nc, .cphd or GOTCHA .mat"),
          out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder (complete or absent after the run)"),
          algorithm: Optional[str] = typer.Option(None, metavar="NAME", help="bp | pfa | omegak | ffbp (fast factorised backprojection, spotlight) | exact (float64 matched filter, the truth; small grids)"),
          accuracy: Optional[str] = typer.Option(None, metavar="LEVEL", help="standard | high (interferometric: bp -75.5 to -78.5 dB, ffbp -64 to -73 dB against the exact matched filter)"),
          window: Optional[str] = typer.Option(None, metavar="NAME", help="amplitude window: none | hamming | taylor"),
          nx: Optional[int] = typer.Option(None, metavar="PIXELS", help="grid size along azimuth, pixels (with --ny, --dx, --dy)"),
          ny: Optional[int] = typer.Option(None, metavar="PIXELS", help="grid size along range, pixels"),
          dx: Optional[float] = typer.Option(None, metavar="METRES", help="pixel spacing along azimuth, m (at most the resolution)"),
          dy: Optional[float] = typer.Option(None, metavar="METRES", help="pixel spacing along range, m (at most the resolution)"),
          plane: Optional[str] = typer.Option(None, metavar="NAME", help="image plane: slant | ground (alone: the default grid in that plane)"),
          autofocus: Optional[str] = typer.Option(None, metavar="NAME", help="none | pga | min-entropy (on the image) | pulse (one phase per pulse)"),
          kernel: Optional[str] = typer.Option(None, metavar="NAME", help="PGA phase-gradient kernel: pd | lumv | ev"),
          sicd: bool = typer.Option(False, "--sicd", help="also write the image as SICD (image.nitf), checked by sarkit"),
          overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new run is complete")):
    """Focus a raw file (.nc, .cphd or GOTCHA .mat) into image.nc, metrics.json, figures and report.html."""
    from ..report import write_run
    from ..systems.airborne import focus_file
    from ..choices import ACCURACY, ALGORITHMS, AUTOFOCUS_METHODS, PGA_KERNELS, PLANES, WINDOWS, check_choice
    for opt, v, allowed in (("--algorithm", algorithm, ALGORITHMS), ("--accuracy", accuracy, ACCURACY),
                            ("--window", window, WINDOWS),
                            ("--autofocus", autofocus, AUTOFOCUS_METHODS), ("--kernel", kernel, PGA_KERNELS),
                            ("--plane", plane, PLANES)):
        if v is not None:
            check_choice(opt, v, allowed)
    from ..io import open_dataset, read_phase_data
    if raw.suffix.lower() in (".cphd", ".mat"):
        probe = None
    else:
        probe = open_dataset(raw)
    from ..io.runfolder import RunFolder
    grid = _grid(nx, ny, dx, dy, plane or "slant")
    if probe is not None and probe.attrs.get("salkit_kind") == "raw_downlooking":
        from .. import plot
        from ..focus import focus as form_image
        from ..io import write_dataset
        image = form_image(probe, algorithm=algorithm, window_name=window, grid=grid, plane=plane, accuracy=accuracy)
        with RunFolder(out_dir, overwrite=overwrite) as tmp:
            write_dataset(image, tmp / "image.nc")
            plot.image_db(image, tmp / "image.png", title="DL-SAL eq-19 image")
        globals()["out"].print(f"wrote {Path(out_dir) / 'image.nc'}")
        return
    ds = read_phase_data(raw)
    if grid is None and plane is not None:
        src = "the scenario stored in the file" if "scenario" in ds.attrs else "the default (256 x 256 at 0.8 of the resolution)"
        out.print(f"--plane {plane} without --nx/--ny/--dx/--dy: grid size and spacing from {src}, "
                  f"in the {plane} plane", highlight=False)
    RunFolder(out_dir, overwrite=overwrite)._check_target()  # before any work
    with RunFolder(out_dir, overwrite=overwrite) as tmp:
        with _Bar() as bar:
            m = write_run(focus_file(ds, algorithm=algorithm, window_name=window, grid=grid, progress=bar,
                                     autofocus=autofocus, kernel=kernel, plane=plane, accuracy=accuracy), tmp,
                          command=_command_line())
        if sicd:
            _export_sicd(tmp / "image.nc", tmp / "image.nitf", None)
    _summary(m, out_dir)


def _export_sicd(src: Path, dst: Path, origin: Optional[str]) -> None:
    from ..io import check_sicd, read_image, write_sicd
    img = read_image(src)
    write_sicd(img, dst, origin=_origin(origin))
    _report_check(check_sicd(dst))
    out.print(f"wrote {dst} (SICD 1.3.0; sarkit consistency check: 0 errors)", highlight=False)


def _report_check(res: dict) -> None:
    """Print a sarkit consistency check's warnings; its errors exit 1 (salkit wrote a bad file)."""
    for w in res["warnings"]:
        out.print(f"[yellow]sarkit warning:[/] {w}", highlight=False)
    if res["errors"]:
        for e in res["errors"]:
            err.print(f"[red]sarkit error:[/] {e}", highlight=False)
        raise typer.Exit(code=1)


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


@app.command()
@_guard
def export(image: Path = typer.Argument(..., metavar="IMAGE.nc", help="salkit image file (image.nc of a run)"),
           dst: Path = typer.Argument(..., metavar="DST.nitf", help="SICD file to write (.nitf or .ntf)"),
           origin: Optional[str] = typer.Option(None, metavar="LAT,LON,HAE", help="scene centre as LAT,LON,HAE (deg, deg, m); default "
                                                "the image's origin_llh, else 0,0,0"),
           overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Export a focused image as SICD 1.3.0 (NITF), metadata from the image and its collection."""
    from ..errors import ScenarioError
    _check_out_file(dst, overwrite, "dst")
    if dst.suffix.lower() not in (".nitf", ".ntf"):
        raise ScenarioError("dst", str(dst), "SICD files end in .nitf or .ntf")
    _export_sicd(image, dst, origin)


@app.command()
@_guard
def convert(src: Path = typer.Argument(..., metavar="SRC", help="input: .nc (raw or phase history), .cphd or .mat (GOTCHA)"),
            dst: Path = typer.Argument(..., metavar="DST", help="output: .nc (phase history), .cphd or .mat"),
            origin: Optional[str] = typer.Option(None, metavar="LAT,LON,HAE", help="scene centre for CPHD as LAT,LON,HAE (deg, deg, m); "
                                                 "default the file's origin_llh, else 0,0,0"),
            check: bool = typer.Option(True, help="run sarkit's consistency checker on a written CPHD"),
            overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Convert phase histories between salkit NetCDF, CPHD and the GOTCHA .mat layout."""
    _check_out_file(dst, overwrite, "dst")
    from ..errors import ScenarioError
    from ..focus import range_compress
    from ..io import PHASE_SUFFIXES, check_cphd, read_phase_data, write_cphd, write_dataset, write_gotcha
    suf = dst.suffix.lower()
    if suf not in PHASE_SUFFIXES:
        raise ScenarioError("dst", str(dst), f"suffix must be one of {', '.join(PHASE_SUFFIXES)}")
    llh = _origin(origin)
    ds = read_phase_data(src)
    ph = range_compress(ds) if ds.attrs.get("salkit_kind") == "raw" else ds
    if suf == ".cphd":
        write_cphd(ph, dst, origin=llh)
        if check:
            _report_check(check_cphd(dst))
            out.print("sarkit CPHD consistency check: 0 errors", highlight=False)
    elif suf == ".mat":
        write_gotcha(ph, dst)
    else:
        write_dataset(ph, dst)
    out.print(f"wrote {dst} ({ph.sizes['slow_time']} pulses x {ph.sizes['frequency']} frequencies)")


@app.command()
@_guard
def screen(n: int = typer.Option(..., "--n", metavar="SAMPLES", help="screen size, samples per side"),
           dx: float = typer.Option(..., "--dx", metavar="METRES", help="sample spacing, m"),
           r0: float = typer.Option(..., "--r0", metavar="METRES", help="Fried parameter r0, m"),
           count: int = typer.Option(1, "--count", metavar="N", help="number of screens"),
           seed: int = typer.Option(0, "--seed", metavar="INT", help="random seed (the same seed gives the same screens)"),
           outer_scale: Optional[float] = typer.Option(None, "--outer-scale", metavar="METRES", help="von Karman outer scale L0, m (default: Kolmogorov, infinite)"),
           inner_scale: Optional[float] = typer.Option(None, "--inner-scale", metavar="METRES", help="inner scale l0, m (default: none)"),
           out: Path = typer.Option(..., "--out", metavar="FILE.nc", help="NetCDF file to write (phase in rad; a PNG of screen 0 beside it)"),
           overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Generate turbulence phase screens (rad) into a NetCDF file, with a picture of the first."""
    from ..atmosphere import phase_screens
    _check_out_file(out, overwrite)
    from ..io.screens import write_screens
    phi = phase_screens(n, dx, r0, count=count, seed=seed, outer_scale=outer_scale, inner_scale=inner_scale)
    from ..plot import screen_image
    nc = write_screens(phi, dx, out, r0=r0, seed=seed, outer_scale=outer_scale, inner_scale=inner_scale)
    png = screen_image(phi[0], dx, out.with_suffix(".png"), title=f"phase screen 0 (r0 = {r0} m)")
    globals()["out"].print(f"wrote {nc} ({count} screens of {n} x {n}) and {png}")


#: Attributes stored as 0/1 (NetCDF has no booleans) that mean yes/no.
FLAG_KEYS = frozenset({"iq", "wavelength_derived", "design_wavelength_derived", "speckle", "beam_weighting",
                       "rvp_removed", "noise_added"})


def _typed(d):
    """JSON-ready values: NumPy scalars and arrays as numbers and lists, flags as booleans."""
    import numpy as np
    if isinstance(d, dict):
        return {k: (bool(v) if k in FLAG_KEYS and isinstance(v, (int, np.integer, bool, np.bool_)) else _typed(v))
                for k, v in d.items()}
    if isinstance(d, (list, tuple)):
        return [_typed(v) for v in d]
    if isinstance(d, np.ndarray):
        return d.tolist()
    if isinstance(d, np.generic):
        return d.item()
    return d


def _with_units(d: dict) -> dict:
    """``d`` with a ``units`` map: every key whose unit is known (:func:`salkit.units.unit_of`)."""
    from ..units import unit_of
    def numeric(v):
        return (isinstance(v, (int, float)) and not isinstance(v, bool)) or (
            isinstance(v, list) and bool(v) and all(numeric(x) for x in v))
    units = {k: unit_of(k) for k, v in d.items() if numeric(v) and unit_of(k)}
    return {**d, "units": units}


@app.command()
@_guard
def propagate(wave: str = typer.Option("plane", "--wave", metavar="KIND", help="plane | spherical (a point source)"),
              wavelength: float = typer.Option(..., "--wavelength", metavar="METRES", help="wavelength, m"),
              cn2: float = typer.Option(..., "--cn2", metavar="M^-2/3", help="refractive-index structure constant Cn2, m^(-2/3), uniform on the path"),
              distance: float = typer.Option(..., "--distance", metavar="METRES", help="path length, m"),
              layers: Optional[int] = typer.Option(None, "--layers", metavar="N", help="phase screens (default: as many as keep each weak, at least 10)"),
              count: int = typer.Option(16, "--count", metavar="K", help="realisations"),
              seed: int = typer.Option(0, "--seed", metavar="INT", help="random seed"),
              inner_scale: Optional[float] = typer.Option(None, "--inner-scale", metavar="METRES", help="inner scale l0 of the modified atmospheric spectrum, m (plane waves; default 0: Kolmogorov)"),
              out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder: field.nc and metrics.json"),
              overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new run is complete")):
    """Propagate a wave through turbulence (split-step wave optics): the received field and its
    scintillation against theory."""
    from ..errors import ScenarioError
    from ..atmosphere.waveoptics import propagation_result
    from ..io import write_dataset
    from ..io.datasets import write_json_atomic
    from ..io.runfolder import RunFolder
    for name, v, ok, rule in (("--wavelength", wavelength, 0 < wavelength < 1e-3, "must be in (0, 1 mm)"),
                              ("--cn2", cn2, 0 <= cn2 < 1e-10, "must be in [0, 1e-10) m^(-2/3)"),
                              ("--distance", distance, 0 < distance <= 1e6, "must be in (0, 1000 km]"),
                              ("--count", count, count >= 1, "must be >= 1"),
                              ("--layers", layers, layers is None or layers >= 1, "must be >= 1"),
                              ("--inner-scale", inner_scale, inner_scale is None or 0 < inner_scale < 1.0,
                               "must be in (0, 1 m)"),
                              ("--inner-scale", inner_scale, inner_scale is None or wave == "plane",
                               "is modelled for plane waves only")):
        if not ok:
            raise ScenarioError(name, v, rule)
    ds, m = propagation_result(wave, wavelength, cn2, distance, count, seed=seed, layers=layers,
                               inner_scale=inner_scale)
    with RunFolder(out_dir, overwrite=overwrite) as tmp:
        write_dataset(ds, tmp / "field.nc")
        write_json_atomic(tmp / "metrics.json", m)
    out.print(f"Rytov variance {m['rytov_variance']:.4g}: scintillation index {m['scintillation_index']:.4g} "
              f"(Andrews-Phillips {m['scintillation_index_theory']:.4g}); r0 {m['r0_plane_m']:.4g} m plane, "
              f"{m['r0_spherical_m']:.4g} m spherical; {m['realisations']} realisations on {m['grid_n']}^2 at "
              f"{m['grid_dx_m'] * 1e3:.3g} mm, {m['layers']} screens", highlight=False, soft_wrap=True)
    out.print(f"wrote {Path(out_dir) / 'field.nc'} and metrics.json", highlight=False)


@app.command()
@_guard
def info(path: Path = typer.Argument(..., metavar="PATH", help="a salkit NetCDF file, or a scenario YAML")):
    """Describe a data file or a scenario (with its derived quantities) as JSON: numbers typed,
    flags as true/false, a "units" map for every quantity with a unit."""
    if path.suffix.lower() in (".yaml", ".yml"):
        from ..params import load_scenario
        from ..geometry import build_collection, check_sampling, resolution_theory
        sc = load_scenario(path)
        if sc.is_downlooking:
            from ..geometry.downlooking import design
            dd = design(sc.experiment)
            d = {"name": sc.name, "kind": "downlooking", **dd.as_dict(), "warnings": list(dd.warnings)}
        else:
            _preflight(sc)
            col = build_collection(sc)
            res = resolution_theory(sc, col)
            kind = sc.experiment.kind if sc.experiment is not None else "sal"
            d = {"name": sc.name, "kind": kind, "pulses": col.n_pulses, "slant_range_m": sc.platform.slant_range,
                 "resolution_range_m": res["range"], "resolution_azimuth_m": res["azimuth"],
                 "aperture_length_m": res["aperture_length"]}
            if sc.experiment is None:  # an experiment checks the sampling of what it images itself
                d.update({f"sampling_{k}": v for k, v in check_sampling(sc, col).as_dict().items()})
            else:
                d["sampling"] = f"checked by the {kind} experiment for what it images"
    else:
        from ..io import describe
        d = describe(path)
    out.print_json(json.dumps(_with_units(_typed(d))))


@app.command()
@_guard
def verify(folder: Path = typer.Argument(..., metavar="DIR", help="an output folder of salkit run / focus")):
    """Check every file of an output folder against its manifest.json (size and SHA-256)."""
    from ..errors import DataFileError
    from ..io.runfolder import verify as verify_folder
    r = verify_folder(folder)
    for x in r["extra"]:
        out.print(f"[yellow]not in the manifest:[/] {x}", highlight=False)
    if not r["ok"]:
        raise DataFileError(f"{folder}: " + "; ".join(r["problems"]))
    out.print(f"{folder}: {r['files']} files match manifest.json", highlight=False)


@app.command()
@_guard
def examples(copy_to: Optional[Path] = typer.Option(None, "--copy", metavar="DIR", help="copy the examples into this folder"),
             overwrite: bool = typer.Option(False, "--overwrite", help="replace files that differ from the shipped ones")):
    """List the shipped example scenarios (and optionally copy them)."""
    import yaml
    d = _examples_dir()
    files = sorted(d.glob("*.yaml"))
    for f in files:
        try:
            desc = (yaml.safe_load(f.read_text()) or {}).get("description", "")
        except yaml.YAMLError:
            desc = "(unreadable)"
        out.print(f"[bold]{f.name}[/]  {desc}", highlight=False)
    if copy_to is not None:
        from ..io.datasets import write_text_atomic
        if copy_to.exists() and not copy_to.is_dir():
            from ..errors import ScenarioError
            raise ScenarioError("--copy", str(copy_to), "names an existing file; give a folder")
        copied, kept = 0, []
        for f in files:
            dst = copy_to / f.name
            text = f.read_text()
            if dst.exists() and dst.read_text() != text and not overwrite:
                kept.append(f.name)
                continue
            write_text_atomic(dst, text)
            copied += 1
        out.print(f"copied {copied} examples to {copy_to}")
        if kept:
            out.print(f"[yellow]kept[/] {len(kept)} edited file(s) ({', '.join(kept)}); --overwrite replaces them",
                      highlight=False)


def _on_signal(signum, frame):  # pragma: no cover - exercised by subprocess tests
    from ..io.runfolder import INTERRUPTED
    INTERRUPTED["signal"] = signum
    raise KeyboardInterrupt(f"signal {signum}")


def main():  # pragma: no cover
    """Entry point of the ``salkit`` command: SIGINT and SIGTERM unwind the same way, so that
    nothing is left half-written; the signal is also recorded, so that a run whose exception was
    swallowed (inside a finaliser) is still discarded at its end.

    Returns
    -------
    object
        What the typer application returns (it exits with the command's status).
    """
    import signal
    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGINT, _on_signal)
    sys.unraisablehook = _unraisable
    _STATE["argv"] = sys.argv[1:]
    try:
        return app()
    except KeyboardInterrupt:  # an interrupt that escaped the command (e.g. while it was exiting):
        sys.exit(130)          # the run folder is already discarded; exit as interrupted, not by SIGINT


def _unraisable(u):  # pragma: no cover - exercised by the signal tests
    """After an interrupt, Python reports as ignored exceptions, with tracebacks, our interrupt raised
    inside a finaliser or a ctypes callback, and the finalisers of what it cut short (llvmlite's,
    when numba was compiling); the run is discarded anyway: keep them quiet."""
    from ..io.runfolder import INTERRUPTED
    if INTERRUPTED["signal"] is not None:
        return
    sys.__unraisablehook__(u)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
