"""Point-target figures of merit against the closed forms: sinc IRW, PSLR, ISLR; window theory."""
import math

import numpy as np
import pytest

from salkit.metrics import analyse_point, contrast, entropy, ipr_1d
from salkit.metrics.pointtarget import window_ipr


def test_ideal_sinc_figures():
    dx = 0.001
    x = np.arange(-2000, 2001) * dx
    m = ipr_1d(np.sinc(x / 0.1), dx, 0.1)
    assert m["irw"] == pytest.approx(0.8859 * 0.1, rel=1e-3)
    assert m["pslr_db"] == pytest.approx(-13.26, abs=0.01)
    assert m["islr_db"] == pytest.approx(-10.16, abs=0.05)  # +-10 cells; -9.68 dB over all sidelobes


def test_window_theory_values():
    assert window_ipr("none")["irw_factor"] == pytest.approx(0.886, abs=1e-3)
    h = window_ipr("hamming")
    assert h["irw_factor"] == pytest.approx(1.30, abs=0.01)
    assert h["pslr_db"] == pytest.approx(-42.7, abs=0.5)
    t = window_ipr("taylor", 4, 35.0)
    assert t["pslr_db"] == pytest.approx(-35.0, abs=0.5)


@pytest.mark.parametrize("carrier", [(0.0, 0.0), (0.31, -0.22), (0.45, 0.4)])
def test_2d_analysis_with_carrier_and_subpixel_offset(carrier):
    d, rho = 0.015, 0.02
    x = (np.arange(128) - 64) * d
    x0, y0 = 0.0037, -0.0051
    X, Y = np.meshgrid(x, x, indexing="ij")
    img = np.sinc((X - x0) / rho) * np.sinc((Y - y0) / rho) * np.exp(
        2j * np.pi * (carrier[0] * (X - x0) / d + carrier[1] * (Y - y0) / d) + 0.9j)
    m = analyse_point(img, x, x, rho, rho)
    assert m["irw_azimuth_m"] == pytest.approx(0.886 * rho, rel=0.005)
    assert m["peak_azimuth_m"] == pytest.approx(x0, abs=rho / 100)
    assert m["peak_range_m"] == pytest.approx(y0, abs=rho / 100)
    assert m["pslr_range_db"] == pytest.approx(-13.26, abs=0.1)


def _circle(pulses: int, f0: float, band: float, freqs: int = 64, elev_deg: float = 45.0):
    """A full circle of pulses around the scene centre, and the plane's axes (ground)."""
    phi = 2 * np.pi * np.arange(pulses) / pulses
    e = math.radians(elev_deg)
    pos = 7000.0 * np.stack([np.cos(e) * np.cos(phi), np.cos(e) * np.sin(phi), np.full_like(phi, np.sin(e))], axis=1)
    freq = f0 + (np.arange(freqs) - freqs // 2) * band / freqs
    return pos, freq, np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0]), math.cos(e)


