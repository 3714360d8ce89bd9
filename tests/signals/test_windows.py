"""Windows: shapes and their callable spec."""
import numpy as np
import pytest

from salkit.errors import ScenarioError
from salkit.signals.windows import Window, window


@pytest.mark.parametrize("name", ["none", "hamming", "taylor"])
def test_symmetric_and_peak_one(name):
    w = window(name, 65)
    np.testing.assert_allclose(w, w[::-1])
    assert w.max() == pytest.approx(1.0)


def test_window_spec():
    w = Window("taylor", nbar=5, sll=40)
    np.testing.assert_array_equal(w(33), window("taylor", 33, 5, 40))
    assert "taylor" in repr(w)
    with pytest.raises(ScenarioError, match="window"):
        Window("kaiser")
    assert window("none", 0).size == 0
