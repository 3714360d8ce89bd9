"""The interrupt a run received: set by the command line's SIGINT/SIGTERM handler, read by the run
folder (:mod:`salkit.io.runfolder`) and the command line.

A module of its own, importing nothing, so that the command line can read it on every exit
(``salkit --help`` included) without loading the library.
"""
from __future__ import annotations

#: Set by the command line's SIGINT/SIGTERM handler: a run that completes after it is discarded
#: (a handler's exception can be swallowed when it lands inside a finaliser).
INTERRUPTED: dict = {"signal": None}

__all__ = ["INTERRUPTED"]