@pytest.mark.parametrize("win", ["none", "hamming", "taylor"])
def test_support_ipr_of_a_narrow_aperture_is_the_windows(win):
    """A straight track's support is a rectangle: the window's figures times c/(2B), lambda/(2 dtheta)."""
    from salkit.metrics.pointtarget import support_ipr
    x = np.linspace(-5.0, 5.0, 301)
    pos = np.stack([x, np.zeros_like(x), np.full_like(x, 2000.0)], axis=1)
    B, f0, M = 2e9, 2e11, 200
    freq = f0 + (np.arange(M) - M // 2) * B / M
    rr, ra = 299792458.0 / (2 * B), 299792458.0 / f0 / (2 * 10.0 / 2000.0 * 301 / 300)
    t = support_ipr(pos, freq, np.array([1.0, 0, 0]), np.array([0, 0, -1.0]), ra, rr, win)
    w = window_ipr(win)
    for ax, res in (("range", rr), ("azimuth", ra)):
        assert t[f"irw_{ax}"] == pytest.approx(w["irw_factor"] * res, rel=2e-3)
        assert t[f"pslr_{ax}"] == pytest.approx(w["pslr_db"], abs=0.1)
        assert t[f"islr_{ax}"] == pytest.approx(w["islr_db"], abs=0.1)


def test_support_ipr_of_a_full_circle_is_a_bessel_j0():
    """A full circle of a narrow band: a thin annulus of radius K = 4 pi f cos(elev) / c, whose
    response is J0(K r) on both axes (IRW 2 x 1.1264 / K, first sidelobe J0^2 = -7.90 dB)."""
    from scipy.optimize import brentq
    from scipy.special import j0, jn_zeros
    from salkit.metrics.pointtarget import support_ipr
    pos, freq, a, r, ce = _circle(720, 3e14, 3e11)  # 0.1 % band
    K = 4 * np.pi * 3e14 * ce / 299792458.0
    x_half = brentq(lambda x: j0(x) ** 2 - 0.5, 0.5, 2.0)
    first = jn_zeros(1, 1)[0]  # J0' = -J1 = 0: the first sidelobe's peak
    res = 2 * np.pi / (2 * K)
    t = support_ipr(pos, freq, a, r, res, res)
    for ax in ("range", "azimuth"):
        assert t[f"irw_{ax}"] == pytest.approx(2 * x_half / K, rel=5e-3)
        assert t[f"pslr_{ax}"] == pytest.approx(20 * math.log10(abs(j0(first))), abs=0.05)


def test_analysis_of_a_wide_band_whose_power_sits_at_its_edges():
    """The analysis' carrier is the middle of the band the chip occupies, not the circular mean of
    its power: a full circle's disc of support, sampled at 0.8 of its resolution, projects with its
    power at the band's edges, where the mean would point into the gap (PSLR 1.5 dB off before)."""
    from salkit.metrics.pointtarget import support_ipr
    pos, freq, a, r, ce = _circle(360, 3e14, 3e12)
    c = 299792458.0
    res = c / (4 * freq[freq.size // 2] * ce)  # 2 pi over the disc's diameter at the reference frequency
    t = support_ipr(pos, freq, a, r, res, res)
    u = pos / np.linalg.norm(pos, axis=1)[:, None]
    k = 4 * np.pi / c * freq[::4]
    for offset in (0.0, 0.37):
        x = (np.arange(-32, 33) + offset) * 0.8 * res
        img = np.exp(1j * np.outer(x, np.outer(u @ a, k).ravel())) @ np.exp(1j * np.outer(np.outer(u @ r, k).ravel(), x))
        m = analyse_point(img, x, x, res, res)
        for ax in ("range", "azimuth"):
            assert m[f"irw_{ax}_m"] == pytest.approx(t[f"irw_{ax}"], rel=0.01)
            assert m[f"pslr_{ax}_db"] == pytest.approx(t[f"pslr_{ax}"], abs=0.1)


@pytest.mark.parametrize("L,reach_cells", [(1 << 17, 20.0), (1 << 12, 900.0), (1 << 15, 0.5)])
def test_support_offsets_are_the_full_transforms_cut(L, reach_cells):
    """The support theory transforms its deposit onto the offsets it keeps alone (a chirp-z
    transform where they are few of the L): the same values as the whole L-point FFT, cut and
    divided by the deposit's taper, to 1e-9 of the peak, and the same offsets."""
    from salkit.metrics.pointtarget import _offsets_transform
    rng = np.random.default_rng(int(reach_cells))
    H = np.abs(rng.normal(size=2049)) * np.hanning(2049)
    dx = 1e-3
    reach = reach_cells * 64 * dx
    j = np.arange(L) - L // 2
    full = np.abs(np.fft.fftshift(np.fft.fft(H, L))) / np.sinc(j / L) ** 2
    want = full[np.abs(j) * dx <= reach]
    got = _offsets_transform(H, L, dx, reach)
    assert got.shape == want.shape
    assert np.max(np.abs(got - want)) <= 1e-9 * want.max()
