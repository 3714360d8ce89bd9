"""Down-looking raw data: the factored simulation equals the field kernel."""

import numpy as np
import pytest

from salkit.geometry.downlooking import design
from salkit.simulate.downlooking import make_scatterers, simulate_factored, simulate_fields, track_positions

from ..conftest import DL_EXAMPLE as EXAMPLE, EXAMPLES, dl_scenario as scenario  # noqa: F401


@pytest.mark.parametrize("hwp", [22.5, 10.0])
def test_factored_simulation_equals_field_kernel(hwp):
    sc = scenario(f"experiment.optics.hwp_angle_deg={hwp}")
    exp, d = sc.experiment, design(sc.experiment)
    rng = np.random.default_rng(0)
    g = np.column_stack([rng.uniform(-0.4, 0.4, 40), rng.uniform(-2, 2, 40), rng.uniform(0, 1.5, 40)])
    s = make_scatterers(g, rng.uniform(0.5, 1.5, 40), rng.uniform(-3, 3, 40), exp.track.range, 30.0)
    Y = track_positions(exp, d, -0.4, 0.4)[::7]
    a = simulate_fields(s, exp, d, Y)
    b = simulate_factored(s, exp, d, Y)
    assert np.abs(a).max() > 1
    assert np.abs(a - b).max() < 1e-5 * np.abs(a).max()
