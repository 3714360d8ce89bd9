"""Scene models: patterns, and extended scenes normalised per resolution cell."""
import numpy as np
import pytest

from salkit.params.models import ExtendedScene
from salkit.simulate.scene import extended_scatterers, pattern_mask


@pytest.mark.parametrize("pattern", ["uniform", "letter_I", "bars", "satellite"])
def test_patterns_are_reflectivities(pattern):
    u, v = np.meshgrid(np.linspace(-0.5, 0.5, 101), np.linspace(-0.5, 0.5, 101), indexing="ij")
    m = pattern_mask(pattern, u, v)
    assert m.shape == u.shape and 0 <= m.min() and m.max() <= 1 and m.max() > 0


def test_speckled_cell_has_mean_power_one():
    ext = ExtendedScene(kind="pattern", pattern="uniform", extent=(1.0, 1.0), spacing=0.005, speckle=True)
    cell = 0.02 * 0.02
    pos, amp = extended_scatterers(ext, cell, np.random.default_rng(0))
    assert pos.shape == (amp.size, 3)
    assert np.sum(np.abs(amp) ** 2) / (1.0 / cell) == pytest.approx(1.0, rel=0.05)
