"""Height from the self-interferogram: what the fringes hold of the terrain."""
import copy
import math

import numpy as np
import pytest

from salkit.errors import SamplingError, ScenarioError
from salkit.geometry.downlooking import design, design_from_requirements
from salkit.interferometry import fringe_period, interferogram
from salkit.params import load_scenario, parse_scenario
from salkit.simulate.downlooking import make_scatterers, simulate_factored, simulate_fields, track_positions
from salkit.systems.downlooking import disturbance_experiment, extended_run, point_run, terrain_run

from ..conftest import DL_EXAMPLE as EXAMPLE, EXAMPLES, dl_scenario as scenario  # noqa: F401


def test_terrain_height_is_not_in_the_fringes():
    sc = scenario("experiment.terrain.extent=[0.8,0.8]", "experiment.terrain.speckle=false",
                  "experiment.terrain.correlation_length=0.25")
    exp, d = sc.experiment, design(sc.experiment)
    r = terrain_run(exp, d, np.random.default_rng(4))
    m = r["metrics"]
    model = m["terrain_phase_per_height_model_rad_per_m"]
    assert model == pytest.approx(4 * math.pi * math.sin(math.radians(45)) / 0.18)
    # the terrain would shift the fringes by tens of radians in ground coordinates ...
    assert m["terrain_ground_fringe_phase_span_rad"] > 10
    # ... but the SAL's interferogram phase does not follow the height
    assert abs(m["terrain_phase_per_height_rad_per_m"]) < 0.02 * model
    assert m["terrain_height_recovered_rms_m"] < 0.1 * m["terrain_height_rms_m"]
    assert m["terrain_height_error_over_height_rms"] == pytest.approx(1.0, abs=0.1)
