"""Sub-apertures and their images: geometric correction across squint, the lean sub-image path
against focus()."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.params import load_scenario, parse_scenario
from salkit.stack import geo_base, subaperture, subimage

from ..conftest import EXAMPLES, GEO, merge


def test_corrected_subimages_match_across_squint():
    """High SNR, smooth (speckle-free) target: the geometrically corrected sub-images at -5, 0 and
    +5 deg agree (normalised correlation of the magnitudes >= 0.95)."""
    sc = parse_scenario(merge(GEO, platform__real_aperture=0.05, scene={"extended": {
        "kind": "pattern", "pattern": "satellite", "extent": [2.0, 1.5], "spacing": 0.02, "speckle": False}},
        processing={"algorithm": "bp", "grid": {"nx": 64, "ny": 48, "dx": 0.04, "dy": 0.04}}))
    ims = {q: np.abs(subimage(sc, q, 0, noise=False)) for q in (-5.0, 0.0, 5.0)}
    for q in (-5.0, 5.0):
        a, b = ims[q].ravel(), ims[0.0].ravel()
        corr = np.dot(a - a.mean(), b - b.mean()) / (np.std(a) * np.std(b) * a.size)
        assert corr >= 0.95, (q, corr)


@pytest.mark.parametrize("accuracy", ["standard", "high"])
def test_subimage_is_the_focused_image(accuracy):
    """The lean sub-image path (the former alone) gives exactly what focus() gives, at either accuracy."""
    base = geo_base(load_scenario(EXAMPLES / "spaceborne_geo.yaml", [f"processing.accuracy={accuracy}"]))
    sc = subaperture(base, 1.5, base.seed)
    raw = simulate(sc, noise=False, rng=np.random.default_rng(base.seed))
    np.testing.assert_array_equal(subimage(base, 1.5, 0, noise=False), focus(raw, sc.processing)["image"].values)
