"""The ``salkit`` command: a thin layer over the library.

Bad input (scenario fields, data files, sampling) prints one clear line naming the field, the
value and the constraint, and exits with status 2, never a traceback.

This module is the entry point: it registers the commands (:data:`COMMANDS`, one module per group:
:mod:`~salkit.cli.runs`, :mod:`~salkit.cli.data`, :mod:`~salkit.cli.turbulence`, :mod:`~salkit.cli.studies`,
:mod:`~salkit.cli.inspection`) on the application of :mod:`~salkit.cli.app` and installs the signal
handling. Each command imports the library inside itself, so ``salkit --help`` loads none of it.
"""
from __future__ import annotations

import os
import sys

from . import data, inspection, runs, studies, turbulence
from .app import _STATE, DeclaredHelpCommand, _Bar, app, show_warning  # noqa: F401  (the application and what the demo uses)
from .options import _examples_dir, print_headline  # noqa: F401

#: The commands, in the order ``salkit --help`` lists them.
COMMANDS = (runs.run, runs.simulate, data.focus, data.export, data.convert, turbulence.screen, turbulence.propagate,
            studies.sweep, inspection.info, inspection.verify, inspection.examples)
for _command in COMMANDS:
    app.command(cls=DeclaredHelpCommand)(_command)


def _on_signal(signum, frame):  # pragma: no cover - exercised by subprocess tests
    from ..interrupts import INTERRUPTED
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
    finally:
        from ..interrupts import INTERRUPTED
        if INTERRUPTED["signal"] is not None:  # the command has cleaned up; leave now, with 130, rather
            sys.stdout.flush()                 # than run finalisers the interrupt may have cut short
            sys.stderr.flush()                 # (numba compiling): one of them re-raising it would
            os._exit(130)                      # end the process by SIGINT instead


def _unraisable(u):  # pragma: no cover - exercised by the signal tests
    """After an interrupt, Python reports as ignored exceptions, with tracebacks, our interrupt raised
    inside a finaliser or a ctypes callback, and the finalisers of what it cut short (llvmlite's,
    when numba was compiling); the run is discarded anyway: keep them quiet."""
    from ..interrupts import INTERRUPTED
    if INTERRUPTED["signal"] is not None:
        return
    sys.__unraisablehook__(u)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
