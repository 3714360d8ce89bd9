"""Shared by the command tests: the in-process runner ``salkit(...)``, a scenario file fixture
(``scen``) and the metric keys every point-target run writes."""
import pytest
import yaml

from ..conftest import SPOT

KEYS = ["irw_range_m", "irw_azimuth_m", "pslr_range_db", "pslr_azimuth_db", "islr_range_db", "islr_azimuth_db",
        "peak_offset_range_m", "peak_offset_azimuth_m", "irw_range_theory_m", "irw_azimuth_theory_m",
        "pslr_range_theory_db", "pslr_azimuth_theory_db", "islr_range_theory_db", "islr_azimuth_theory_db",
        "peak_offset_range_theory_m", "peak_offset_azimuth_theory_m"]


class _Result:
    def __init__(self, r):
        self.returncode, self.stdout, self.stderr = r.exit_code, r.stdout, r.stderr
        self.exception = r.exception


def salkit(*args):
    """Run the command line in-process (typer's CliRunner), wide enough that no line wraps.
    Real subprocesses are exercised in test_reliability.py (signals, the entry point)."""
    from typer.testing import CliRunner
    from salkit.cli.main import app
    r = CliRunner().invoke(app, [str(a) for a in args], env={"COLUMNS": "400"})
    assert r.exception is None or isinstance(r.exception, SystemExit), repr(r.exception)
    return _Result(r)


@pytest.fixture
def scen(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump(SPOT))
    return p
