"""The ``salkit`` application: the typer app and its global options, the error guard every command
runs under (exit 2 for bad input, 1 for the environment, 130 when interrupted, one line each),
warnings on stderr, the progress bar, the command line as typed."""
from __future__ import annotations

import functools
import logging
from typing import Optional

import typer
import typer.core
from rich.console import Console
from rich.markup import escape as rich_escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from ..errors import SalkitError

app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False, rich_markup_mode=None,
                  help="salkit: synthetic aperture ladar simulation, imaging and metrics.")
err = Console(stderr=True, emoji=False)  # a user's text as written: ":-1:" is not an emoji code here
out = Console(emoji=False)


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


#: Placeholders an option's help may hold, filled from the declarations when the help is shown
#: (so that ``salkit`` itself starts without loading the library).
def _formers_help() -> str:
    from ..focus.formers import former_help
    return former_help()


DECLARED_HELP = {"{formers}": _formers_help}


class DeclaredHelpCommand(typer.core.TyperCommand):
    """A command whose options' help may name what is declared (``{formers}``: the image formers
    and what each is), read from the registries when ``--help`` is shown."""

    def format_help(self, ctx, formatter):
        for p in self.params:
            text = getattr(p, "help", None)
            if text:
                for key, fill in DECLARED_HELP.items():
                    if key in text:
                        text = text.replace(key, fill())
                p.help = text
        return super().format_help(ctx, formatter)

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


class _NoteHandler(logging.Handler):
    """salkit's informational log lines (how a job is cut to fit its memory) as ``note: ...`` on stderr."""

    def emit(self, record: logging.LogRecord) -> None:
        err.print(f"[cyan]note:[/] {rich_escape(record.getMessage())}", highlight=False, soft_wrap=True)


def _notes() -> None:
    log = logging.getLogger("salkit")
    if not any(isinstance(h, _NoteHandler) for h in log.handlers):
        log.addHandler(_NoteHandler())
    log.setLevel(logging.INFO)


def _say(msg: str) -> None:
    err.print(f"[bold red]error:[/] {rich_escape(msg)}", highlight=False, markup=True, soft_wrap=True)


def _limited(fn, *a, **k):
    """Run a command; a --memory-limit it set ends with it (back to --max-memory's limit)."""
    from ..resources import set_limit
    try:
        return fn(*a, **k)
    finally:
        set_limit(_STATE.get("max_memory"))


def _guard(fn):
    """Exit 2 for bad input and usage, 1 for the environment (permissions, a full disk, memory, a
    busy folder), 130 when interrupted, each with one line; ``--debug`` shows the traceback."""
    @functools.wraps(fn)
    def wrapper(*a, **k):
        from ..interrupts import KEPT_FOR_RESUME
        KEPT_FOR_RESUME.update(resume=None, out=None)
        try:
            return _limited(fn, *a, **k)
        except (typer.Exit, typer.Abort, SystemExit):
            raise
        except SalkitError as e:
            if _STATE["debug"]:
                raise
            _say(str(e))
            raise typer.Exit(code=e.exit_code)
        except KeyboardInterrupt:
            if KEPT_FOR_RESUME["resume"]:
                err.print(f"interrupted: no output folder was written; the finished work is kept in "
                          f"{KEPT_FOR_RESUME['resume']}: the same command (with --resume for a sweep) continues from it "
                          f"into {KEPT_FOR_RESUME['out']}; delete it to start afresh", highlight=False, soft_wrap=True)
            else:
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
          max_memory: Optional[str] = typer.Option(None, "--max-memory", metavar="SIZE", help="memory the jobs may use (e.g. 8GiB; "
                                                   "default: what is available): image formation beyond it runs in tiles (bp, ffbp), other jobs are refused"),
          version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                       help="print the version and exit")):
    """salkit: synthetic aperture ladar simulation, imaging and metrics."""
    import warnings
    _STATE["debug"] = debug
    if not debug:
        warnings.showwarning = show_warning
    _notes()
    from ..resources import parse_size, set_limit
    try:
        _STATE["max_memory"] = parse_size(max_memory) if max_memory is not None else None
        set_limit(_STATE["max_memory"])
    except SalkitError as e:
        _say(str(e))
        raise typer.Exit(code=2)


#: Said once a process, on stderr, when numba starts compiling one of salkit's kernels (a cache miss:
#: the first run on a machine, or after an upgrade). Without it a first run sits silent for a minute.
COMPILE_NOTICE = ("note: compiling salkit's numba kernels for this CPU, once (they are cached for later runs): "
                  "a first run takes up to a minute or two longer")
_COMPILING = {"listening": False, "said": False}


def _announce_compiling() -> None:
    """Listen for numba's compile events (cache misses only; loading from the cache fires none) and
    say :data:`COMPILE_NOTICE` once, before the first of salkit's kernels compiles."""
    if _COMPILING["listening"]:
        return
    from numba.core import event

    class _Notice(event.Listener):
        def on_start(self, ev):
            if _COMPILING["said"]:
                return
            fn = getattr(ev.data.get("dispatcher"), "py_func", None)
            if getattr(fn, "__module__", "").startswith("salkit."):
                _COMPILING["said"] = True
                err.print(COMPILE_NOTICE, highlight=False, soft_wrap=True)

        def on_end(self, ev):
            pass

    event.register("numba:compile", _Notice())
    _COMPILING["listening"] = True


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
        _announce_compiling()  # the work about to run may compile first
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
        from ..interrupts import INTERRUPTED
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
