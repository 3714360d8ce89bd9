"""Measuring a salkit image (:func:`salkit.metrics.measure`): the IPR against theory, and the two
phases under their two names: the image's phase at its peak, and the target's phase (the
deterministic phase restored at the true position), which recovers the reflectivity's."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.metrics import measure
from salkit.metrics.table import undeclared
from salkit.params import parse_scenario

from ..conftest import SPOT, merge


@pytest.fixture(scope="module")
def image():
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.0, "y": 0.0, "phase": 1.1}]}))
    return focus(simulate(sc), scenario=sc)


def test_the_target_phase_recovers_the_reflectivity_and_the_image_phase_is_the_image(image):
    m = measure(image, reflectivity_phase=1.1)
    assert abs(m["peak_phase_error_rad"]) < 0.05 and abs(np.angle(np.exp(1j * (m["peak_phase_rad"] - 1.1)))) < 0.05
    img = image["image"].values
    i, j = np.unravel_index(np.abs(img).argmax(), img.shape)
    # the image's own phase at the peak: the brightest sample's, to the sub-pixel move of the peak
    assert abs(np.angle(np.exp(1j * (m["image_phase_at_peak_rad"] - np.angle(img[i, j]))))) < 0.5
    assert m["irw_range_m"] == pytest.approx(m["irw_range_theory_m"], rel=0.05)
    assert undeclared(m) == []


def test_without_the_truth_there_is_no_target_phase(image):
    bare = image.drop_vars([v for v in image.data_vars if v.startswith("target_")])
    m = measure(bare, reflectivity_phase=1.1)
    assert "image_phase_at_peak_rad" in m and "peak_phase_rad" not in m and "peak_phase_error_rad" not in m


def test_what_is_not_an_image_is_refused_saying_what_it_is(image):
    """measure(raw) raised KeyError "No variable named 'image'"; it now names the dataset's kind and
    the step it missed."""
    from salkit.errors import DataFileError
    sc = parse_scenario(SPOT)
    with pytest.raises(DataFileError, match=r"this is a dataset of salkit_kind 'raw' with signal.*focus it first"):
        measure(simulate(sc))
    with pytest.raises(DataFileError, match=r"needs a focused image.*this is an object of type ndarray"):
        measure(image["image"].values)


def test_the_numbers_are_plain_python_numbers(image):
    """Every metric is a Python float, int or bool (some were numpy scalars, printed as
    np.float64(...) beside the others); the details' cuts stay arrays."""
    m = measure(image, reflectivity_phase=1.1)
    assert all(type(v) in (float, int, bool) for v in m.values()), {k: type(v) for k, v in m.items()}
    d = measure(image, details=True)
    assert any(isinstance(v, np.ndarray) for k, v in d.items() if k.startswith("_"))


def test_the_truth_is_pairs_and_one_pair_is_one_target(image):
    """truth=[1, 2, 3] raised TypeError from inside; a (T, 2) array or one (azimuth, range) pair is taken."""
    from salkit.errors import ScenarioError
    one = measure(image, truth=(0.0, 0.0))
    assert one == measure(image, truth=np.zeros((1, 2))) and one["target_index"] == 0
    for bad in ([1, 2, 3], np.zeros((2, 3)), np.zeros((4, 2, 1)), "0,0", [[0, 0], [1]]):
        with pytest.raises(ScenarioError, match=r"truth = .*must be \(azimuth, range\) pairs in m"):
            measure(image, truth=bad)


def test_the_reflectivity_phase_must_be_phases(image):
    """reflectivity_phase="a" raised TypeError from inside (float minus str)."""
    from salkit.errors import ScenarioError
    for bad in ("a", float("nan"), [[1.0, 2.0]]):
        with pytest.raises(ScenarioError, match=r"reflectivity_phase = .*must be a finite phase in rad"):
            measure(image, reflectivity_phase=bad)
    assert measure(image, reflectivity_phase=[1.1])["peak_phase_error_rad"] == measure(
        image, reflectivity_phase=1.1)["peak_phase_error_rad"]
