import pytest
from pydantic import ValidationError

from salkit.errors import ScenarioError
from salkit.params import apply_overrides, dump_scenario, load_scenario, parse_scenario
from salkit.params.models import Waveform

from ..conftest import EXAMPLES, SPOT, merge


@pytest.mark.parametrize("name", ["spotlight_points", "stripmap_scene", "geo_range_point"])
def test_examples_parse(name):
    sc = load_scenario(EXAMPLES / f"{name}.yaml")
    assert sc.name == name
    assert sc.waveform.wavelength == pytest.approx(1.55e-6)



def test_overrides_set_nested_fields():
    d = apply_overrides(SPOT, ["waveform.bandwidth=3e9", "scene.points.0.x=0.25", "processing.window=hamming"])
    sc = parse_scenario(d)
    assert sc.waveform.bandwidth == 3e9
    assert sc.scene.points[0].x == 0.25
    assert sc.processing.window == "hamming"


def test_round_trip_dump(spot):
    import yaml
    again = parse_scenario(yaml.safe_load(dump_scenario(spot)))
    assert again == spot


@pytest.mark.parametrize("path,value,field,words", [
    ("waveform__bandwidth", -1.0, "waveform.bandwidth", "greater than 0"),
    ("waveform__chirp_rate", 1e10, "waveform.chirp_rate", "bandwidth/pulse_width"),
    ("waveform__prf", 2e5, "waveform.prf", "duty cycle"),
    ("platform__speed", 0.0, "platform.speed", "greater than 0"),
    ("receiver__noise__quantum_efficiency", 1.5, "receiver.noise.quantum_efficiency", "less than or equal"),
    ("receiver__noise__signal_photons", 0.0, "receiver.noise.signal_photons", "greater than 0"),
    ("processing__algorithm", "magic", "processing.algorithm", "bp"),
    ("waveform__colour", "red", "waveform.colour", "is not a field of waveform"),
])
def test_bad_fields_name_field_value_constraint(path, value, field, words):
    with pytest.raises(ScenarioError) as ei:
        parse_scenario(merge(SPOT, **{path: value}))
    msg = str(ei.value)
    assert ei.value.field == field
    assert words in msg
    assert repr(value) in msg or str(value) in msg


def test_missing_field_is_named():
    d = merge(SPOT)
    del d["waveform"]["wavelength"]
    with pytest.raises(ScenarioError) as ei:
        parse_scenario(d)
    assert ei.value.field == "waveform.wavelength"
    assert "required" in str(ei.value).lower()


def test_empty_scene_rejected():
    with pytest.raises(ScenarioError, match="at least one point target"):
        parse_scenario(merge(SPOT, scene={"points": []}))


def test_bad_override_syntax():
    with pytest.raises(ScenarioError, match="key.path=value"):
        apply_overrides(SPOT, ["waveform.bandwidth"])


@pytest.mark.parametrize("sets,field,value", [
    (["platform.trajectory=keplerian"], "platform.trajectory", "keplerian"),
    (["waveform.chirp_rate=5"], "waveform.chirp_rate", 5.0),
    (["platform.real_aperture=1e-6"], "platform.real_aperture", 1e-6),
])
def test_checks_across_fields_name_the_field(sets, field, value):
    """A check that spans fields (a model validator) names the field it refuses, not the object."""
    with pytest.raises(ScenarioError) as e:
        load_scenario(EXAMPLES / "spotlight_points.yaml", sets)
    assert (e.value.field, e.value.value) == (field, value)


def test_experiment_fields_without_the_union_tag():
    with pytest.raises(ScenarioError) as e:
        load_scenario(EXAMPLES / "spaceborne_geo.yaml", ["experiment.r1=1e9"])
    assert e.value.field == "experiment.r1" and "below r2" in e.value.constraint
