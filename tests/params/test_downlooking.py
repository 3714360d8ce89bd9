"""The down-looking scenario model: bad inputs named, the foundation blocks required elsewhere."""
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


@pytest.mark.parametrize("sets,err,match", [
    (["experiment.scan.factor=2.0"], ScenarioError, "inconsistent with the aperture"),
    (["experiment.track.spacing=0.012"], SamplingError, "Nyquist"),
    (["experiment.scan.samples=512"], SamplingError, "alias"),
    (["experiment.track.speed=1.0"], ScenarioError, "scans would overlap"),
    (["experiment.optics.bias_common=0.002"], ScenarioError, "M S_b = 3 m < X_p/2 = 3.75 m"),
])
def test_bad_inputs(sets, err, match):
    with pytest.raises(err, match=match):
        sc = scenario(*sets)
        design(sc.experiment)


def test_foundation_blocks_still_required_elsewhere():
    data = {"scene": {"points": [{"x": 0, "y": 0}]}}
    with pytest.raises(ScenarioError, match="waveform"):
        parse_scenario(copy.deepcopy(data))
