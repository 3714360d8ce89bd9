"""Nonlinear chirp corrections against the ideal linear chirp (seed 002, section 4.1 parameters)."""
import math

import numpy as np
import pytest

from salkit.focus.chirpcorr import (PhaseUnwrapError, correct_deskew, correct_paper, correct_resample,
                                    estimate_nonlinear_phase, reference_beat, spectral_width)
from salkit.focus.dechirp import deskew
from salkit.metrics.pointtarget import ipr_1d

C = 299792458.0
F0, K, TP = C / 1.55e-6, 5.44e14, 7.8e-6
COEFFS = (5.58e18 / 2, 8.58e22 / 6)  # f''/2, f'''/6: R1 = R2 = 50 (1 % of the sweep at the edge)
FS = 250e6
N = int(TP * FS) - 2
T = (np.arange(N) - N // 2) / FS
DR = (1.9 - 0.5) / C  # reference path 1.9 m, reference LO 0.5 m


def profile(sig, up=16):
    spec = np.fft.fftshift(np.fft.fft(sig, n=sig.size * up))
    return spec, FS / (sig.size * up)


def figures(sig):
    spec, df = profile(sig)
    m = ipr_1d(spec, df, K / FS * 0 + FS / N)
    return m["irw"], m["pslr_db"]


def _case(rng_m, coeffs):
    dz = 2 * rng_m / C
    ideal = deskew(reference_beat(T, F0, K, (), dz)[None], FS, K)[0]
    raw = reference_beat(T, F0, K, coeffs, dz)[None].astype(np.complex64)
    e = estimate_nonlinear_phase(reference_beat(T, F0, K, coeffs, DR), T, F0, K, DR)
    return ideal, raw, e


@pytest.mark.parametrize("rng_m", [5.0, 19.8645, 26.9355])
def test_resampling_reaches_the_ideal_at_seed_nonlinearity(rng_m):
    """R1 = R2 = 50: the reference-estimated chirp and resampling to uniform optical frequency give
    IRW within 5 % and PSLR within 1 dB of the linear chirp at every range; uncorrected fails."""
    ideal, raw, e = _case(rng_m, COEFFS)
    irw_i, pslr_i = figures(ideal)
    assert figures(deskew(raw, FS, K)[0])[0] > 1.5 * irw_i  # uncorrected: badly defocused
    irw, pslr = figures(deskew(correct_resample(raw, e, T, K), FS, K)[0])
    assert irw == pytest.approx(irw_i, rel=0.05)
    assert abs(pslr - pslr_i) < 1.0


@pytest.mark.parametrize("rng_m", [5.0, 26.9355])
def test_deskew_correction_reaches_the_ideal_in_its_regime(rng_m):
    """Meta et al.'s exp(+je) / deskew / exp(-je) is exact while the nonlinear frequency excursion
    is small against the beat spread (here R1 = R2 ~ 500, 69 rad of e); at the seed's R1 = R2 = 50
    (690 rad, +-42 MHz) the deskew's linear frequency-to-delay mapping breaks (docs/chirp.md)."""
    coeffs = tuple(0.1 * c for c in COEFFS)
    ideal, raw, e = _case(rng_m, coeffs)
    irw_i, pslr_i = figures(ideal)
    irw, pslr = figures(correct_deskew(raw, e, FS, K)[0])
    assert irw == pytest.approx(irw_i, rel=0.05)
    assert abs(pslr - pslr_i) < 1.0


def test_no_nonlinearity_every_method_is_ideal():
    dz = 2 * 20.0 / C
    raw = reference_beat(T, F0, K, (), dz)[None].astype(np.complex64)
    ref = reference_beat(T, F0, K, (), DR)
    e = estimate_nonlinear_phase(ref, T, F0, K, DR)
    assert np.max(np.abs(e)) < 1e-3
    ideal = figures(deskew(raw, FS, K)[0])
    for out in (correct_deskew(raw, e, FS, K)[0], deskew(correct_resample(raw, e, T, K), FS, K)[0]):
        assert figures(out)[0] == pytest.approx(ideal[0], rel=1e-3)


def test_paper_method_compresses_its_design_target():
    """Seed 002's method matched to target A (26.9355 m): the spectral width shrinks."""
    dz = 2 * 26.9355 / C
    raw = reference_beat(T, F0, K, COEFFS, dz)[None]
    ref = reference_beat(T, F0, K, COEFFS, DR)
    before = spectral_width(profile(raw[0])[0], profile(raw[0])[1])
    out = correct_paper(raw, ref, T, FS, (dz, 0.0), (DR, 0.0))[0]
    after = spectral_width(profile(out)[0], profile(out)[1])
    assert before / after > 5


def test_bad_references():
    with pytest.raises(PhaseUnwrapError, match="zero-length"):
        estimate_nonlinear_phase(np.ones(N, complex), T, F0, K, 0.0)
    rng = np.random.default_rng(0)
    noisy = reference_beat(T, F0, K, COEFFS, DR) + 3 * (rng.standard_normal(N) + 1j * rng.standard_normal(N))
    with pytest.raises(PhaseUnwrapError, match="too weak"):
        estimate_nonlinear_phase(noisy, T, F0, K, DR)


@pytest.mark.parametrize("alg", ["bp", "pfa"])
def test_imaging_with_nonlinear_chirp_and_correction(alg):
    """A spotlight scene collected with a 1 % nonlinear chirp: range IRW is broadened; with the
    reference channel and resampling it focuses to theory."""
    from salkit import focus, measure, simulate
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    c2 = 0.03 * 7.5e14 / 5e-6  # 3 % of the sweep at the pulse edge
    base = merge(SPOT, waveform__nonlinearity=[c2, c2 / (50 * 5e-6)],
                 scene={"points": [{"x": 0.0, "y": 0.8, "phase": 0.3}]},
                 receiver={"adc_rate": 20e6, "reference_channel": {"d_r": 1.9, "d_rlo": 0.5}},
                 processing__algorithm=alg)
    off = parse_scenario(base)
    on = parse_scenario(merge(base, processing__chirp_correction="resample"))
    raw = simulate(off)
    m_off = measure(focus(raw, off.processing))
    m_on = measure(focus(raw, on.processing), reflectivity_phase=0.3)
    assert m_off["irw_range_m"] > 1.5 * m_off["irw_range_theory_m"]
    assert m_on["irw_range_m"] == pytest.approx(m_on["irw_range_theory_m"], rel=0.03)
    assert abs(m_on["pslr_range_db"] - m_on["pslr_range_theory_db"]) < 0.5
    assert abs(m_on["peak_offset_range_m"]) < 0.1 * m_on["resolution_range_theory_m"]


def test_zero_length_reference_rejected():
    from salkit.errors import ScenarioError
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    with pytest.raises(ScenarioError, match="zero-length reference"):
        parse_scenario(merge(SPOT, receiver={"adc_rate": 20e6, "reference_channel": {"d_r": 1.0, "d_rlo": 1.0}}))


def test_nonlinearity_that_aliases_or_folds_is_rejected():
    from salkit.errors import SamplingError
    from salkit.geometry import check_sampling
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    pts = {"points": [{"x": 0.0, "y": 1.0}]}  # 0.8 m slant: beat 4 MHz linear; ADC 20 MHz
    ok = parse_scenario(merge(SPOT, scene=pts))
    check_sampling(ok)
    c2 = 0.3 * 7.5e14 / 5e-6  # instantaneous chirp rate 0.4 k .. 1.6 k: the beat outgrows a 9 MHz ADC
    with pytest.raises(SamplingError, match="chirp rate up to"):
        check_sampling(parse_scenario(merge(SPOT, scene=pts, receiver={"adc_rate": 9e6},
                                            waveform__nonlinearity=[c2])))
    with pytest.raises(SamplingError, match="non-monotonic"):
        check_sampling(parse_scenario(merge(SPOT, scene=pts, waveform__nonlinearity=[-3 * 7.5e14 / 5e-6])))


def test_paper_method_is_ideal_without_nonlinearity():
    dz = 2 * 26.9355 / C
    raw = reference_beat(T, F0, K, (), dz)[None]
    ref = reference_beat(T, F0, K, (), DR)
    ideal = figures(deskew(raw.astype(np.complex64), FS, K)[0])
    out = figures(correct_paper(raw, ref, T, FS, (dz, 0.0), (DR, 0.0))[0])
    assert out[0] == pytest.approx(ideal[0], rel=0.01)
    assert abs(out[1] - ideal[1]) < 0.3


def test_arbitrary_random_chirp_error_corrected():
    """A seeded random chirp phase error (5 rad RMS, 1 MHz): uncorrected, the range response of a
    target 27 m away breaks up; the Fourier estimate from the reference channel and Meta's deskew
    correction restore it (2 pi df_nl^2 / k ~ 0.3 rad: its regime). Resampling, first order in the
    delay, does not: the second-order term D^2 e''/2 is ~3 rad here (docs/chirp.md)."""
    from salkit.params.models import ChirpPhaseError
    tab = ChirpPhaseError(kind="random", rms=5.0, bandwidth=1e6, seed=3).table(TP)
    dz = 2 * 26.9355 / C
    dr = 4.0 / C
    ideal = figures(deskew(reference_beat(T, F0, K, (), dz)[None].astype(np.complex64), FS, K)[0])
    raw = reference_beat(T, F0, K, (), dz, tab)[None].astype(np.complex64)
    ref = reference_beat(T, F0, K, (), dr, tab)
    assert figures(deskew(raw, FS, K)[0])[1] > -5.0  # uncorrected: PSLR destroyed
    e = estimate_nonlinear_phase(ref, T, F0, K, dr, method="fourier", bandwidth=5e6)
    irw, pslr = figures(correct_deskew(raw, e, FS, K)[0])
    assert irw == pytest.approx(ideal[0], rel=0.05)
    assert abs(pslr - ideal[1]) < 1.0


def test_simulator_applies_arbitrary_chirp_error():
    from salkit.params import parse_scenario
    from salkit.simulate import simulate
    from ..conftest import SPOT, merge
    sc = parse_scenario(merge(SPOT, waveform__phase_error={"kind": "random", "rms": 5.0, "bandwidth": 2e6},
                              scene={"points": [{"x": 0.0, "y": 0.8}]}))
    raw = simulate(sc)
    tab = sc.waveform.phase_error.table(sc.waveform.pulse_width)
    t = raw["fast_time"].values
    from salkit.geometry import build_collection
    col = build_collection(sc)
    p = col.positions[0]
    d = 2 * (np.linalg.norm(np.array([0.0, 0.8, 0.0]) - p) - col.reference_range[0]) / C
    want = reference_beat(t, C / sc.waveform.wavelength, sc.waveform.rate, (), d, tab)
    got = raw["signal"].values[0]
    assert np.max(np.abs(np.angle(got * np.conj(want)))) < 0.02
