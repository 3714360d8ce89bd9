"""Range profiles and their interpolations: each interpolation's declared mean response is what
interpolating a tone at random positions between bins gives on average (so dividing it out
removes the mean error), and the profile of one scatterer peaks at its range."""
import numpy as np
import pytest

from salkit.constants import SPEED_OF_LIGHT
from salkit.errors import ScenarioError
from salkit.focus.profiles import (INTERPOLATIONS, interpolation_of, keys_kernel, pack_profiles, pad_profiles,
                                   profile_sampling, range_profiles, range_profiles_into)


def _interpolate(name, samples, x, M=33, nfft=64):
    """Read ``samples`` at positions ``x`` the way the kernel does (four-tap kernels with their
    coefficients for an M-sample band in an nfft-point profile)."""
    i0 = np.floor(x).astype(int)
    t = x - i0
    if name == "nearest":
        return samples[i0 + (t >= 0.5)]
    if name == "linear":
        return samples[i0] + t * (samples[i0 + 1] - samples[i0])
    if name == "cubic":
        return sum(keys_kernel(t - k) * samples[i0 + k] for k in (-1, 0, 1, 2))
    w = np.vander(t, 4, increasing=True) @ np.asarray(INTERPOLATIONS[name].coefficients(M, nfft)).T
    return sum(w[:, q] * samples[i0 + q - 1] for q in range(4))


@pytest.mark.parametrize("name", list(INTERPOLATIONS))
def test_the_declared_gain_is_the_mean_response(name):
    nfft, M = 64, 33
    rng = np.random.default_rng(3)
    x = rng.uniform(4, 60, 200000)
    ms = np.arange(M) - M // 2  # the profile's frequencies: tones up to a quarter of the band
    gain = INTERPOLATIONS[name].gain(ms, nfft)
    for m in (3, 9, 16):
        nu = m / nfft
        tone = np.exp(2j * np.pi * nu * np.arange(nfft + 4))
        mean = np.mean(_interpolate(name, tone, x, M, nfft) * np.exp(-2j * np.pi * nu * x))
        assert mean.real == pytest.approx(float(gain[ms == m][0]), abs=3e-3)


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


def _compensated_error_db(coefficients, M, nfft):
    """Error energy of a four-tap kernel over a white band of M of nfft frequencies and all
    fractions, its mean response divided out (what is left in the image)."""
    from salkit.focus.profiles import taps4_response
    nu = (np.arange(M) - M // 2) / nfft
    h = taps4_response(coefficients, nu, (np.arange(200) + 0.5) / 200)
    return 10 * np.log10(np.mean(np.abs(h / h.mean(axis=0) - 1.0) ** 2))


def test_the_fitted_kernel_beats_keys_and_lagrange_at_every_upsampling():
    """Fitted to the band, four taps at 4, 6, 8 bins a cell reach -73, -87, -97 dB; Keys' cubic
    -52, -63, -71 dB; 4-point Lagrange (exact for cubics) -61, -75, -85 dB."""
    from salkit.focus.profiles import KEYS_COEFFICIENTS, fitted_coefficients
    lagrange = np.array([[0, -1 / 3, 1 / 2, -1 / 6], [1, -1 / 2, -1, 1 / 2], [0, 1, 1 / 2, -1 / 2], [0, -1 / 6, 0, 1 / 6]])
    M = 200
    for up, want in ((4, -72.0), (6, -86.5), (8, -96.5)):
        fit = _compensated_error_db(fitted_coefficients(M, M * up), M, M * up)
        assert fit < want
        assert fit < _compensated_error_db(lagrange, M, M * up) - 11.0
        assert fit < _compensated_error_db(KEYS_COEFFICIENTS, M, M * up) - 20.0


@pytest.mark.parametrize("kernel", ["keys", "fitted", "ffbp"])
def test_symmetric_coefficients_rebuild_every_taps_weight(kernel):
    """Each tap's weight rebuilt from its pair's even and odd parts (E + O, its mirror E - O) is the
    weight of the kernel's own polynomial, at every fraction: Keys' cubic and a fitted kernel in t
    about 1/2, FFBP's eight-tap degree-6 weights in s = 2t - 1 about 0."""
    from salkit.focus.ffbp_leaves import polynomial_weights
    from salkit.focus.profiles import KEYS_COEFFICIENTS, fitted_coefficients, symmetric_coefficients
    c, centre = {"keys": (KEYS_COEFFICIENTS, 0.5), "fitted": (fitted_coefficients(738, 4428), 0.5),
                 "ffbp": (polynomial_weights(8, 1.75).astype(np.float64), 0.0)}[kernel]
    taps, n = c.shape
    sym = symmetric_coefficients(c, centre)
    assert sym.shape == (taps // 2 * n,)
    x = np.linspace(centre - 0.5, centre + 0.5, 41) if centre else np.linspace(-1, 1, 41)
    u = x - centre
    want = np.polynomial.polynomial.polyval(x, c.T)  # (taps, nx)
    for b in range(taps // 2):
        e = sym[n * b:n * b + (n + 1) // 2]
        o = sym[n * b + (n + 1) // 2:n * (b + 1)]
        even = np.polynomial.polynomial.polyval(u * u, e)
        odd = u * np.polynomial.polynomial.polyval(u * u, o)
        np.testing.assert_allclose(even + odd, want[b], atol=2e-6 * np.abs(c).max())
        np.testing.assert_allclose(even - odd, want[taps - 1 - b], atol=2e-6 * np.abs(c).max())


def test_symmetric_coefficients_refuse_a_lopsided_kernel():
    from salkit.focus.profiles import KEYS_COEFFICIENTS, symmetric_coefficients
    lopsided = np.array(KEYS_COEFFICIENTS, dtype=float)
    lopsided[0, 1] += 0.01
    with pytest.raises(ValueError, match="not symmetric about 0.5"):
        symmetric_coefficients(lopsided, 0.5)
    with pytest.raises(ValueError, match="3 taps, must be even"):
        symmetric_coefficients(np.ones((3, 4)), 0.5)


@pytest.mark.parametrize("interpolation", ["fitted", "linear"])
def test_profiles_into_a_kept_buffer_are_range_profiles_bit_for_bit(interpolation):
    """Blocks of pulses written one after another into one buffer, transformed in place, with the
    four-tap layout's zero bins around them: each block's rows are range_profiles' padded, the bits
    the same, and the rows a shorter last block leaves are not read."""
    rng = np.random.default_rng(5)
    M = 101
    freq = 9.6e9 + np.arange(M) * 2e6
    nfft, _ = profile_sampling(freq, 6)
    work = np.zeros((8, 1 + nfft + 2), np.complex64)
    for P in (8, 3):  # the second block shorter and into the buffer the first one filled
        ph = rng.standard_normal((P, M)) + 1j * rng.standard_normal((P, M))
        got = range_profiles_into(work, ph, freq, 6, np.hanning(M), True, interpolation, lead=1)
        prof, r0, dr, f_c = range_profiles(ph, freq, 6, np.hanning(M), True, interpolation)
        assert got == (r0, dr, f_c)
        assert np.array_equal(work[:P].view(np.float32), pad_profiles(prof))


def test_profiles_into_refuse_a_buffer_too_small():
    freq = 9.6e9 + np.arange(16) * 2e6
    with pytest.raises(ValueError, match="at least"):
        range_profiles_into(np.zeros((2, 20), np.complex64), np.ones((2, 16)), freq, 2, np.ones(16))
    with pytest.raises(ValueError, match="complex64"):
        range_profiles_into(np.zeros((2, 40), np.complex128), np.ones((2, 16)), freq, 2, np.ones(16))
