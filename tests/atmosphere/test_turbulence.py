"""Turbulence conversions and phase screens against theory."""
import math

import numpy as np
import pytest

from salkit.atmosphere import (combine_r0, cn2_from_r0, max_layer_spacing, phase_screens, r0_from_cn2, r0_path,
                               rytov_variance, structure_function, structure_function_estimate, turbulence_class)
from salkit.atmosphere.turbulence import PSD_CONST, SF_CONST
from salkit.errors import ScenarioError


def test_constants():
    assert SF_CONST == pytest.approx(6.88, abs=0.005)
    assert PSD_CONST == pytest.approx(0.023, abs=0.0002)
    # with kappa in rad/m the constant is 0.490: Phi_f(f) = Phi_kappa(2 pi f) (2 pi)^2
    assert PSD_CONST == pytest.approx(0.4898 * (2 * math.pi) ** (-5 / 3), rel=1e-3)


def test_r0_conversions():
    lam, Z = 2e-6, 1e4
    r0 = r0_from_cn2(1e-14, Z, lam)
    assert r0 == pytest.approx((0.423 * (2 * math.pi / lam) ** 2 * 1e-14 * Z) ** (-0.6))
    assert cn2_from_r0(r0, Z, lam) == pytest.approx(1e-14)
    assert r0_from_cn2(1e-14, Z, lam, "spherical") / r0 == pytest.approx((0.423 / 0.159) ** 0.6, rel=1e-9)
    # the seed's screen formula 1.17e-8 (1e6 lambda)^(6/5) / (Z Cn2)^(3/5) is the plane-wave r0
    seed = 1.17e-8 * (1e6 * lam) ** 1.2 / (Z * 1e-14) ** 0.6
    assert seed == pytest.approx(r0, rel=0.01)
    # a constant profile integrates to the same r0; 50 equal layers combine to it too
    z = np.linspace(0, Z, 51)
    assert r0_path(np.full(51, 1e-14), z, lam) == pytest.approx(r0, rel=1e-9)
    layers = r0_from_cn2(1e-14, Z / 50, lam) * np.ones(50)
    assert combine_r0(layers) == pytest.approx(r0, rel=1e-9)


def test_classes_spacing_rytov():
    assert turbulence_class(1e-16) == "very weak"
    assert turbulence_class(1e-15) == "weak"
    assert turbulence_class(1e-14) == "medium"
    assert turbulence_class(1e-13) == "strong"
    assert turbulence_class(1e-12) == "very strong"
    assert max_layer_spacing(1e-13, 2e-6) == pytest.approx(337.5, abs=0.1)  # the seed's 0.3375 km
    k = 2 * math.pi / 2e-6
    assert rytov_variance(1e-14, 1e4, 2e-6) == pytest.approx(1.23 * 1e-14 * k ** (7 / 6) * 1e4 ** (11 / 6))
    assert rytov_variance(1e-14, 1e4, 2e-6, "spherical") == pytest.approx(0.5 * 1e-14 * k ** (7 / 6) * 1e4 ** (11 / 6))


@pytest.mark.parametrize("bad", [-1e-14, 0.0, float("nan")])
def test_bad_turbulence_inputs(bad):
    with pytest.raises(ScenarioError, match="cn2"):
        r0_from_cn2(bad, 1e4, 2e-6)
    with pytest.raises(ScenarioError):
        phase_screens(64, 0.01, bad if bad == bad else float("nan"))


def test_von_karman_limits():
    r = np.array([1e-3, 1e-2])
    kol = structure_function(r, 0.05)
    vk = structure_function(r, 0.05, outer_scale=1e7)
    assert vk == pytest.approx(kol, rel=0.01)  # huge L0 tends to Kolmogorov
    big = structure_function(np.array([1e3]), 0.05, outer_scale=1.0)
    from salkit.atmosphere import phase_variance
    assert big[0] == pytest.approx(2 * phase_variance(0.05, 1.0), rel=1e-6)  # saturates at 2 sigma^2
    # inner scale: for r << l0, D = 4 pi^3 r^2 int Phi f^3 df = 4 pi^3 C r0^(-5/3) fm^(1/3) Gamma(1/6)/2 r^2
    from scipy.special import gamma
    r = np.array([1e-5, 1e-4])
    li = structure_function(r, 0.05, outer_scale=1e7, inner_scale=0.01)
    fm = 5.92 / (2 * math.pi * 0.01)
    asym = 4 * math.pi ** 3 * PSD_CONST * 0.05 ** (-5 / 3) * fm ** (1 / 3) * gamma(1 / 6) / 2 * r ** 2
    assert li == pytest.approx(asym, rel=0.02)
    ratio = li / structure_function(r, 0.05)  # r^2 against r^(5/3): the ratio goes as r^(1/3)
    assert ratio[0] / ratio[1] == pytest.approx(10 ** (-1 / 3), rel=0.01)


def test_spectral_constants_are_their_gamma_expressions_to_the_last_bit():
    """The module writes its constants as numbers (scipy.special loads on first use, not at import):
    they are the gamma-function expressions exactly, and 0.023 / 6.88 as the literature rounds them."""
    import math
    from scipy import special
    from salkit.atmosphere import turbulence as t
    g = special.gamma
    assert t.PSD_CONST == (g(11 / 6) ** 2 / (2 * math.pi ** (11 / 3))) * (24 / 5 * g(6 / 5)) ** (5 / 6)
    assert t.SF_CONST == 2 * (24 / 5 * g(6 / 5)) ** (5 / 6)
    assert t.VK_CONST == (g(11 / 6) / (2 ** (5 / 6) * math.pi ** (8 / 3))) * (24 / 5 * g(6 / 5)) ** (5 / 6)
    assert t.GAMMA_5_6 == g(5 / 6)
    assert round(t.PSD_CONST, 3) == 0.023 and round(t.SF_CONST, 2) == 6.88
