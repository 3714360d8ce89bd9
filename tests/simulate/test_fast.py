"""The fast simulator (one non-uniform FFT a pulse) against the direct sum, the reference: a
speckled extended scene and a point at 5 km and 200 km to its stated accuracy (-80 dB by default,
-100 dB when asked), with turbulence screens too; refused with the reason where it does not hold."""
import numpy as np
import pytest

from salkit import simulate
from salkit.errors import ScenarioError
from salkit.params import parse_scenario

from ..conftest import GEO, SPOT, merge

SCENE = {"extended": {"pattern": "uniform", "extent": [0.3, 0.3], "spacing": 0.005},
         "points": [{"x": 0.0, "y": 0.0}]}


def _error_db(a, b):
    return 10 * np.log10(np.sum(np.abs(a - b) ** 2) / np.sum(np.abs(a) ** 2))


@pytest.mark.parametrize("base", [SPOT, GEO], ids=["5km", "200km"])
@pytest.mark.parametrize("accuracy", [-80.0, -100.0])
def test_the_fast_simulator_meets_its_accuracy(base, accuracy):
    d = merge(base, scene=SCENE)
    direct = simulate(parse_scenario(d))["signal"].values
    fast = simulate(parse_scenario(merge(d, simulation={"method": "nufft", "accuracy_db": accuracy})))["signal"].values
    assert _error_db(direct, fast) < accuracy


def test_through_turbulence_screens():
    d = merge(SPOT, scene=SCENE, atmosphere={"cn2": 1e-14, "layers": 4, "seed": 3})
    direct = simulate(parse_scenario(d))["signal"].values
    fast = simulate(parse_scenario(merge(d, simulation={"method": "nufft"})))["signal"].values
    assert _error_db(direct, fast) < -80


def test_refused_where_it_does_not_hold_and_auto_falls_back():
    d = merge(SPOT, scene=SCENE, waveform={**SPOT["waveform"], "nonlinearity": [1e15]})
    with pytest.raises(ScenarioError, match="simulation.method = 'nufft'.*linear chirp"):
        simulate(parse_scenario(merge(d, simulation={"method": "nufft"})))
    auto = simulate(parse_scenario(merge(d, simulation={"method": "auto"})))["signal"].values
    np.testing.assert_array_equal(auto, simulate(parse_scenario(d))["signal"].values)  # the direct sum
