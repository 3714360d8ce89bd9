"""The simulators by scenario kind (:data:`SIMULATORS`) and ``simulate(scenario)``, which dispatches."""
from __future__ import annotations

import numpy as np
import xarray as xr

from ..errors import ScenarioError
from ..params.scenario import require_scenario
from .downlooking import simulate_downlooking
from .echoes import ProgressFn
from .sal import simulate_sal


def simulate(scenario, progress: ProgressFn = None, noise: bool | None = None,
             rng: np.random.Generator | None = None) -> xr.Dataset:
    """Simulate the raw data of a scenario, with the simulator its kind names (:data:`SIMULATORS`:
    ``sal`` dechirped stretch echoes for every :class:`~salkit.params.Scenario`, ``downlooking``
    the balanced current of a :class:`~salkit.params.DownlookingScenario`).

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario
    progress : callable, optional
        ``progress(done, total)`` in pulses (scans).
    noise : bool, optional
        Override the scenario's noise switch.
    rng : numpy.random.Generator, optional
        Default: seeded from ``scenario.seed``.

    Returns
    -------
    xarray.Dataset
        Raw data in the format of ``docs/data-format.md``.

    Examples
    --------
    >>> from salkit.params import load_scenario
    >>> raw = simulate(load_scenario("examples/spotlight_points.yaml",
    ...                              ["platform.aperture_length=0.5"]))  # doctest: +SKIP
    """
    require_scenario(scenario)
    if progress is not None and not callable(progress):
        raise ScenarioError("progress", progress, "must be a callable progress(done, total), or None")
    if noise is not None and not isinstance(noise, (bool, np.bool_)):  # "no" would be true
        raise ScenarioError("noise", noise, "must be True, False or None (the scenario's receiver.noise.enabled)")
    kind = "downlooking" if scenario.is_downlooking else "sal"
    return SIMULATORS[kind](scenario, progress=progress, noise=noise, rng=rng)


#: scenario kind -> simulator, all ``f(scenario, progress=, noise=, rng=) -> xr.Dataset``.
SIMULATORS = {"sal": simulate_sal, "downlooking": simulate_downlooking}
