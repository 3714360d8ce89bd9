"""The parameter models: frozen, derived quantities, flags."""
import pytest
from pydantic import ValidationError

from salkit.errors import ScenarioError
from salkit.params import apply_overrides, dump_scenario, load_scenario, parse_scenario
from salkit.params.models import Waveform

from ..conftest import EXAMPLES, SPOT, merge


def test_objects_are_frozen(spot):
    with pytest.raises(ValidationError):
        spot.waveform.bandwidth = 1.0


def test_derived_quantities(spot):
    w = spot.waveform
    assert w.range_resolution == pytest.approx(299792458.0 / (2 * 7.5e9))
    assert w.rate == pytest.approx(7.5e9 / 10e-6)
    assert spot.platform.slant_range == pytest.approx(5000.0)


def test_waveform_nonlinearity_flag():
    w = Waveform(wavelength=1.55e-6, bandwidth=1e9, pulse_width=1e-5, prf=1e3, nonlinearity=(1e17,))
    assert not w.is_linear
