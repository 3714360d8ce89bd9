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


def test_zero_cn2_is_the_turbulence_free_path():
    """atmosphere.cn2 = 0 drops the atmosphere (a Cn2 sweep may start at 0); negative values and a
    profile with a zero layer are still refused, naming the field."""
    sc = parse_scenario(merge(SPOT, atmosphere={"cn2": 0.0, "layers": 10}))
    assert sc.atmosphere is None and sc == parse_scenario(SPOT)
    for bad in (-1e-15, [0.0] * 10):
        with pytest.raises(ScenarioError, match="cn2"):
            parse_scenario(merge(SPOT, atmosphere={"cn2": bad, "layers": 10}))
