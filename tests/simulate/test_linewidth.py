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
