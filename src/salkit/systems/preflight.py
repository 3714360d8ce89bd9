"""Every check that needs no work, made before a scenario runs: the down-looking design's
sampling, the memory of simulating and focusing, the collection's sampling (PRF, ADC rate, gate,
grid) and, for wave optics, every turbulence class's screens."""
from __future__ import annotations

from ..focus.pipeline import run_memory_plan
from ..geometry import build_collection, check_sampling
from ..geometry.downlooking import design
from ..resources import check_memory
from ..simulate import screen_size


def preflight(scenario) -> list[str]:
    """Check a scenario before any work; raise on what would fail, return what only warns.

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario

    Returns
    -------
    list of str
        Warnings (the down-looking design's).

    Raises
    ------
    SamplingError, ScenarioError, EnvironmentProblem
        Aliasing, a bad design, or a job too big for the machine's memory.
    """
    sc = scenario
    if sc.is_downlooking:
        return list(design(sc.experiment).warnings)  # sampling errors are raised by the design
    run_memory_plan(sc)  # simulating fits; focusing fits whole or in tiles beside the signal
    if sc.experiment is None:
        check_sampling(sc, build_collection(sc))
    atm = sc.atmosphere
    if atm is not None and atm.model == "wave_optics":  # plan every class's beam and screens before any work
        col = build_collection(sc)
        classes = getattr(sc.experiment, "classes", None) or {"atmosphere.cn2": atm.cn2}
        for cn2 in (c for c in classes.values() if c):
            n = screen_size(sc.model_copy(update={"atmosphere": atm.model_copy(update={"cn2": cn2})}), col)
            check_memory(atm.layers * n * n * 4.0, f"{atm.layers} phase screens of {n} x {n} (Cn2 = {cn2})",
                         "use fewer atmosphere.layers or a coarser atmosphere.screen_dx")
    return []
