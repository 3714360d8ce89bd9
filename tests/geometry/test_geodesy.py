"""Placing the scene frame on the earth (pyproj, WGS84) against the ellipsoid's own geometry and
against sarkit's independent east-north-up frame."""
import math

import numpy as np
import pytest

from salkit.geometry.geodesy import check_origin, enu_to_geodetic

A, F = 6378137.0, 1 / 298.257223563
E2 = F * (2 - F)


@pytest.mark.parametrize("lat", [0.0, 30.0, 45.0, 61.5, -33.9])
def test_a_small_step_north_and_east_follows_the_radii_of_curvature(lat):
    """1 m north moves the latitude by 1 / M (meridian radius), 1 m east the longitude by
    1 / (N cos lat) (prime vertical radius): to 1e-6 relative."""
    s = math.sin(math.radians(lat))
    M = A * (1 - E2) / (1 - E2 * s * s) ** 1.5
    N = A / math.sqrt(1 - E2 * s * s)
    la, lo, h = enu_to_geodetic([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]], (lat, 10.0, 0.0))
    assert math.radians(la[0] - lat) == pytest.approx(1 / M, rel=1e-6)
    assert math.radians(lo[1] - 10.0) == pytest.approx(1 / (N * math.cos(math.radians(lat))), rel=1e-6)
    assert abs(h[0]) < 1e-6 and abs(h[1]) < 1e-6


def test_agrees_with_sarkits_frame_to_a_millimetre():
    import sarkit.wgs84 as w
    rng = np.random.default_rng(0)
    for _ in range(5):
        llh = np.array([rng.uniform(-80, 80), rng.uniform(-180, 180), rng.uniform(-100, 3000)])
        enu = rng.uniform(-5000, 5000, 3)
        ecef = w.geodetic_to_cartesian(llh) + enu[0] * w.east(llh) + enu[1] * w.north(llh) + enu[2] * w.up(llh)
        ref = w.cartesian_to_geodetic(ecef)
        la, lo, h = enu_to_geodetic(enu, llh)
        assert abs(la - ref[0]) * 111e3 < 1e-3 and abs(lo - ref[1]) * 111e3 < 1e-3 and abs(h - ref[2]) < 1e-3


def test_bad_origins_are_refused():
    for bad in ([91, 0, 0], [0, 400, 0], [0, 0], [0, float("nan"), 0]):
        with pytest.raises(ValueError, match="latitude"):
            check_origin(bad)


def test_a_scenario_origin_reaches_the_image():
    """scene.origin: the raw data carry it, the image its pixels' geodetic positions."""
    import salkit
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    sc = parse_scenario(merge(SPOT, scene__origin=[-33.86, 151.21, 40.0]))
    img = salkit.focus(salkit.simulate(sc), sc.processing, scenario=sc)
    assert list(img.attrs["origin_llh"]) == [-33.86, 151.21, 40.0]
    assert img.attrs["center_latitude"] == pytest.approx(-33.86, abs=1e-7)
    with pytest.raises(salkit.ScenarioError, match="scene.origin"):
        parse_scenario(merge(SPOT, scene__origin=[95.0, 0.0, 0.0]))
