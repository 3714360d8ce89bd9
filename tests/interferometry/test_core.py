"""Phase unwrapping and the fringe-projection height model."""
import math

import numpy as np
import pytest

from salkit.interferometry import height_from_fringe_shift, unwrap_phase, wrap


@pytest.mark.parametrize("method", ["skimage", "least_squares"])
def test_unwrap_recovers_smooth_surface(method):
    y, x = np.mgrid[0:96, 0:128]
    true = 0.003 * (x - 30.0) ** 2 + 0.25 * y + 3 * np.sin(x / 11.0) * np.cos(y / 17.0)
    assert np.ptp(true) > 40  # many wraps
    got = unwrap_phase(wrap(true), method)
    err = (got - got[0, 0]) - (true - true[0, 0])
    assert np.abs(err).max() < 1e-6


def test_unwrap_rejects_bad_input():
    with pytest.raises(ValueError, match="method"):
        unwrap_phase(np.zeros((4, 4)), "magic")
    with pytest.raises(ValueError, match="2-D"):
        unwrap_phase(np.zeros(8))


def test_least_squares_with_noise_is_unbiased():
    rng = np.random.default_rng(3)
    y, x = np.mgrid[0:64, 0:64]
    true = 0.4 * x + 0.1 * y
    got = unwrap_phase(wrap(true + 0.3 * rng.standard_normal(true.shape)), "least_squares")
    slope = np.polyfit(x.ravel(), (got - true).ravel(), 1)[0]
    assert abs(slope) < 1e-3


def test_height_model_inverts_projection():
    # flat fringes of period P across the beam shift by 2 x 2 pi h sin(theta) / P in the interferogram
    P, th, h = 0.18, 45.0, np.array([0.1, 0.5, -0.3])
    dphi = 2 * 2 * math.pi * h * math.sin(math.radians(th)) / P
    np.testing.assert_allclose(height_from_fringe_shift(dphi, P, th), h, rtol=1e-12)
    with pytest.raises(ValueError, match="nadir"):
        height_from_fringe_shift(dphi, P, 0.0)
