"""The workflows by scenario kind (:data:`WORKFLOWS`) and :func:`run_workflow`, which imports and
runs only the one a scenario names."""
import importlib

from ..metrics.table import warn_undeclared
from .result import RunResult


def run_workflow(scenario, out_dir=None, progress=None) -> RunResult:
    """Run the workflow a scenario names (``experiment.kind``; none: the foundation run).

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
    out_dir : path, optional
        Where a workflow may keep checkpoints (the space-borne stack).
    progress : callable, optional
        ``progress(stage, done, total)``.

    Returns
    -------
    RunResult
    """

    module = importlib.import_module(f"{__package__}.{WORKFLOWS[scenario.kind]}")  # only the one that runs
    result = module.run(scenario, out_dir, progress=progress)
    warn_undeclared(result.metrics, f"the {scenario.kind} workflow")  # every metric is in the table
    return result


#: scenario kind -> the module of ``salkit.systems`` whose ``run`` is its workflow.
WORKFLOWS = {"sal": "airborne", "turbulence_pga": "turbulence", "nonlinear_chirp": "chirp",
             "spaceborne_geo": "spaceborne", "downlooking": "downlooking"}

