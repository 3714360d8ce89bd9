"""Autofocus recovers injected, known phase errors."""
import numpy as np
import pytest
import scipy.fft as sfft

from salkit.autofocus import min_entropy, pga
from salkit.autofocus.pga import _detrend


def scene_with_error(kind, n=256, ny=128, seed=0, strength=1.0):
    """A band-limited speckle scene with bright points; a known azimuth phase error in the band."""
    rng = np.random.default_rng(seed)
    refl = (rng.standard_normal((n, ny)) + 1j * rng.standard_normal((n, ny))) * 0.1
    for _ in range(40):
        refl[rng.integers(n), rng.integers(ny)] += 8 * np.exp(2j * np.pi * rng.random())
    spec = sfft.fft(refl, axis=0)
    band = np.zeros(n, bool)
    nb = int(0.8 * n)
    band[sfft.ifftshift(np.arange(n))[(n - nb) // 2:(n - nb) // 2 + nb]] = True
    spec[~band] = 0
    k = sfft.fftshift(np.arange(n)) - n // 2  # centred index of each FFT bin
    t = k / (nb / 2)
    if kind == "quadratic":
        phi = 6.0 * t ** 2
    elif kind == "sinusoidal":
        phi = 1.0 * np.sin(2 * np.pi * 2.5 * t)  # 1 rad: the main lobe stays brightest (J0 > J1)
    else:  # random smooth (low-pass filtered noise)
        r = rng.standard_normal(n)
        r = np.real(sfft.ifft(sfft.fft(r) * (np.abs(sfft.fftfreq(n)) < 0.02)))
        phi = 1.5 * r / r.std()
    phi = strength * np.where(band, phi, 0.0)
    clean = sfft.ifft(spec, axis=0)
    blurred = sfft.ifft(spec * np.exp(1j * phi)[:, None], axis=0)
    return clean, blurred, phi, band


def residual_ratio(est, phi, band):
    """RMS of (estimate - truth) over the band after removing constant and linear terms, over the
    RMS of the detrended truth; in centred frequency order (the band wraps in FFT order)."""
    sel = np.flatnonzero(sfft.fftshift(band))
    true = _detrend(sfft.fftshift(phi)[sel])
    got = _detrend(sfft.fftshift(est)[sel])
    return np.sqrt(np.mean((got - true) ** 2)) / np.sqrt(np.mean(true ** 2))


@pytest.mark.parametrize("kind", ["quadratic", "sinusoidal", "random"])
@pytest.mark.parametrize("kernel", ["pd", "lumv", "ev"])
def test_pga_recovers_injected_error(kind, kernel):
    clean, blurred, phi, band = scene_with_error(kind)
    res = pga(blurred, kernel=kernel, band=band)
    assert residual_ratio(res.phase, phi, band) < 0.2
    assert res.history[-1]["entropy"] < res.history[0]["entropy"]
    from salkit.metrics import entropy
    assert entropy(res.image) < entropy(blurred)
    # most of the entropy the error added is gone
    assert entropy(res.image) - entropy(clean) <= 0.2 * (entropy(blurred) - entropy(clean))


@pytest.mark.parametrize("kind", ["quadratic", "sinusoidal", "random"])
def test_min_entropy_recovers_injected_error(kind):
    clean, blurred, phi, band = scene_with_error(kind)
    res = min_entropy(blurred, band=band)
    assert residual_ratio(res.phase, phi, band) < 0.2


def test_pga_never_worse_and_stops_on_focused_image():
    clean, _, _, band = scene_with_error("quadratic")
    res = pga(clean, band=band)
    from salkit.metrics import entropy
    assert entropy(res.image) <= entropy(clean) + 1e-9
    assert res.converged and len(res.history) - 1 < 30  # stopped by itself, well before max_iter


def test_more_iterations_never_worse():
    from salkit.metrics import entropy
    _, blurred, _, band = scene_with_error("random", seed=3)
    prev = np.inf
    for it in (1, 3, 10, 30):
        e = entropy(pga(blurred, max_iter=it, band=band).image)
        assert e <= prev + 1e-9
        prev = e


@pytest.mark.parametrize("method,alg", [("pga", "pfa"), ("pga", "bp"), ("min-entropy", "pfa")])
def test_end_to_end_phase_error_removed(tmp_path, method, alg):
    """A spotlight collection with a known per-pulse phase error (8 rad quadratic): focused, it is
    badly defocused; autofocus restores the azimuth IRW to theory."""
    from salkit import focus, measure, simulate
    from salkit.autofocus import autofocus
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    pts = [{"x": 0.0, "y": 0.0, "amplitude": 1.0}, {"x": 0.3, "y": 0.2, "amplitude": 0.8},
           {"x": -0.4, "y": -0.3, "amplitude": 0.8}, {"x": 0.2, "y": -0.5, "amplitude": 0.6}]
    sc = parse_scenario(merge(SPOT, processing__algorithm=alg, scene={"points": pts},
                              platform__phase_error={"kind": "quadratic", "amplitude": 8.0}))
    img = focus(simulate(sc), sc.processing)
    before = measure(img)
    assert before["irw_azimuth_m"] > 1.3 * before["irw_azimuth_theory_m"]
    af, res = autofocus(img, method)
    after = measure(af)
    assert after["irw_azimuth_m"] == pytest.approx(after["irw_azimuth_theory_m"], rel=0.05)
    assert after["entropy"] < before["entropy"]
