"""Backprojection sharpness (Ash 2012): the measure, and its per-pulse maximisation on synthetic
contributions with a known phase error."""
import numpy as np
import pytest

from salkit.autofocus.sharpness import pulse_sharpness, sharpness


def test_sharpness_limits():
    assert sharpness(np.array([0, 3.0, 0, 0])) == pytest.approx(1.0)
    assert sharpness(np.ones(16)) == pytest.approx(1 / 16)
    assert sharpness(np.zeros(4)) == 0.0


def test_known_phase_error_recovered():
    """K pixels, each the sum over P pulses of a point-like contribution; a random per-pulse phase
    error is undone up to a constant (sharpness cannot see one)."""
    rng = np.random.default_rng(3)
    P, K = 64, 48
    b = (rng.standard_normal((P, K)) + 1j * rng.standard_normal((P, K))) * 0.05
    b[:, 10] += 1.0  # a dominant scatterer in pixel 10, in phase across pulses
    err = rng.uniform(-np.pi, np.pi, P)
    res = pulse_sharpness(b * np.exp(1j * err)[:, None], max_sweeps=20)
    resid = np.angle(np.exp(1j * (res.phase + err)))
    resid -= np.angle(np.mean(np.exp(1j * resid)))
    assert np.sqrt(np.mean(resid ** 2)) < 0.1
    assert res.history[-1]["sharpness"] >= res.history[0]["sharpness"]
    peak = abs(np.exp(1j * res.phase) @ (b[:, 10] * np.exp(1j * err)))
    assert peak / P > 0.98 and abs(np.sum(b[:, 10] * np.exp(1j * err))) / P < 0.3  # coherent again
