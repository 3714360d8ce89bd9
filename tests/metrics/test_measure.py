import math

import numpy as np
import pytest

from salkit.metrics import analyse_point, contrast, entropy, ipr_1d
from salkit.metrics.pointtarget import window_ipr



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
