"""Terrain models: seeded heights with the requested size, scatterers of unit mean power per cell."""
import numpy as np
import pytest

from salkit.interferometry import terrain_height, terrain_scatterers
from salkit.params.downlooking import Terrain


@pytest.mark.parametrize("kind", ["hills", "random"])
def test_heights_are_seeded_and_sized(kind):
    t = Terrain(extent=(4.0, 3.0), spacing=0.02, kind=kind, peak_height=0.5, seed=7)
    x, y = np.meshgrid(np.linspace(-2, 2, 81), np.linspace(-1.5, 1.5, 61), indexing="ij")
    h1, h2 = terrain_height(t, x, y), terrain_height(t, x, y)
    np.testing.assert_array_equal(h1, h2)
    if kind == "hills":
        # peak_height is the tallest hill's amplitude; overlapping hills add (here to 0.71 m)
        assert 0 <= h1.min() and 0.5 <= h1.max() <= 0.5 * 5
    else:  # RMS height over the grid, within the sampling of a 4 x 3 m patch
        assert np.sqrt(np.mean(h1 ** 2)) == pytest.approx(0.5, rel=0.35)


def test_scatterers_unit_mean_power_per_cell():
    t = Terrain(extent=(2.0, 2.0), spacing=0.01, seed=1)
    cell = 0.05 * 0.05
    pos, amp = terrain_scatterers(t, cell, np.random.default_rng(0))
    assert pos.shape == (amp.size, 3)
    per_cell = np.sum(np.abs(amp) ** 2) / (4.0 / cell)  # total power over cells in the patch
    assert per_cell == pytest.approx(1.0, rel=0.1)
