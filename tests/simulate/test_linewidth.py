"""Lasers of finite linewidth against theory (Monte Carlo, seeded): the beat's phase error has
variance 2 pi linewidth |tau - tau_LO| and a point's image loses exp(-sigma^2) of its peak power,
within 10 %, at 5 km and 200 km; an LO matched to the echo's delay removes it; a pulse's noise is
the same whichever block simulates it."""
import math

import numpy as np
import pytest

from salkit import focus, simulate
from salkit.constants import SPEED_OF_LIGHT
from salkit.params import parse_scenario
from salkit.simulate.linewidth import peak_power_loss, phase_noise_variance

from ..conftest import GEO, SPOT, merge

POINT = {"points": [{"x": 0.0, "y": 0.0}]}


def _scenario(base, linewidth, lo_delay=0.0, seed=0):
    return parse_scenario(merge(base, scene=POINT, waveform={**base["waveform"], "linewidth": linewidth},
                                receiver={**base["receiver"], "lo_delay": lo_delay}, seed=seed))


def _tau(sc):
    """Round-trip delay of the scene centre, s."""
    p = sc.platform
    return 2.0 * math.hypot(p.altitude, p.standoff) / SPEED_OF_LIGHT


@pytest.mark.parametrize("base,sigma2", [(SPOT, 0.3), (SPOT, 1.0), (GEO, 0.3), (GEO, 1.0)],
                         ids=["5km-0.3", "5km-1", "200km-0.3", "200km-1"])
def test_phase_error_variance_and_peak_loss_follow_theory(base, sigma2):
    clean = _scenario(base, 0.0)
    linewidth = sigma2 / (2 * math.pi * _tau(clean))  # an undelayed LO: the whole round trip
    raw0 = simulate(clean)
    img0 = np.abs(focus(raw0, scenario=clean)["image"].values).max()
    var, loss = [], []
    for seed in range(3):
        sc = _scenario(base, linewidth, seed=seed)
        raw = simulate(sc)
        a, b = raw["signal"].values, raw0["signal"].values
        lit = np.abs(b) > 0.5 * np.abs(b).max()
        var.append(np.var(np.angle(a[lit] / b[lit])))
        loss.append((np.abs(focus(raw, scenario=sc)["image"].values).max() / img0) ** 2)
    theory = phase_noise_variance(linewidth, _tau(clean))
    assert theory == pytest.approx(sigma2, rel=1e-9)
    if sigma2 < 0.5:  # wrapping leaves the variance alone only while |phase| stays well below pi
        assert np.mean(var) == pytest.approx(theory, rel=0.10)
    assert np.mean(loss) == pytest.approx(peak_power_loss(linewidth, _tau(clean)), rel=0.10)


def test_an_lo_matched_to_the_echo_removes_the_noise():
    undelayed = simulate(_scenario(SPOT, 20e3))
    matched = simulate(_scenario(SPOT, 20e3, lo_delay=None))  # the LO delayed to the reference range
    clean = simulate(_scenario(SPOT, 0.0))["signal"].values
    lit = np.abs(clean) > 0.5 * np.abs(clean).max()
    err = {k: np.var(np.angle(r["signal"].values[lit] / clean[lit])) for k, r in
           (("undelayed", undelayed), ("matched", matched))}
    assert err["matched"] < 0.01 * err["undelayed"]


def test_the_noise_of_a_pulse_does_not_depend_on_the_blocks():
    from salkit.simulate.sal import _Echoes
    sc = _scenario(SPOT, 5e3)
    echoes = _Echoes(sc, np.random.default_rng(0))
    P = echoes.col.n_pulses
    whole = echoes.block(0, P, noise=False)
    parts = np.concatenate([echoes.block(0, 100, noise=False), echoes.block(100, P, noise=False)])
    np.testing.assert_array_equal(parts, whole)
    np.testing.assert_array_equal(whole, simulate(sc)["signal"].values)  # and simulate draws the same


