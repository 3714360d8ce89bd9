"""The former registry: one signature, one normalisation, registered by name."""
import numpy as np
import pytest

from salkit import simulate
from salkit.choices import ALGORITHMS
from salkit.errors import ScenarioError
from salkit.focus import FORMERS, ImageGrid, get_former, phase_history, register_former
from salkit.params import parse_scenario
from salkit.signals.windows import Window

from ..conftest import SPOT, STRIP, merge


def test_registry_matches_the_choices():
    assert sorted(FORMERS) == sorted(ALGORITHMS)


def test_unknown_and_duplicate_names_refused():
    with pytest.raises(ScenarioError, match="processing.algorithm"):
        get_former("fft")
    with pytest.raises(ValueError, match="already registered"):
        register_former("bp")(lambda *a, **k: None)
    with pytest.raises(ValueError, match="not in salkit.choices"):
        register_former("newalg")(lambda *a, **k: None)


@pytest.mark.parametrize("alg,base", [("bp", SPOT), ("pfa", SPOT), ("bp", STRIP), ("omegak", STRIP)])
def test_every_former_normalises_a_unit_point_to_one(alg, base):
    sc = parse_scenario(merge(base, scene={"points": [{"x": 0.0, "y": 0.0}]}))
    ph = phase_history(simulate(sc))
    grid = ImageGrid.of(ph, sc.processing.grid)
    res = get_former(alg)(ph, grid, Window("none"))
    assert res.image.shape == grid.shape and res.image.dtype == np.complex64
    assert np.abs(res.image).max() == pytest.approx(1.0, abs=0.05)
    assert res.info["support_range"] > 0
