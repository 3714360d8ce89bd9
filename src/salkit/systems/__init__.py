"""Seed systems as compositions of the lower layers."""


def run_experiment(scenario, out_dir, progress=None) -> dict:
    """Run the experiment a scenario names (``experiment.kind``)."""
    kind = scenario.experiment.kind
    if kind == "turbulence_pga":
        from .turbulence import run
    elif kind == "spaceborne_geo":
        from .spaceborne import run
    elif kind == "downlooking":
        from .downlooking import run
    else:
        from .chirp import run
    return run(scenario, out_dir, progress=progress)
