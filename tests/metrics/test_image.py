"""Image-quality measures: entropy and contrast."""
import math

import numpy as np
import pytest

from salkit.metrics import analyse_point, contrast, entropy, ipr_1d
from salkit.metrics.pointtarget import window_ipr


def test_entropy_and_contrast():
    n = 64
    assert entropy(np.ones((n, n))) == pytest.approx(math.log(n * n))
    point = np.zeros((n, n))
    point[3, 4] = 1
    assert entropy(point) == pytest.approx(0.0)
    assert contrast(np.ones((n, n))) == pytest.approx(0.0)
    rng = np.random.default_rng(0)
    speckle = rng.standard_normal((512, 512)) + 1j * rng.standard_normal((512, 512))
    assert contrast(speckle) == pytest.approx(1.0, rel=0.02)  # exponential intensity
