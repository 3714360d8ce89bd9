"""Design studies: parameter sweeps with realisations (Monte Carlo), on Dask.

``sweep(scenario, vary={"waveform.bandwidth": "lin:1e9:7.5e9:7"}, realisations=20)`` runs, for every
point of the grid (or of the zipped axes) and every realisation, what ``salkit run`` runs up to its
metrics, and returns one labelled dataset: each metric (and its theory) against the varied fields
and ``realisation``, with a ``status`` per point. Realisation r draws every random field from seeds
derived from the scenario's seeds and r alone: every point sees the same realisations, and a rerun
with any number of workers gives identical numbers.

Modules: :mod:`~salkit.studies.spec` (``FIELD=SPEC`` axes), :mod:`~salkit.studies.plan` (points,
seeds, checks before any work), :mod:`~salkit.studies.engine` (running, checkpoints, the dataset).
"""
from .engine import Checkpoint, assemble, execute, plan_of, run_point, select_metrics, sweep
from .plan import SweepPlan, check_points, make_plan, realisation_seed, with_realisation
from .spec import Axis, parse_vary

__all__ = ["Axis", "Checkpoint", "SweepPlan", "assemble", "check_points", "execute", "make_plan", "parse_vary",
           "plan_of", "realisation_seed", "run_point", "select_metrics", "sweep", "with_realisation"]
