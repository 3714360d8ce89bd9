"""Design studies' engine: parameter sweeps with realisations (Monte Carlo), on Dask.

A plan holds a base scenario, its varied fields (a grid or zipped axes) and the realisations;
``execute(plan, invalid, runner)`` runs every (point, realisation) through ``runner`` (in this
process or on Dask, checkpointed) and returns one labelled dataset: each metric (and its theory)
against the varied fields and ``realisation``, with a ``status`` per point. Realisation r draws
every random field from seeds derived from the scenario's seeds and r alone: every point sees the
same realisations, and a rerun with any number of workers gives identical numbers. What a point
runs is the caller's: :mod:`salkit.systems.study` (``salkit.sweep``, ``salkit sweep``) runs the
scenario's workflow; the systems' own loops pass their point functions.

Modules: :mod:`~salkit.studies.spec` (``FIELD=SPEC`` axes), :mod:`~salkit.studies.plan` (points,
seeds, checks before any work), :mod:`~salkit.studies.engine` (running, checkpoints, the dataset).
"""
from .engine import Checkpoint, assemble, execute, plan_of, select_metrics
from .plan import SweepPlan, check_points, make_plan, realisation_seed, with_realisation
from .spec import Axis, parse_vary

__all__ = ["Axis", "Checkpoint", "SweepPlan", "assemble", "check_points", "execute", "make_plan", "parse_vary",
           "plan_of", "realisation_seed", "select_metrics", "with_realisation"]
