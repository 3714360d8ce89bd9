"""The interrupt a run received (set by the command line's SIGINT/SIGTERM handler) and what a failed
run kept for resuming: read and written by the run folder (:mod:`salkit.io.runfolder`) and the
command line.

A module of its own, importing nothing, so that the command line can read it on every exit
(``salkit --help`` included) and before any command's work without loading the library.
"""
from __future__ import annotations

#: Set by the command line's SIGINT/SIGTERM handler: a run that completes after it is discarded
#: (a handler's exception can be swallowed when it lands inside a finaliser).
INTERRUPTED: dict = {"signal": None}
#: What the last failed or interrupted run kept for resuming: the ``.NAME.resume`` folder and the
#: output folder it belongs to (None when nothing was kept), so that the command can say so.
KEPT_FOR_RESUME: dict = {"resume": None, "out": None}

__all__ = ["INTERRUPTED", "KEPT_FOR_RESUME"]
