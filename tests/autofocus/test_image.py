"""autofocus(): dispatch on the method, refusal of the per-pulse method on an image."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.autofocus import autofocus, history_metrics
from salkit.errors import ScenarioError
from salkit.params import parse_scenario

from ..conftest import SPOT, merge


@pytest.fixture(scope="module")
def blurred():
    sc = parse_scenario(merge(SPOT, platform__phase_error={"kind": "quadratic", "amplitude": 6.0}))
    return focus(simulate(sc), sc.processing)


@pytest.mark.parametrize("method", ["pga", "min-entropy"])
def test_methods_sharpen(blurred, method):
    af, res = autofocus(blurred, method)
    peak = lambda ds: float(np.abs(ds["image"].values).max())  # noqa: E731
    assert peak(af) > 1.5 * peak(blurred)
    assert af.attrs["autofocus"] == method
    m = history_metrics(res)
    assert all(isinstance(v, (int, float)) for v in m.values())


def test_none_is_identity(blurred):
    af, _ = autofocus(blurred, "none")
    np.testing.assert_array_equal(af["image"].values, blurred["image"].values)


@pytest.mark.parametrize("method", ["pulse", "sharpest"])
def test_unknown_or_pulse_method_refused(blurred, method):
    with pytest.raises(ScenarioError):
        autofocus(blurred, method)
