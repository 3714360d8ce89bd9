"""Seed 000 down-looking SAL against the paper's closed forms (eqs 20-25) and the physics."""
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


@pytest.mark.parametrize("sa", [0.5e-3, 1.0e-3])
def test_fringe_period_eq24_25(sa):
    sc = scenario(f"experiment.optics.bias_opposite={sa}", "scene.extended.pattern=uniform",
                  "scene.extended.extent=[0.6,0.8]")
    exp, d = sc.experiment, design(sc.experiment)
    _, imgs, _ = extended_run(sc, d, exp, np.random.default_rng(2))
    per = fringe_period(interferogram(imgs.forward.astype(complex), imgs.backward.astype(complex)), imgs.x)
    theory = design(exp).fringe_period_x
    assert theory == pytest.approx(1500 * 2e-6 * 0.06 / (2 * sa))
    assert per["period_m"] == pytest.approx(theory, rel=0.01)


@pytest.mark.parametrize("x,mod", [(0.03, 1.0), (0.075, 0.0), (0.06, abs(math.cos(2 * math.pi * 3.81 / 0.18)))])
def test_point_fringe_modulation_and_the_paper_order(x, mod):
    # eq 19: the pair sum is 2 cos(2 pi xi_p S_a / v_x) times the PSF, xi_p the point's beat frequency.
    # x = 0.075 m puts the point on a fringe zero: eq 19 says it vanishes.
    from salkit.focus.downlooking import focus_downlooking
    sc = scenario(f"scene.points.0.y={x}")
    exp, d = sc.experiment, design(sc.experiment)
    _, Y, cur, imgs, _ = point_run(sc, d, exp, np.random.default_rng(1), half_window=0.2)
    fw = np.abs(imgs.forward).max()
    assert np.abs(imgs.combined).max() / (2 * fw) == pytest.approx(mod, abs=0.01)
    # adding the pairs before the along-track filter (eq 16 then eq 17) focuses the forward scans only:
    # the backward ones carry the conjugate along-track history, and no fringe forms
    paper = focus_downlooking(cur, Y, d, exp, y_range=(-0.2, 0.2), x_range=(x - 0.2, x + 0.2), order="paper")
    assert np.abs(paper.combined).max() / (2 * fw) == pytest.approx(0.5, abs=0.03)


def test_fringe_vanishes_without_opposite_bias():
    sc = scenario("experiment.optics.bias_opposite=0.0", "scene.extended.pattern=uniform",
                  "scene.extended.extent=[0.4,0.6]")
    exp, d = sc.experiment, design(sc.experiment)
    assert math.isinf(d.fringe_period_x)
    _, imgs, _ = extended_run(sc, d, exp, np.random.default_rng(2))
    f = np.abs(imgs.forward)
    good = f > 0.5 * f.max()
    ratio = imgs.combined[good] / imgs.forward[good]
    assert np.abs(ratio - 2).max() < 0.01  # forward and backward add in phase everywhere: no fringe


def test_twin_image_when_sideband_condition_violated():
    # S_b = 1.5 mm < W_x/2: M S_b = 2.25 m < X_p/2 = 3.75 m. A point at x = -3 m beats at
    # |x + M S_b| = 0.75 m on the negative side; its twin lands at -x - 2 M S_b = -1.5 m.
    with pytest.raises(ScenarioError, match="sideband condition"):
        scenario("experiment.optics.bias_common=0.0015")
    sc = scenario("experiment.optics.bias_common=0.0015", "experiment.optics.bias_opposite=0.0002",
                  "experiment.allow_twin_overlap=true", "scene.points.0.y=-3.0")
    exp, d = sc.experiment, design(sc.experiment)
    _, Y, cur, _, _ = point_run(sc, d, exp, np.random.default_rng(1))
    from salkit.focus.downlooking import focus_downlooking
    imgs = focus_downlooking(cur, Y, d, exp, y_range=(-0.2, 0.2))
    j = np.argmax(np.abs(imgs.forward).max(axis=0))
    assert imgs.x[j] == pytest.approx(-1.5, abs=d.resolution_x)
    # with the condition met (S_b = 2.5 mm) the same point images where it is
    sc2 = scenario("scene.points.0.y=-3.0")
    _, Y2, cur2, _, _ = point_run(sc2, design(sc2.experiment), sc2.experiment, np.random.default_rng(1))
    im2 = focus_downlooking(cur2, Y2, design(sc2.experiment), sc2.experiment, y_range=(-0.2, 0.2))
    assert im2.x[np.argmax(np.abs(im2.forward).max(axis=0))] == pytest.approx(-3.0, abs=0.01)


def test_common_mode_immunity_and_side_looking_degradation():
    sc = scenario()
    exp, d = sc.experiment, design(sc.experiment)
    res = disturbance_experiment(sc, exp, d)["cases"]
    # common mode cancels in e_V e_P*: the DL-SAL image does not change
    assert res["common"]["max_change_over_peak"] < 1e-9
    assert res["common"]["irw_azimuth_m"] == pytest.approx(res["none"]["irw_azimuth_m"], rel=1e-9)
    # the same vibration ruins a side-looking SAL of the same resolution
    assert res["side_clean"]["irw_azimuth_m"] == pytest.approx(0.88589 * d.resolution_y, rel=0.03)
    assert res["side_vibration"]["peak_ratio"] < 0.5
    assert res["side_vibration"]["pslr_azimuth_db"] > -10
    # not common mode: a turbulent layer at the transmit pupil and a polarisation-dependent phase
    assert res["transmitter"]["peak_ratio"] < 0.7
    dr = exp.disturbance.differential_rms
    assert res["differential"]["peak_ratio"] == pytest.approx(math.exp(-dr ** 2 / 2), rel=0.05)


def test_receiver_noise_in_the_image_follows_the_processing_gain():
    # white noise of std sigma per fast-time sample: the cross-track FFT (gain 1/N_t) and the along-track
    # filter (1/N_a over the footprint) leave sigma^2 / (N_t N_a) per pixel in each single-direction image
    sc = scenario("experiment.noise_snr_db=0")
    exp, d = sc.experiment, design(sc.experiment)
    _, Y, cur, imgs, _ = point_run(sc, d, exp, np.random.default_rng(7), half_window=0.6)
    sigma = 2.0  # beat amplitude of a unit scatterer is 2 (45-degree plate); SNR 0 dB
    n_a = d.spot_y / (2 * exp.track.spacing)
    theory = sigma ** 2 / (d.samples * n_a)
    yy, xx = np.meshgrid(imgs.y, imgs.x, indexing="ij")
    far = (np.abs(yy) > 0.15) & (np.abs(xx - 0.03) > 0.15)  # away from the point's sidelobe cross
    got = float(np.mean(np.abs(imgs.forward[far]) ** 2))
    assert got == pytest.approx(theory, rel=0.1)
