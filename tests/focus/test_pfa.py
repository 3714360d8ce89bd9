"""PFA never aliases: a grid smaller than the illuminated scene is formed on a covering extent."""
import numpy as np

from salkit import focus, simulate
from salkit.focus import phase_history
from salkit.focus.pfa import illuminated_extent, pfa_on_grid
from salkit.geometry.collection import grid_axes, plane_from
from salkit.params import parse_scenario

from ..conftest import SPOT, merge


def _corr(a, b):
    a, b = np.abs(a).ravel(), np.abs(b).ravel()
    a, b = a - a.mean(), b - b.mean()
    return float(a @ b / np.linalg.norm(a) / np.linalg.norm(b))


def test_small_grid_in_large_speckled_scene():
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.1, "y": -0.05, "amplitude": 3.0}],
                                           "extended": {"kind": "pattern", "pattern": "uniform",
                                                        "extent": [4.0, 4.0], "spacing": 0.008}},
                              receiver__adc_rate=25e6,
                              processing__grid={"nx": 64, "ny": 64, "dx": 0.015, "dy": 0.015}))
    raw = simulate(sc)
    bp = focus(raw, algorithm="bp")["image"].values
    img = focus(raw, algorithm="pfa")
    assert img.attrs["cover_azimuth"] > 64 and img.attrs["cover_range"] > 64
    assert _corr(bp, img["image"].values) >= 0.99
    # without the cover the scene folds in: the check is not vacuous
    ph = phase_history(raw)
    pl = plane_from(ph.track, ph.center_position, "slant")
    az, rg = grid_axes(sc.processing.grid)
    folded, _ = pfa_on_grid(ph.data, ph.freq, ph.positions, ph.reference_range, pl, az, rg, np.ones, np.ones)
    assert _corr(bp, folded) < 0.8
    ext = illuminated_extent(ph.freq, ph.positions, pl, ph.real_aperture)
    assert 3.0 < ext["azimuth"] < 4.5 and 3.0 < ext["range"] < 5.5


def test_aperture_wider_than_the_band_allows_is_refused_with_the_numbers():
    """Over a 60-degree arc the X-band pulses' annuli share no range frequencies (their direction
    cosines along range span a ratio of 1.069 in size, the band's frequencies 1.067): a
    ScenarioError naming both, not an IndexError from an empty K-space rectangle. A 30-degree arc
    is formed."""
    import pytest
    from salkit.errors import ScenarioError
    from salkit.focus.formers import ImageGrid, get_former
    from salkit.signals.windows import Window
    from salkit.simulate.testbeds import wide_angle
    for arc, ok in ((30.0, True), (60.0, False)):
        tb = wide_angle(arc, 0.5, "slant", pulses=256)
        pts, amp = tb.speckle(32, extent=1.0, density=0.05, seed=1)
        ph = phase_history(tb.dataset(pts, amp))
        ig = ImageGrid.of(ph, tb.grid(32))
        if ok:
            assert np.isfinite(get_former("pfa")(ph, ig, Window("none")).image).all()
        else:
            with pytest.raises(ScenarioError, match=r"share no band of range frequencies.* ratio of 1\.06[89].* ratio of 1\.067"):
                get_former("pfa")(ph, ig, Window("none"))
