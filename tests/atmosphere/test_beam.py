"""Wave-optics transmit beam and two-way gains: vacuum against the Fresnel diffraction of a
uniform disc, the sign convention shared with the phase-screen model, agreement with the ray
phases in weak turbulence, transmit scintillation against the spherical-wave Rytov variance
(seeded ensemble), and the plan's refusal of a case too big for memory."""
import dataclasses
import math

import numpy as np
import pytest
from scipy.special import j0

from salkit.atmosphere.beam import (plan_beam, plan_for_path, sample_field, screen_need, transmit_field,
                                    two_way_gains)
from salkit.atmosphere.path import build_path, two_way_phases
from salkit.errors import SamplingError
from salkit.simulate.echoes import _path_args

LAM, L, D = 2e-6, 1e4, 0.04
U0 = np.array([0.0, -0.8, 0.6])
TRACK = np.array([1.0, 0.0, 0.0])


def _fresnel_disc(x):
    """Exact Fresnel field of a uniform disc of diameter D at L, geometric phase removed, over its
    value on the axis: int_0^a exp(j k rho^2 / 2L) J0(k rho r / L) rho d rho."""
    k = 2 * math.pi / LAM
    rho = np.linspace(0, D / 2, 4001)
    v = np.array([np.trapezoid(np.exp(1j * k * rho ** 2 / (2 * L)) * j0(k * rho * abs(r) / L) * rho, rho) for r in x])
    return v / v[np.argmin(np.abs(x))]


def test_vacuum_beam_matches_the_fresnel_disc():
    """The planned grid reproduces the disc's Fresnel pattern (main lobe, first null at 0.61 m and
    first sidelobe) within 3e-3 of the on-axis field, along both axes."""
    z = (np.arange(50) + 0.5) * L / 50
    s = plan_beam(LAM, L, D, 1.22, math.inf, z)
    t = transmit_field(s, LAM, D)
    x = np.linspace(-0.7, 0.7, 57)
    ref = _fresnel_disc(x)
    for c in (np.stack([x, 0 * x], 1), np.stack([0 * x, x], 1)):
        g = sample_field(t, s.deltan, c) / t[0, 0]
        assert np.max(np.abs(g - ref)) < 3e-3


def _path(cn2, seed=3, n=700):
    return build_path(cn2, L, LAM, 50, n, 0.01, U0 * L, TRACK, seed=seed)


def _positions(count):
    return np.stack([np.linspace(-0.25, 0.25, count), np.full(count, -8000.0), np.full(count, 6000.0)], 1)


def test_gains_follow_the_phase_screen_sign_convention():
    """Constant screens of c rad on each of the 50 layers give every scatterer, at every pulse, the
    two-way gain of the vacuum times exp(+j 2 * 50 c): the phase the phase-screen model applies."""
    path = _path(1e-15)
    pos = _positions(3)
    tg = np.array([[0.0, 0.0, 0.0], [0.2, 0.1, 0.0]])
    s = plan_for_path(path, D, 1.22)
    flat0 = dataclasses.replace(path, screens=np.zeros_like(path.screens))
    flat = dataclasses.replace(path, screens=np.full_like(path.screens, 0.1))
    g0, _ = two_way_gains(flat0, pos, tg, D, 1.22, sampling=s)
    g1, _ = two_way_gains(flat, pos, tg, D, 1.22, sampling=s)
    np.testing.assert_allclose(g1, g0 * np.exp(1j * 2 * 50 * 0.1), atol=2e-5)
    assert abs(g0[0, 0] - 1) < 1e-6  # normalised to the vacuum boresight


