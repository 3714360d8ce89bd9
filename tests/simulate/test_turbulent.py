"""The atmosphere of a SAL scenario: the simulated echo carries the path's two-way phase, screens
too small are refused with the size they need, the layers' frame is the path's."""
import numpy as np
import pytest

from salkit.atmosphere.path import two_way_phases
from salkit.errors import ScenarioError
from salkit.geometry import build_collection
from salkit.params import parse_scenario
from salkit.simulate import screen_size, simulate, turbulent_path
from salkit.simulate.turbulent import _los_frame

from ..conftest import SPOT, merge

TURBULENT = merge(SPOT, atmosphere={"cn2": 1e-14, "layers": 20, "screen_dx": 0.005})


def test_simulated_raw_carries_the_path_phase():
    """The simulator's echo of the scene-centre target is exp(j phi_two_way) per pulse."""
    sc = parse_scenario(TURBULENT)
    col = build_collection(sc)
    path = turbulent_path(sc, col)
    phi = two_way_phases(col.positions, np.zeros((1, 3)), path.screens, path.z, path.origin, path.dx,
                         path.u0, path.a, path.b)[:, 0]
    raw = simulate(sc)["signal"].values
    got = np.angle(raw.mean(axis=1))
    refl = sc.scene.points[0].phase  # the reflectivity phase rides along
    assert np.max(np.abs(np.angle(np.exp(1j * (got - phi - refl))))) < 1e-3
    assert np.std(phi) > 0.1  # the turbulence is really there


def test_screen_too_small_is_refused_with_the_size_needed():
    sc = parse_scenario(merge(SPOT, atmosphere={"cn2": 1e-14, "layers": 10, "screen_dx": 0.005, "screen_n": 16}))
    need = screen_size(sc.model_copy(update={"atmosphere": sc.atmosphere.model_copy(update={"screen_n": None})}),
                       build_collection(sc))
    with pytest.raises(ScenarioError, match=rf"atmosphere.screen_n.*>= {need} samples"):
        simulate(sc)


def test_layers_frame_is_the_paths():
    sc = parse_scenario(TURBULENT)
    col = build_collection(sc)
    R, u0, a, b = _los_frame(col)
    path = turbulent_path(sc, col)
    assert R == pytest.approx(np.linalg.norm(col.center_position))
    for mine, theirs in ((u0, path.u0), (a, path.a), (b, path.b)):
        np.testing.assert_allclose(mine, theirs, atol=1e-15)
