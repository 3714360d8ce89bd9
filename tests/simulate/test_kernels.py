"""The numba echo kernels against the closed form, and the exact kernel against the fast one."""

import numpy as np
import pytest

from salkit.simulate.linewidth import NO_PHASE_NOISE
from salkit.geometry import build_collection
from salkit.geometry.collection import beam_gain_table
from salkit.params import parse_scenario
from salkit.simulate import echo_signal, fast_time_axis
from salkit.simulate.echoes import _NO_PATH
from salkit.simulate.kernels import simulate_exact

from ..conftest import GEO, SPOT


C = 299792458.0


def closed_form(col, pos, amp, sc, t):
    """g exp(-j 2 pi (f0 + k t) dtau + j pi k dtau^2) per pulse and sample, g = (2 J1(u)/u)^2."""
    from scipy.special import j1
    f0, k = C / sc.waveform.wavelength, sc.waveform.rate
    rel = pos[None, :, :] - col.positions[:, None, :]
    R = np.linalg.norm(rel, axis=2)
    cosb = np.einsum("pnk,pk->pn", rel, col.boresight) / R
    u = np.pi * sc.platform.real_aperture * np.sqrt(np.maximum(1 - cosb ** 2, 0)) / sc.waveform.wavelength
    g = np.where(u > 1e-12, (2 * j1(np.maximum(u, 1e-12)) / np.maximum(u, 1e-12)) ** 2, 1.0)
    amp = amp[None, :] * g
    dtau = 2 * (R - col.reference_range[:, None]) / C
    cyc = -(f0 + k * t[None, None, :]) * dtau[..., None] + 0.5 * k * dtau[..., None] ** 2
    return (amp[:, :, None] * np.exp(2j * np.pi * (cyc - np.floor(cyc)))).sum(axis=1)


@pytest.mark.parametrize("base", [SPOT, GEO])
def test_fast_kernel_matches_closed_form(base):
    sc = parse_scenario(base)
    col = build_collection(sc)
    pos = np.array([[0.0, 0.0, 0.0], [0.02, -0.03, 0.0], [-0.01, 0.04, 0.01]])
    amp = np.array([1.0, 0.5 * np.exp(1j), 0.3])
    t = fast_time_axis(64, sc.receiver.adc_rate)
    s = echo_signal(col, pos, amp, sc, t)
    ref = closed_form(col, pos, amp, sc, t)
    # float32 accumulation of unit-amplitude echoes: absolute error well below 1e-4
    assert np.max(np.abs(s - ref)) < 1e-4


def test_exact_kernel_equals_fast_for_linear_chirp(spot):
    col = build_collection(spot)
    rng = np.random.default_rng(0)
    pos = np.c_[rng.uniform(-0.5, 0.5, (20, 2)), np.zeros(20)]
    amp = rng.standard_normal(20) + 1j * rng.standard_normal(20)
    t = fast_time_axis(100, spot.receiver.adc_rate)
    fast = echo_signal(col, pos, amp, spot, t)
    table, dsin = beam_gain_table(spot.waveform.wavelength, spot.platform.real_aperture)
    re = np.zeros(fast.shape, np.float32)
    im = np.zeros(fast.shape, np.float32)
    w = spot.waveform
    simulate_exact(col.positions, col.velocity, col.reference_range, col.boresight, pos, amp.real.copy(),
                   amp.imag.copy(), t[0], t[1] - t[0], w.carrier_frequency, w.rate, w.pulse_width,
                   np.zeros(0), False, table, dsin, re, im, *_NO_PATH, np.zeros((0, 0), np.complex128), 0.0, 1.0,
                   np.zeros(0), *NO_PHASE_NOISE)
    np.testing.assert_allclose(re + 1j * im, fast, atol=1e-4)
