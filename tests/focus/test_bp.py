"""The bp former: windows normalised by their sums, progress in pulses."""
import numpy as np
import pytest

from salkit import simulate
from salkit.focus import ImageGrid, phase_history
from salkit.focus.bp import form_bp
from salkit.params import parse_scenario
from salkit.signals.windows import Window

from ..conftest import SPOT, merge


@pytest.mark.parametrize("win", ["none", "hamming", "taylor"])
def test_peak_is_one_under_every_window(win):
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.0, "y": 0.0}]}))
    ph = phase_history(simulate(sc))
    calls = []
    res = form_bp(ph, ImageGrid.of(ph, sc.processing.grid), Window(win), progress=lambda d, n: calls.append((d, n)))
    assert np.abs(res.image).max() == pytest.approx(1.0, abs=0.03)
    assert calls[-1] == (ph.data.shape[0], ph.data.shape[0])
