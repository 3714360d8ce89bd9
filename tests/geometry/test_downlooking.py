"""The down-looking design (seed 000 section 5): the example's numbers."""
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


def test_design_example_numbers():
    d = design_from_requirements(1800.0, 7.5, 0.018, 0.005, 0.06)
    assert d["magnification"] == pytest.approx(1500)
    assert d["focal_transmit"] == pytest.approx(1.2)
    assert d["wavelength"] == pytest.approx(2.0e-6)       # derived: first null 18 mm
    assert d["fringe_period_x"] == pytest.approx(0.180)   # the paper's 180 mm
    assert d["width_eq22"] == pytest.approx(0.036)
    sc = scenario()
    dd = design(sc.experiment)
    assert dd.wavelength_derived and dd.wavelength == pytest.approx(2e-6)
    assert dd.spot_x == pytest.approx(7.5) and dd.resolution_x == pytest.approx(0.018)
    # S_b = W_x/2 exactly: the seed's design sits on the sideband limit -> a warning with the numbers
    assert any("3.75 m" in w for w in dd.warnings)
    # lens widths: first principles (2 W_x for K = 1) and the paper's formula (1.5 W_x + S_1 for S_1 > W_x/2)
    assert dd.lens_width_forward == pytest.approx(0.010)
    assert dd.lens_width_paper_forward == pytest.approx(0.0105)
    assert dd.lens_width_paper_backward == pytest.approx(0.010)
