"""Errors: what a user sees and the exit status each kind of problem gives."""
import pytest

from salkit.errors import (DataFileError, EnvironmentProblem, ResourceError, SalkitError, SamplingError,
                           ScenarioError)


def test_scenario_error_names_field_value_and_constraint():
    e = ScenarioError("waveform.prf", -3, "must be > 0")
    assert "waveform.prf" in str(e) and "-3" in str(e) and "must be > 0" in str(e)


@pytest.mark.parametrize("cls,code", [(ScenarioError, 2), (SamplingError, 2), (DataFileError, 2),
                                      (ResourceError, 2), (EnvironmentProblem, 1)])
def test_exit_codes(cls, code):
    e = cls("f", 1, "c") if issubclass(cls, ScenarioError) else cls("message")
    assert isinstance(e, SalkitError) and e.exit_code == code


def test_require_scenario_file_names_a_folder_and_a_missing_file(tmp_path):
    from salkit.errors import require_scenario_file
    with pytest.raises(ScenarioError, match="is a folder, not a YAML file"):
        require_scenario_file(tmp_path)
    with pytest.raises(ScenarioError, match="'nothere.yaml': file does not exist"):
        require_scenario_file("nothere.yaml")
    (tmp_path / "s.yaml").write_text("a: 1\n")
    assert require_scenario_file(tmp_path / "s.yaml") is None
