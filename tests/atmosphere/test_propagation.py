"""``salkit propagate``'s experiment: an ensemble measured against theory, every figure declared in
the table of metrics, and a wave that is neither plane nor spherical refused."""
import numpy as np
import pytest

from salkit.atmosphere.propagation import propagation_result
from salkit.errors import SamplingError
from salkit.metrics.table import undeclared


def test_a_plane_wave_ensemble_and_its_figures():
    ds, m = propagation_result("plane", 1.55e-6, 1e-14, 1000.0, 3, seed=2)
    assert ds["field"].shape[0] == 3 and ds["x"].attrs["units"] == "m"
    assert m["scintillation_index_theory"] == pytest.approx(m["rytov_variance"], rel=0.1)  # weak: sigma_I^2 ~ sigma_R^2
    assert np.isfinite(m["scintillation_index"]) and m["r0_spherical_m"] > m["r0_plane_m"]  # spherical r0 = 1.8 x plane
    assert undeclared(m) == []
    again = propagation_result("plane", 1.55e-6, 1e-14, 1000.0, 3, seed=2)[0]
    np.testing.assert_array_equal(again["field"].values, ds["field"].values)  # seeded: repeats exactly


def test_an_unknown_wave_is_refused():
    with pytest.raises(SamplingError, match="--wave"):
        propagation_result("conical", 1.55e-6, 1e-14, 1000.0, 2)
