"""Checks before any work: aliasing and memory raise, the down-looking design's warnings return."""
import pytest

from salkit.errors import SalkitError
from salkit.params import parse_scenario
from salkit.systems.preflight import preflight

from ..conftest import SPOT, dl_scenario, merge


def test_preflight(monkeypatch):
    assert preflight(parse_scenario(SPOT)) == []
    with pytest.raises(SalkitError, match="processing.grid.dx"):
        preflight(parse_scenario(merge(SPOT, waveform__prf=50.0)))
    monkeypatch.setenv("SALKIT_MAX_MEMORY", "1MB")
    with pytest.raises(SalkitError, match="memory"):
        preflight(parse_scenario(SPOT))
    monkeypatch.delenv("SALKIT_MAX_MEMORY")
    assert isinstance(preflight(dl_scenario()), list)
