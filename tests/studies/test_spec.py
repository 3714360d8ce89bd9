"""Sweep axes: the three SPEC forms, and every malformed one refused naming --vary before any work."""
import numpy as np
import pytest

from salkit.errors import ScenarioError
from salkit.studies import parse_vary


def test_forms():
    a = parse_vary("waveform.bandwidth=lin:1e9:7e9:4")
    assert a.field == "waveform.bandwidth" and a.scale == "lin" and a.numeric
    np.testing.assert_allclose(a.values, [1e9, 3e9, 5e9, 7e9])
    g = parse_vary("atmosphere.cn2=log:1e-16:1e-12:5")
    np.testing.assert_allclose(g.values, [1e-16, 1e-15, 1e-14, 1e-13, 1e-12], rtol=1e-12)
    assert parse_vary("processing.algorithm=bp, pfa").values == ("bp", "pfa")
    assert parse_vary("receiver.noise.signal_photons=1,2.5,10").values == (1, 2.5, 10)
    assert parse_vary("x.y=lin:3:3:1").values == (3.0,)


@pytest.mark.parametrize("item,words", [
    ("waveform.bandwidth", "FIELD=SPEC"),
    ("=1,2", "field path is empty"),
    ("a..b=1,2", "empty part"),
    ("a.b=lin:1:2", "lin:START:STOP:N"),
    ("a.b=lin:1:2:0", "positive integer"),
    ("a.b=lin:1:2:-3", "positive integer"),
    ("a.b=lin:1:2:2.5", "positive integer"),
    ("a.b=lin:x:2:3", "not a number"),
    ("a.b=lin:1:inf:3", "finite"),
    ("a.b=log:0:1:3", "cannot pass through zero or negative"),
    ("a.b=log:-1e-3:1:3", "cannot pass through zero or negative"),
    ("a.b=", "empty"),
    ("a.b=1,,2", "empty entry"),
    ("a.b=1,2,1", "repeats a value"),
    ("a.b=lin:0:1:100000", "exceeds"),
])
def test_malformed_refused(item, words):
    with pytest.raises(ScenarioError) as e:
        parse_vary(item)
    assert e.value.field == "--vary" and e.value.value == item and words in e.value.constraint


def test_a_sweep_files_metrics_are_checked_against_the_table(tmp_path):
    """A metric a sweep file names that salkit does not measure is refused with the file, the name
    and the nearest declared one; declared ones (with case labels) pass."""
    from salkit.studies.spec import read_sweep_file
    (tmp_path / "s.yaml").write_text("sweep: 1\nscenario: base.yaml\nvary: {waveform.bandwidth: '1e9,2e9'}\n"
                                     "metrics: [irw_range_m, medium_pga_entropy, pslr_azimth_db]\n")
    with pytest.raises(ScenarioError, match=r"s.yaml: metrics = 'pslr_azimth_db'.*the nearest: 'pslr_azimuth_db'"):
        read_sweep_file(tmp_path / "s.yaml")
    (tmp_path / "t.yaml").write_text("sweep: 1\nscenario: base.yaml\nvary: {waveform.bandwidth: '1e9,2e9'}\n"
                                     "metrics: [irw_range_m, medium_pga_entropy]\n")
    assert read_sweep_file(tmp_path / "t.yaml").metrics == ("irw_range_m", "medium_pga_entropy")


def test_a_sweep_files_missing_scenario_says_where_it_was_looked_for(tmp_path):
    """A relative base scenario is read from the sweep file's folder: the error says so (it said only
    "scenario = '<folder>/examples/x.yaml': file does not exist" for a path written from the
    repository's root)."""
    from salkit.studies.spec import resolve_request
    (tmp_path / "s.yaml").write_text("sweep: 1\nscenario: examples/x.yaml\nvary: {waveform.bandwidth: '1e9,2e9'}\n")
    with pytest.raises(ScenarioError) as e:
        resolve_request(tmp_path / "s.yaml")
    assert e.value.field == "s.yaml: scenario" and e.value.value == str(tmp_path / "examples" / "x.yaml")
    assert f"read from the sweep file's folder, {tmp_path.resolve()}" in e.value.constraint
