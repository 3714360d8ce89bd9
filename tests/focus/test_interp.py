"""Windowed-sinc interpolation: band-limited signals resampled to the kernel's accuracy."""
import numpy as np

from salkit.focus.interp import resample_rows


def test_band_limited_tone_resampled():
    n = 128
    x = np.arange(n)
    f = 0.17  # cycles per sample, well inside the band
    data = np.exp(2j * np.pi * f * x)[None, :].astype(np.complex64)
    pos = np.linspace(10, n - 11, 301)[None, :]
    out = resample_rows(data, pos, half=8)
    err = np.abs(out[0] - np.exp(2j * np.pi * f * pos[0]))
    assert err.max() < 2e-3


def test_outside_the_row_gives_zero():
    data = np.ones((1, 16), np.complex64)
    out = resample_rows(data, np.array([[-3.0, 20.0]]))
    np.testing.assert_array_equal(out, 0)
