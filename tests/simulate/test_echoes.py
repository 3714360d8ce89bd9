"""SAL echoes against the closed-form dechirped signal, computed independently in float64; photon
noise statistics."""

import numpy as np
import pytest

from salkit.geometry import build_collection
from salkit.params import parse_scenario
from salkit.simulate import echo_signal, fast_time_axis, simulate

from ..conftest import SPOT, merge

C = 299792458.0


def test_nonlinear_chirp_phase_against_long_double():
    c2, c3 = 5.58e18, 8.58e22
    sc = parse_scenario(merge(SPOT, waveform__nonlinearity=[c2, c3], scene={"points": [{"x": 0.0, "y": 0.6}]}))
    col = build_collection(sc)
    raw = simulate(sc)
    s = raw["signal"].values
    t = raw["fast_time"].values.astype(np.longdouble)
    p = sc.scene.points[0]
    R = np.linalg.norm(np.array([p.x, p.y, p.z]) - col.positions, axis=1).astype(np.longdouble)
    d = 2 * (R - col.reference_range.astype(np.longdouble)) / np.longdouble(C)
    f0, k = np.longdouble(C) / np.longdouble(1.55e-6), np.longdouble(7.5e14)

    def phi(x):  # transmitted phase in cycles
        return f0 * x + k * x ** 2 / 2 + np.longdouble(c2) * x ** 3 / 3 + np.longdouble(c3) * x ** 4 / 4
    cyc = phi(t[None, :] - d[:, None]) - phi(t[None, :])
    ref = np.exp(2j * np.pi * (cyc - np.floor(cyc)).astype(np.float64))
    ratio = s / ref
    assert np.max(np.abs(np.angle(ratio))) < 1e-3
    # and the nonlinearity matters: without it the phase differs by more than 1 rad somewhere
    lin = np.exp(2j * np.pi * ((-(f0 + k * t[None, :]) * d[:, None] + k * d[:, None] ** 2 / 2) % 1).astype(np.float64))
    assert np.max(np.abs(np.angle(s / lin))) > 1.0


def test_beam_first_null_gives_no_echo():
    sc = parse_scenario(SPOT)
    col = build_collection(sc)
    R = 5000.0
    null = 1.2196698912665045 * sc.waveform.wavelength / sc.platform.real_aperture * R
    pos = np.array([[0.0, 0.0, 0.0], [null, 0.0, 0.0]])
    t = fast_time_axis(32, sc.receiver.adc_rate)
    s0 = echo_signal(col, pos[:1], np.array([1.0 + 0j]), sc, t)
    s1 = echo_signal(col, pos[1:], np.array([1.0 + 0j]), sc, t)
    assert np.abs(s0).mean() == pytest.approx(1.0, abs=1e-3)
    assert np.abs(s1).max() < 0.02


def test_photon_noise_statistics():
    from salkit.params.models import Noise
    from salkit.simulate import photon_noise
    rng = np.random.default_rng(5)
    for model in ("gaussian", "poisson"):
        nz = Noise(enabled=True, model=model, lo_photons=1e6 * 64, quantum_efficiency=0.8, mixing_efficiency=0.9)
        s = np.zeros((400, 64), np.complex64) + np.complex64(0.5 + 0.25j)
        photon_noise(s, nz, rng)
        assert np.mean(s) == pytest.approx(0.5 + 0.25j, abs=0.01)
        assert np.var(s) == pytest.approx(1.0, rel=0.03)  # unit shot-noise variance per sample