def test_the_expected_loss_is_exp_minus_sigma2_then_its_pedestal():
    from salkit.simulate.linewidth import expected_peak_power_loss
    tau, dt, v, w = 33e-6, 5e-8, np.ones(200), np.ones(243)
    for lw in (100.0, 1e3, 5e3):  # where exp(-sigma^2) >> 1/pulses the two agree
        assert expected_peak_power_loss(lw, tau, dt, v, w) == pytest.approx(peak_power_loss(lw, tau), rel=0.01)
    far = expected_peak_power_loss(1e8, tau, dt, v, w)  # every sample decorrelated: 1 / (pulses x samples)
    assert far == pytest.approx(1.0 / (243 * 200), rel=0.05)


def _referenced(linewidth, D, delta, correction="none", seed=0):
    """SPOT, a point at the scene centre, the LO delayed to ``delta`` before its echo, a reference
    channel of delay ``D``."""
    tau = 2.0 * math.hypot(SPOT["platform"]["altitude"], SPOT["platform"]["standoff"]) / SPEED_OF_LIGHT
    return parse_scenario(merge(SPOT, scene=POINT, seed=seed, waveform={**SPOT["waveform"], "linewidth": linewidth},
                                receiver={**SPOT["receiver"], "lo_delay": tau - delta,
                                          "reference_channel": {"d_r": D * SPEED_OF_LIGHT, "d_rlo": 0.0}},
                                processing={**SPOT["processing"], "phase_noise_correction": correction}))


def test_the_reference_channel_removes_the_noise_its_delay_matches():
    """A 10 ns reference channel (3 m of delay line), a laser of 4.8 MHz linewidth (sigma^2 0.3 at
    10 ns), the LO 5, 10 and 15 ns short of the echo: without the correction the echo's phase error
    has variance 2 pi linewidth delta; with it, 2 pi linewidth |delta - D| (nothing at delta = D),
    within 10 %, and so has the image's peak loss (3 seeds). The noise tables resolve the 10 ns
    (16 points over it, where the ADC samples every 50 ns)."""
    from salkit.focus.rangecomp import range_compress
    D = 10e-9
    lw = 0.3 / (2 * math.pi * D)
    clean = _referenced(0.0, D, D)
    raw0 = simulate(clean)
    ph0 = range_compress(raw0)["signal"].values
    lit = np.abs(ph0) > 0.5 * np.abs(ph0).max()
    peak0 = np.abs(focus(raw0, scenario=clean)["image"].values).max()
    for delta in (0.5 * D, D, 1.5 * D):
        for correction in ("none", "reference"):
            var, loss = [], []
            for seed in range(3):
                sc = _referenced(lw, D, delta, correction, seed)
                raw = simulate(sc)
                assert raw["reference_signal"].dims == ("slow_time", "fast_time")
                ph = range_compress(raw, "none", correction)["signal"].values
                var.append(np.var(np.angle(ph[lit] / ph0[lit])))
                loss.append((np.abs(focus(raw, scenario=sc)["image"].values).max() / peak0) ** 2)
            left = abs(delta - D) if correction == "reference" else delta
            theory = phase_noise_variance(lw, left)
            if left == 0:
                assert np.mean(var) < 0.01 * phase_noise_variance(lw, delta) and np.mean(loss) > 0.995
                continue
            assert np.mean(var) == pytest.approx(theory, rel=0.10), (delta, correction)
            assert np.mean(loss) == pytest.approx(peak_power_loss(lw, left), rel=0.10), (delta, correction)


def test_the_noise_correction_needs_a_reference_of_every_pulse():
    from salkit.errors import ScenarioError
    from salkit.focus.rangecomp import range_compress
    raw = simulate(_scenario(SPOT, 1e3))
    with pytest.raises(ScenarioError, match="phase_noise_correction"):
        range_compress(raw, "none", "reference")
