"""A sweep's plan: grid order and zipped axes, seeds of the realisations (common random numbers,
realisation 0 the scenario's own), and every point checked before any work."""
import pytest

from salkit.errors import ScenarioError
from salkit.params import parse_scenario
from salkit.studies import SweepPlan, check_points, make_plan, parse_vary, realisation_seed, with_realisation
from salkit.systems.preflight import preflight

from ..conftest import SPOT, merge


@pytest.fixture(scope="module")
def spot():
    return parse_scenario(merge(SPOT, platform__phase_error={"kind": "random", "amplitude": 1.0, "seed": 3}))


def test_grid_and_zip(spot):
    axes = [parse_vary("waveform.bandwidth=5e9,7.5e9"), parse_vary("processing.window=none,hamming,taylor")]
    p = make_plan(spot, axes)
    assert p.shape == (2, 3) and p.n_points == 6
    assert p.point_values(4) == (7.5e9, "hamming")  # C order: the last axis fastest
    assert parse_scenario(p.point_data(4)).processing.window == "hamming"
    with pytest.raises(ScenarioError, match="same number of values"):
        make_plan(spot, axes, zipped=True)
    z = make_plan(spot, [axes[0], parse_vary("processing.window=none,taylor")], zipped=True)
    assert z.shape == (2,) and z.point_values(1) == (7.5e9, "taylor")


def test_bad_plans_refused_before_any_work(spot):
    with pytest.raises(ScenarioError) as e:
        make_plan(spot, [parse_vary("waveform.bandwith=1,2")])
    assert e.value.field == "--vary" and e.value.value == "waveform.bandwith"
    # a misspelt section is the sweep's error too, not every point's (it was "none can run")
    with pytest.raises(ScenarioError) as e:
        make_plan(spot, [parse_vary("wavefrm.wavelength=1e-6,2e-6")])
    assert e.value.field == "--vary" and e.value.value == "wavefrm.wavelength"
    assert "did you mean 'waveform'?" in e.value.constraint
    with pytest.raises(ScenarioError, match="twice"):
        make_plan(spot, [parse_vary("seed=1,2"), parse_vary("seed=3,4")])
    with pytest.raises(ScenarioError, match="realisations"):
        make_plan(spot, [parse_vary("seed=1,2")], realisations=0)
    with pytest.raises(ScenarioError, match="at least one"):
        SweepPlan({}, ())


def test_a_section_a_down_looking_scenario_lacks_is_refused_naming_the_kind():
    from ..conftest import EXAMPLES
    from salkit.params import load_scenario
    dl = load_scenario(EXAMPLES / "downlooking_3d.yaml")
    with pytest.raises(ScenarioError) as e:
        make_plan(dl, [parse_vary("waveform.wavelength=1e-6,2e-6")])
    assert e.value.field == "--vary" and e.value.value == "waveform.wavelength"
    assert "is not a field of a down-looking scenario" in e.value.constraint


def test_realisation_seeds_are_common_random_numbers(spot):
    p = make_plan(spot, [parse_vary("waveform.bandwidth=5e9,7.5e9")], realisations=3)
    assert p.point_data(0, 0)["seed"] == spot.seed  # realisation 0 is the scenario as written
    r1 = [p.point_data(i, 1) for i in range(2)]
    assert r1[0]["seed"] == r1[1]["seed"] == realisation_seed(spot.seed, 1) != spot.seed
    assert r1[0]["platform"]["phase_error"]["seed"] == realisation_seed(3, 1)  # every random field
    assert p.point_data(0, 2)["seed"] != r1[0]["seed"]
    assert with_realisation({"a": [{"seed": 5}], "seed": True}, 2) == {"a": [{"seed": realisation_seed(5, 2)}],
                                                                       "seed": True}


def test_invalid_points_named(spot):
    p = make_plan(spot, [parse_vary("waveform.prf=25000,50")])  # 50 Hz: too few pulses for the grid
    bad = check_points(p, preflight)
    assert list(bad) == [1] and bad[1].startswith("processing.grid.dx = 0.015: must be <=")
