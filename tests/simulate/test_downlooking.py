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


def test_factor_recurrences_equal_the_direct_factors():
    """The along-track and scan factors by their recurrences (exact sin and cos every ANCHOR_ROWS
    rows, complex128 rotations between) equal the factors computed element by element to float32
    rounding, over many anchors and phases of hundreds of radians; scan positions that are not
    uniform take the direct kernel."""
    from salkit.simulate import downlooking as D
    rng = np.random.default_rng(3)
    t = -0.5e-3 + np.arange(1000) / 1e6
    x = rng.uniform(-2e-3, 2e-3, 700)
    k = np.pi / (1.55e-6 * 0.5)
    a = D._along_factor_direct(t, x, k, -60.0, -2e-4, 1e-5)
    step = D._uniform(t)
    assert step is not None
    b = D._along_factor(t, step[1], x, k, -60.0, -2e-4, 1e-5)
    assert np.max(np.abs(k * (-60.0 * t - 2e-4))) * 2 * np.max(np.abs(x - 1e-5)) > 300  # phases of hundreds of rad
    for u, v in zip(a, b):
        assert np.abs(u - v).max() < 3e-7
    Y = -4.5 + 0.009 * np.arange(333)
    y, dz = rng.uniform(-4, 4, 700), rng.uniform(29, 31, 700)
    w, diff = rng.uniform(0.5, 1.5, 700), rng.uniform(-3, 3, Y.size)
    ky = 2 * np.pi / (1.55e-6 * 0.5)
    args = (diff, y, dz, w, ky, -0.3, 0.01)
    a = D._scan_factor_direct(Y, *args)
    b = D._scan_factor(*D._uniform(Y), Y.size, *args)
    assert 0.05 < (a[0] != 0).mean() < 0.95 and ((a[0] != 0) == (b[0] != 0)).all()
    for u, v in zip(a, b):
        assert np.abs(u - v).max() < 3e-7 * np.abs(w).max()
    Y[5] += 1e-6
    assert D._uniform(Y) is None
