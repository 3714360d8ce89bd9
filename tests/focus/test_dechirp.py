"""Operations on dechirped samples: RVP removal and deskew against the closed form, the analytic
signal of real samples keeps the echoes' side of the spectrum."""
import numpy as np
import pytest

from salkit.focus.dechirp import analytic, deskew

C = 299792458.0


@pytest.mark.parametrize("dtau", [-60e-9, -5e-9, 0.0, 13e-9, 80e-9])
def test_deskew_removes_rvp_exactly(dtau):
    fs, k, f0 = 200e6, 7.5e14, C / 1.55e-6
    n = 2000
    t = (np.arange(n) - n // 2) / fs
    s = np.exp(2j * np.pi * ((-(f0 + k * t) * dtau + 0.5 * k * dtau ** 2) % 1.0))[None, :]
    rvp = np.pi * k * dtau ** 2
    out = deskew(s.astype(np.complex64), fs, k)[0]
    want = np.exp(2j * np.pi * ((-(f0 + k * t) * dtau) % 1.0))
    core = slice(n // 8, n - n // 8)  # away from the circular edges
    err = np.angle(out[core] * want[core].conj())
    assert np.max(np.abs(err)) < 2e-3, f"RVP {rvp:.3g} rad not removed"
    if rvp > 0.5:  # and it was really there
        assert np.max(np.abs(np.angle(s[0, core] * want[core].conj()))) > 0.4


@pytest.mark.parametrize("sideband,beat", [("negative", -3.1e6), ("positive", 2.3e6)])
def test_analytic_keeps_one_side(sideband, beat):
    fs, n = 20e6, 4000
    t = np.arange(n) / fs
    phase = 0.7
    real = np.cos(2 * np.pi * beat * t + phase)[None, :]
    out = analytic(real, sideband)[0]
    want = np.exp(1j * (2 * np.pi * beat * t + phase))
    core = slice(n // 8, n - n // 8)
    np.testing.assert_allclose(out[core], want[core], atol=2e-2)
    wrong = analytic(real, "positive" if sideband == "negative" else "negative")[0]
    np.testing.assert_allclose(wrong[core], want[core].conj(), atol=2e-2)  # the mirror image: the side is a choice
