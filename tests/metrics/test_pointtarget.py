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


@pytest.mark.parametrize("carrier", [(0.0, 0.0), (0.31, -0.22), (0.45, 0.4)])
def test_2d_analysis_with_carrier_and_subpixel_offset(carrier):
    d, rho = 0.015, 0.02
    x = (np.arange(128) - 64) * d
    x0, y0 = 0.0037, -0.0051
    X, Y = np.meshgrid(x, x, indexing="ij")
    img = np.sinc((X - x0) / rho) * np.sinc((Y - y0) / rho) * np.exp(
        2j * np.pi * (carrier[0] * (X - x0) / d + carrier[1] * (Y - y0) / d) + 0.9j)
    m = analyse_point(img, x, x, rho, rho)
    assert m["irw_azimuth_m"] == pytest.approx(0.886 * rho, rel=0.005)
    assert m["peak_azimuth_m"] == pytest.approx(x0, abs=rho / 100)
    assert m["peak_range_m"] == pytest.approx(y0, abs=rho / 100)
    assert m["pslr_range_db"] == pytest.approx(-13.26, abs=0.1)
