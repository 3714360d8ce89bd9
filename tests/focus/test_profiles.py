"""Range profiles and their interpolations: each interpolation's declared mean response is what
interpolating a tone at random positions between bins gives on average (so dividing it out
removes the mean error), and the profile of one scatterer peaks at its range."""
import numpy as np
import pytest

from salkit.constants import SPEED_OF_LIGHT
from salkit.errors import ScenarioError
from salkit.focus.profiles import INTERPOLATIONS, interpolation_of, keys_kernel, pack_profiles, range_profiles


def _interpolate(name, samples, x):
    """Read ``samples`` at positions ``x`` the way the kernel does."""
    i0 = np.floor(x).astype(int)
    t = x - i0
    if name == "nearest":
        return samples[i0 + (t >= 0.5)]
    if name == "linear":
        return samples[i0] + t * (samples[i0 + 1] - samples[i0])
    return sum(keys_kernel(t - k) * samples[i0 + k] for k in (-1, 0, 1, 2))


@pytest.mark.parametrize("name", list(INTERPOLATIONS))
def test_the_declared_gain_is_the_mean_response(name):
    nfft = 64
    rng = np.random.default_rng(3)
    x = rng.uniform(4, 60, 200000)
    for m in (3, 9, 16):  # tones up to a quarter of the band
        nu = m / nfft
        tone = np.exp(2j * np.pi * nu * np.arange(nfft + 4))
        mean = np.mean(_interpolate(name, tone, x) * np.exp(-2j * np.pi * nu * x))
        assert mean.real == pytest.approx(float(INTERPOLATIONS[name].gain(np.array([m]), nfft)[0]), abs=3e-3)


def test_cubic_is_exact_for_quadratics_and_the_gains_order():
    x = np.linspace(2.1, 5.9, 50)
    s = (np.arange(10) - 3.0) ** 2
    np.testing.assert_allclose(_interpolate("cubic", s, x), (x - 3.0) ** 2, atol=1e-12)
    m = np.array([16])
    g = {n: float(i.gain(m, 64)[0]) for n, i in INTERPOLATIONS.items()}
    assert max(g["nearest"], g["linear"]) < g["cubic"] < 1.0  # cubic attenuates the band edge least
    with pytest.raises(ScenarioError, match="interpolation = 'spline'"):
        interpolation_of("spline")


def test_one_scatterers_profile_peaks_at_its_range():
    M, df, dr0 = 256, 1e6, 3.7
    freq = 1.93e14 + (np.arange(M) - M // 2) * df
    ph = np.exp(-4j * np.pi * freq * dr0 / SPEED_OF_LIGHT)[None, :]
    prof, r0, dr, f_c = range_profiles(ph.astype(np.complex64), freq, 8, np.ones(M))
    k = int(np.argmax(np.abs(prof[0])))
    assert r0 + k * dr == pytest.approx(dr0, abs=dr)
    assert np.abs(prof[0]).max() == pytest.approx(M, rel=0.01)  # the transform sums the M samples
    assert pack_profiles(prof).shape == prof.shape + (4,)
