"""Down-looking image formation: point position (eq 20) and PSF (eqs 22-23)."""
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


def _psf_checks(m, d, prefix=""):
    assert m[prefix + "irw_range_m"] == pytest.approx(0.88589 * d.resolution_x, rel=0.03)
    assert m[prefix + "irw_azimuth_m"] == pytest.approx(0.88589 * d.resolution_y, rel=0.03)
    assert m[prefix + "pslr_range_db"] == pytest.approx(-13.26, abs=0.3)
    assert m[prefix + "pslr_azimuth_db"] == pytest.approx(-13.26, abs=0.3)


@pytest.mark.parametrize("look,pt", [(0.0, (0.0, 0.03, 0.0)), (0.0, (0.7, -2.1, 0.0)),
                                     (35.0, (-0.3, 1.2, 0.8))])
def test_point_position_eq20_and_psf_eq22_23(look, pt):
    from salkit.metrics import measure
    from salkit.systems.downlooking import image_dataset
    sc = scenario(f"experiment.track.look_angle_deg={look}", f"scene.points.0.x={pt[0]}",
                  f"scene.points.0.y={pt[1]}", f"scene.points.0.z={pt[2]}")
    exp, d = sc.experiment, design(sc.experiment)
    scat, Y, cur, imgs, truth = point_run(sc, d, exp, np.random.default_rng(1), half_window=0.3)
    ds = image_dataset(imgs.forward, imgs, d, exp, look, "forward", truth)
    m = measure(ds)
    # eq 20 with the point's own magnification M = d_z / f_t
    assert abs(m["peak_offset_range_m"]) < 0.1 * d.resolution_x
    assert abs(m["peak_offset_azimuth_m"]) < 0.1 * d.resolution_y
    _psf_checks(m, d)
    if pt[2] != 0.0:  # height moves the image by about h sin(look): x = M_ref f_t d_x / d_z
        shift = truth[0, 1] - pt[1] * math.cos(math.radians(look))
        assert shift == pytest.approx(pt[2] * math.sin(math.radians(look)), rel=0.01)
