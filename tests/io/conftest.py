"""Shared fixtures of the io tests: one simulated collection and its image."""
import numpy as np
import pytest

from salkit import focus, simulate


def _ccorr(a, b):
    return float(abs(np.vdot(a, b)) / np.linalg.norm(a) / np.linalg.norm(b))


@pytest.fixture(scope="module")
def collection():
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.0, "y": 0.0}, {"x": 0.3, "y": -0.2, "amplitude": 0.7}]}))
    raw = simulate(sc)
    return sc, raw, focus(raw, sc.processing)["image"].values


@pytest.fixture
def files(tmp_path, spot):
    """A simulated raw file and its image file (paths), and the datasets."""
    from salkit.io import write_dataset
    raw = simulate(spot)
    img = focus(raw, spot.processing)
    return write_dataset(raw, tmp_path / "raw.nc"), write_dataset(img, tmp_path / "image.nc"), raw, img
