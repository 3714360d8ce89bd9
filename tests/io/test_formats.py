"""salkit.io: reading phase data by suffix."""
import pytest

from salkit.errors import DataFileError
from salkit.io import PHASE_SUFFIXES, read_phase_data


def test_unknown_suffix_refused(tmp_path):
    with pytest.raises(DataFileError, match="unknown suffix"):
        read_phase_data(tmp_path / "x.bin")


def test_suffixes():
    assert set(PHASE_SUFFIXES) >= {".nc", ".cphd", ".mat"}
