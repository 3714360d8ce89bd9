import pytest
from pydantic import ValidationError

from salkit.errors import NOT_GIVEN, ScenarioError
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
    assert ei.value.value is NOT_GIVEN
    # the field alone, not its section's other values shown as if they were the missing one's
    assert str(ei.value) == "waveform.wavelength: is required"


def test_every_problem_is_named_not_only_the_first():
    """A scenario with a bad value beside missing sections names the bad value too (it used to say
    "scene = {the whole document}: is required (and 7 more problems)" and hide the -1)."""
    with pytest.raises(ScenarioError) as ei:
        parse_scenario({"name": "x", "waveform": {"wavelength": -1}})
    e = ei.value
    assert (e.field, e.value) == ("scene", NOT_GIVEN)
    assert str(e).startswith("scene: is required")
    assert "and 7 more problems" in e.constraint
    assert "waveform.wavelength = -1: Input should be greater than 0" in e.constraint
    assert "missing: waveform.bandwidth, waveform.pulse_width, waveform.prf, platform, receiver, processing" \
        in e.constraint


def test_many_problems_are_counted_past_the_listed_ones():
    from salkit.params.scenario import LISTED_PROBLEMS
    bad = {k: -1.0 for k in ("bandwidth", "pulse_width", "prf", "wavelength")}
    platform = {**SPOT["platform"], "speed": -1.0, "altitude": -1.0, "real_aperture": -1.0, "standoff": -1.0}
    with pytest.raises(ScenarioError) as ei:
        parse_scenario(merge(SPOT, waveform=bad, platform=platform))
    c = ei.value.constraint
    assert c.startswith("Input should be greater than 0 (and 7 more problems: ")
    assert c.count("= -1.0: Input should be greater than") == LISTED_PROBLEMS  # the first, then 5 named
    assert c.endswith("; 2 more)")


def test_a_down_looking_scenario_with_a_sal_section_is_told_why():
    """experiment.kind = downlooking takes no waveform section: the error says so, lists that
    model's fields and does not suggest the key it refuses (it said "'waveform' is not a field of
    the scenario (did you mean 'waveform'?)", listing waveform among the fields)."""
    d = {"name": "x", "experiment": {"kind": "downlooking"}, "waveform": {"wavelength": 1.55e-6}}
    with pytest.raises(ScenarioError) as ei:
        parse_scenario(d)
    e = ei.value
    assert e.field == "waveform"
    assert "is not a field of a down-looking scenario" in e.constraint
    assert "did you mean" not in e.constraint
    assert "its fields: description, experiment, name, scene, seed" in e.constraint
    assert "missing: scene, experiment.optics, experiment.scan, experiment.track" in e.constraint


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


def test_what_is_not_a_scenario_is_refused_where_one_is_taken():
    """salkit.simulate("x.yaml") raised AttributeError ('str' object has no attribute
    'is_downlooking'), salkit.sweep the same with 'model_dump': each names the argument now, and
    how to make a scenario of what was given."""
    import salkit
    from salkit.params import require_scenario
    for call in (lambda x: salkit.simulate(x), lambda x: salkit.sweep(x, vary={"waveform.bandwidth": "1e9,2e9"}),
                 lambda x: salkit.focus(salkit.simulate(parse_scenario(SPOT)), scenario=x)):
        with pytest.raises(ScenarioError) as e:
            call("examples/spotlight_points.yaml")
        assert (e.value.field, e.value.value) == ("scenario", "examples/spotlight_points.yaml")
        assert "salkit.load_scenario(path)" in e.value.constraint
    with pytest.raises(ScenarioError, match="salkit.params.parse_scenario"):
        require_scenario(dict(SPOT))
    with pytest.raises(ScenarioError, match=r"scenario = None: must be a Scenario"):
        require_scenario(None)
    require_scenario(parse_scenario(SPOT))


def test_one_override_as_a_string():
    """load_scenario(path, "waveform.bandwidth=5e9") was read character by character ("--set = 'w'")."""
    one = load_scenario(EXAMPLES / "spotlight_points.yaml", "waveform.bandwidth=5e9")
    assert one == load_scenario(EXAMPLES / "spotlight_points.yaml", ["waveform.bandwidth=5e9"])
    assert one.waveform.bandwidth == 5e9


@pytest.mark.parametrize("example,key,fields", [
    ("spaceborne_geo", "experiment.r9", "kind, r1, r2, resolution, squint_max_deg, target_attitude"),
    ("nonlinear_chirp", "experiment.zz", "d_r, d_rlo, kind, points, r1, r2"),
    ("downlooking_3d", "experiment.scan.stpe", "duration, factor, samples, speed"),
])
def test_an_unknown_experiment_key_lists_that_experiments_fields(example, key, fields):
    """A misspelt key in a spaceborne or chirp experiment listed the turbulence experiment's fields
    (the union's first member), and in a down-looking experiment's section none at all."""
    with pytest.raises(ScenarioError) as e:
        load_scenario(EXAMPLES / f"{example}.yaml", [f"{key}=1"])
    assert e.value.field == key and f"its fields: {fields}" in e.value.constraint


def test_an_experiment_kind_that_does_not_exist_is_the_error():
    """kind: spaceborne_ge was reported as "waveform: is required ..." (the SAL model's missing
    sections), the kind's own error last; it is now first, with the nearest kind and all of them."""
    with pytest.raises(ScenarioError) as e:
        load_scenario(EXAMPLES / "downlooking_3d.yaml", ["experiment.kind=spaceborne_ge"])
    assert (e.value.field, e.value.value) == ("experiment.kind", "spaceborne_ge")
    assert e.value.constraint.startswith("is not an experiment kind (did you mean 'spaceborne_geo'?); the kinds: "
                                         "turbulence_pga, nonlinear_chirp, spaceborne_geo, downlooking")
