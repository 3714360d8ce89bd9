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


def test_grid_spacing_auto_follows_the_resolution_through_a_sweep():
    """``dx: auto`` / ``dy: auto``: AUTO_GRID_FRACTION (one half) of the nominal resolution, kept as
    'auto' in the dumped scenario, so that a sweep of the bandwidth gets a finer pixel at each point
    (a fixed 1.5 cm pixel undersampled 12 GHz); a scenario without what it needs is refused naming dx."""
    import yaml

    from salkit.params.models import AUTO_GRID_FRACTION, nominal_resolution
    sc = parse_scenario(merge(SPOT, processing__grid__dx="auto", processing__grid__dy="auto"))
    res = nominal_resolution(SPOT)
    assert sc.processing.grid.dy == pytest.approx(AUTO_GRID_FRACTION * 299792458.0 / (2 * 7.5e9))
    assert sc.processing.grid.dx == pytest.approx(AUTO_GRID_FRACTION * res["azimuth"])
    d = yaml.safe_load(dump_scenario(sc))
    d["waveform"]["bandwidth"] = 15e9
    assert parse_scenario(d).processing.grid.dy == pytest.approx(sc.processing.grid.dy / 2)
    bad = merge(SPOT, processing__grid__dx="auto")
    bad["platform"] = {k: v for k, v in bad["platform"].items() if k != "aperture_length"}
    with pytest.raises(ScenarioError, match="processing.grid.dx"):
        parse_scenario(bad)