def test_the_vacuum_reference_is_propagated_once_a_sampling(monkeypatch):
    """Two paths of other screens on one grid share the vacuum boresight field the gains are
    normalised by: the second call propagates its pulses only, and the reference it reuses is the
    vacuum propagation's own number (another grid gets its own)."""
    import salkit.atmosphere.beam as beam
    path = _path(1e-15, n=400)
    other = _path(1e-15, seed=4, n=400)
    s = plan_for_path(path, D, 1.22)
    beam._vacuum_boresight.cache_clear()
    calls = []
    real = beam.transmit_field
    monkeypatch.setattr(beam, "transmit_field", lambda *a, **k: calls.append(len(a) == 3) or real(*a, **k))
    tg = np.array([[0.0, 0.0, 0.0]])
    two_way_gains(path, _positions(2), tg, D, 1.22, sampling=s)
    two_way_gains(other, _positions(2), tg, D, 1.22, sampling=s)
    assert calls == [True, False, False, False, False]  # one vacuum propagation, then the four pulses
    assert beam._vacuum_boresight(s, path.wavelength, D) == complex(real(s, path.wavelength, D)[0, 0])
    coarser = dataclasses.replace(s, deltan=1.5 * s.deltan)
    assert beam._vacuum_boresight(coarser, path.wavelength, D) != beam._vacuum_boresight(s, path.wavelength, D)


def test_geometric_optics_limit_reproduces_the_ray_phase():
    """Screens whose eddies are all larger than the Fresnel zone (inner scale 1 m against
    sqrt(lambda L) = 0.14 m) are the geometric-optics limit, where the wave's phase is the ray's:
    the wave-optics two-way phase follows the ray model's pulse to pulse within 2 % of the phase's
    own RMS variation (mean removed). (The amplitude does change, by up to 10 % off axis: the
    screens' tilt makes the beam wander, which the phase-only model leaves out.)"""
    path = build_path(1e-15, L, LAM, 50, 700, 0.01, U0 * L, TRACK, seed=3, inner_scale=1.0)
    pos = _positions(11)
    tg = np.array([[0.0, 0.0, 0.0], [0.15, -0.1, 0.0]])
    g, _ = two_way_gains(path, pos, tg, D, 1.22)
    ray = two_way_phases(pos, tg, *_path_args(path))
    wo = np.unwrap(np.angle(g), axis=0)
    d = (wo - ray) - np.mean(wo - ray, axis=0)
    var = ray - ray.mean(axis=0)
    assert np.sqrt(np.mean(var ** 2)) > 0.3  # the screens move the phase by radians across the aperture
    assert np.sqrt(np.mean(d ** 2)) < 0.02 * np.sqrt(np.mean(var ** 2))


def test_transmit_scintillation_matches_the_spherical_rytov_variance():
    """A 1 cm aperture through 6 independent paths at spherical sigma_R^2 = beta_0^2 = 0.1: the
    intensity at the target, |g|^2 at 9 x 9 targets over 1 m (the Fresnel scale is 14 cm), has a
    scintillation index within 15 % of 0.1. Weak fluctuations: a point source gives beta_0^2; this
    beam (Lambda_0 = 2L / k W0^2 = 255) gives 0.94-0.96 beta_0^2 in Andrews and Phillips' Gaussian
    beam theory. Measured 0.094 here; 0.0996 (standard error 0.005) over 12 paths whose screens
    cover the whole grid (these 4 m screens are clamped beyond the beam, to keep the test short)."""
    k = 2 * math.pi / LAM
    cn2 = 0.1 / (0.5 * k ** (7 / 6) * L ** (11 / 6))
    ap = 0.01
    xs = np.linspace(-0.5, 0.5, 9)
    tg = np.array([[a, 0.6 * b, 0.8 * b] for a in xs for b in xs])  # in the plane across the line of sight
    inten = []
    for seed in range(6):
        path = _path(cn2, seed=seed, n=400)
        g, _ = two_way_gains(path, np.array([[0.0, -8000.0, 6000.0]]), tg, ap, 1.1)
        inten.append(np.abs(g[0]))  # |g^2| = |g|^2, the one-way intensity
    i = np.asarray(inten)
    si = np.mean(i ** 2) / np.mean(i) ** 2 - 1
    assert abs(si / 0.1 - 1) < 0.15, si


def test_plan_refuses_a_beam_too_big_for_memory():
    z = (np.arange(50) + 0.5) * L / 50
    with pytest.raises(SamplingError, match="4096"):
        plan_beam(LAM, L, D, 1.22, 0.002, z)


def test_screen_need_covers_the_grids_and_the_sweep():
    z = (np.arange(10) + 0.5) * L / 10
    s = plan_beam(LAM, L, D, 1.22, 0.05, z)
    ext = s.extents()
    assert screen_need(s, L, 0.5) >= ext[1:-1].max()
    assert screen_need(s, L, 0.5) <= ext[1:-1].max() + 0.5
