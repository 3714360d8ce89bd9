"""Seed systems as compositions of the lower layers: each ``run(scenario, out_dir, progress)``
returns a :class:`~salkit.systems.result.RunResult`; the report layer writes it.

Modules: :mod:`~salkit.systems.registry` (``run_workflow``, ``WORKFLOWS``), one module per workflow
(:mod:`~salkit.systems.airborne`, :mod:`~salkit.systems.turbulence`, :mod:`~salkit.systems.chirp`,
:mod:`~salkit.systems.spaceborne`, :mod:`~salkit.systems.downlooking`), :mod:`~salkit.systems.result`,
:mod:`~salkit.systems.study` (workflows as sweep points: ``sweep``, ``salkit sweep``'s runs).
"""
from .registry import WORKFLOWS, run_workflow
from .result import RunResult

__all__ = ["RunResult", "WORKFLOWS", "run_workflow"]
