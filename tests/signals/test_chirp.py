"""Chirp models: the nonlinear phase integrates the sweep; the reference beat is its difference."""
import numpy as np
import pytest

from salkit.signals.chirp import nonlinear_phase, reference_beat


def test_nonlinear_phase_is_the_integral_of_the_sweep():
    t = np.linspace(-5e-6, 5e-6, 20001)
    c2, c3 = 3e16, -4e21
    e = nonlinear_phase(t, (c2, c3))
    df = np.gradient(e, t) / (2 * np.pi)
    np.testing.assert_allclose(df, c2 * t ** 2 + c3 * t ** 3, atol=1e-3 * abs(c2) * 25e-12)


def test_linear_chirp_beat_is_a_tone_at_minus_k_tau():
    fs, k, tau = 50e6, 1e13, 2e-7
    t = (np.arange(4096) - 2048) / fs
    beat = reference_beat(t, 1.9e14, k, (), tau)
    f = np.fft.fftfreq(t.size, 1 / fs)[np.argmax(np.abs(np.fft.fft(beat)))]
    assert f == pytest.approx(-k * tau, abs=fs / t.size)
    np.testing.assert_allclose(np.abs(beat), 1.0, rtol=1e-12)
