"""The base of the parameter objects: frozen, no unknown fields, no inf or NaN; the shared phase
error has the amplitude, shape and statistics it names."""
import numpy as np
import pytest
from pydantic import ValidationError

from salkit.params.base import PhaseError


def test_frozen_and_strict():
    e = PhaseError(amplitude=1.0)
    with pytest.raises(ValidationError):
        e.amplitude = 2.0
    with pytest.raises(ValidationError, match="amplitud"):
        PhaseError(amplitud=1.0)
    with pytest.raises(ValidationError):
        PhaseError(amplitude=float("inf"))


def test_phase_error_shapes():
    n = 1001
    q = PhaseError(kind="quadratic", amplitude=2.0).values(n)
    assert q[0] == pytest.approx(2.0) and q[-1] == pytest.approx(2.0) and q[n // 2] == pytest.approx(0.0)
    s = PhaseError(kind="sinusoidal", amplitude=0.5, cycles=2.5).values(n)
    assert np.max(np.abs(s)) == pytest.approx(0.5, rel=1e-3)
    r = PhaseError(kind="random", amplitude=0.3, bandwidth=4.0, seed=7).values(n)
    assert np.std(r) == pytest.approx(0.3) and abs(np.mean(r)) < 1e-12
    np.testing.assert_array_equal(r, PhaseError(kind="random", amplitude=0.3, bandwidth=4.0, seed=7).values(n))
    spec = np.abs(np.fft.rfft(r)) ** 2
    assert spec[:8].sum() / spec.sum() > 0.99  # band-limited to about 4 cycles across the aperture
