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
