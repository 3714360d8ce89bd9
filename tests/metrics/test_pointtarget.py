"""Point-target figures of merit against the closed forms: sinc IRW, PSLR, ISLR; window theory."""
import math

import numpy as np
import pytest

from salkit.metrics import analyse_point, contrast, entropy, ipr_1d
from salkit.metrics.pointtarget import window_ipr


def test_ideal_sinc_figures():
    dx = 0.001
    x = np.arange(-2000, 2001) * dx
    m = ipr_1d(np.sinc(x / 0.1), dx, 0.1)
    assert m["irw"] == pytest.approx(0.8859 * 0.1, rel=1e-3)
    assert m["pslr_db"] == pytest.approx(-13.26, abs=0.01)
    assert m["islr_db"] == pytest.approx(-10.16, abs=0.05)  # +-10 cells; -9.68 dB over all sidelobes


def test_window_theory_values():
    assert window_ipr("none")["irw_factor"] == pytest.approx(0.886, abs=1e-3)
    h = window_ipr("hamming")
    assert h["irw_factor"] == pytest.approx(1.30, abs=0.01)
    assert h["pslr_db"] == pytest.approx(-42.7, abs=0.5)
    t = window_ipr("taylor", 4, 35.0)
    assert t["pslr_db"] == pytest.approx(-35.0, abs=0.5)
