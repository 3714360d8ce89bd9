"""Wave-optics propagation: vacuum against the analytic Gaussian beam, periodic screens against
the Kolmogorov spectrum, plane-wave scintillation against Rytov theory in weak fluctuations
(ensembles, seeded), and the sampling plan's refusal of a case too big for memory."""
import math

import numpy as np
import pytest
import scipy.fft as sfft

from salkit.atmosphere import r0_from_cn2, rytov_variance
from salkit.atmosphere.scintillation import (scintillation_index, scintillation_theory)
from salkit.atmosphere.waveoptics import periodic_screens, plan_sampling, plane_wave_ensemble, propagate
from salkit.errors import SamplingError


def test_vacuum_gaussian_beam_matches_the_analytic_beam():
    """A w0 = 2 cm beam at 1 um over 500 m (z/zR = 0.4): field within 1e-3 of
    (w0/w) exp(-r^2/w^2) exp(+j k r^2 / 2R - j psi) (exp(+j k z) convention, carrier left out);
    the angular spectrum is exact for this band-limited beam (4e-16 here)."""
    lam, w0, z, n, dx = 1e-6, 0.02, 500.0, 512, 0.001
    x = (np.arange(n) - n // 2) * dx
    r2 = x[:, None] ** 2 + x[None, :] ** 2
    u = propagate(np.exp(-r2 / w0 ** 2), lam, dx, z)
    zr = math.pi * w0 ** 2 / lam
    w = w0 * math.sqrt(1 + (z / zr) ** 2)
    R = z * (1 + (zr / z) ** 2)
    psi = math.atan(z / zr)
    k = 2 * math.pi / lam
    exact = (w0 / w) * np.exp(-r2 / w ** 2) * np.exp(1j * k * r2 / (2 * R) - 1j * psi)
    assert np.linalg.norm(u - exact) / np.linalg.norm(exact) < 1e-3


def test_periodic_screens_follow_the_kolmogorov_spectrum():
    """Ensemble power per FFT cell within 10 % of 0.023 r0^(-5/3) f^(-11/3) df^2, along the axes
    and the diagonal (an edge would add f^-2 leakage along the axes)."""
    n, dx, r0 = 64, 0.01, 0.1
    ph = periodic_screens(n, dx, r0, 400, np.random.default_rng(5))
    P = np.mean(np.abs(sfft.fft2(ph)) ** 2, axis=0) / n ** 4
    f = sfft.fftfreq(n, dx)
    df = 1 / (n * dx)
    for i, j in ((1, 0), (4, 0), (16, 0), (31, 0), (4, 4), (16, 16)):
        th = 0.023 * r0 ** (-5 / 3) * math.hypot(f[i], f[j]) ** (-11 / 3) * df ** 2
        assert P[i, j] == pytest.approx(th, rel=0.15), (i, j)


@pytest.mark.parametrize("rytov", [0.05, 0.2, 0.5])
def test_plane_wave_scintillation_within_10_percent_of_rytov_theory(rytov):
    """Weak fluctuations: the scintillation index of a plane wave after 2 km at 1 um, over an
    ensemble of 24 realisations, within 10 % of sigma_R^2 = 1.23 Cn2 k^(7/6) L^(11/6) (and of the
    Andrews-Phillips expression, which equals it here within 6 %)."""
    lam, L = 1e-6, 2000.0
    k = 2 * math.pi / lam
    cn2 = rytov / (1.23 * k ** (7 / 6) * L ** (11 / 6))
    assert rytov_variance(cn2, L, lam) == pytest.approx(rytov)
    fields, s = plane_wave_ensemble(lam, L, cn2, count=24, seed=7)
    si = scintillation_index(fields)
    assert si == pytest.approx(rytov, rel=0.10)
    assert si == pytest.approx(scintillation_theory(rytov), rel=0.12)


def test_vacuum_plane_wave_stays_uniform():
    fields, _ = plane_wave_ensemble(1e-6, 1000.0, 0.0, count=1)
    assert scintillation_index(fields) < 1e-20


def test_sampling_plan_and_refusal():
    lam, L = 1.55e-6, 1000.0
    s = plan_sampling(lam, L, 1e-14)
    r0 = r0_from_cn2(1e-14, L, lam)
    assert s.dx <= min(r0, math.sqrt(lam * L)) / 4 + 1e-12 and s.layers >= 10
    assert rytov_variance(1e-14, s.dz, lam) <= 0.1
    with pytest.raises(SamplingError, match="more than"):
        plan_sampling(2e-6, 50e3, 1e-13)


