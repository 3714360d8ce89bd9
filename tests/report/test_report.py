"""The report layer: a scenario run written as a complete folder whose report links resolve."""
import re

from salkit.params import parse_scenario
from salkit.report import comparison_rows, run_scenario

from ..conftest import SPOT


def test_run_scenario_writes_a_complete_report(tmp_path):
    m = run_scenario(parse_scenario(SPOT), tmp_path)
    html = (tmp_path / "report.html").read_text()
    for ref in re.findall(r'(?:src|href)="([^"#:]+)"', html):
        assert (tmp_path / ref).is_file(), ref
    for f in ("scenario.yaml", "raw.nc", "image.nc", "metrics.json", "image.png", "cuts.png"):
        assert (tmp_path / f).is_file(), f
    assert m["irw_range_m"] > 0


def test_comparison_rows_only_for_present_metrics():
    assert comparison_rows({}) == []
    rows = comparison_rows({"pslr_range_db": -13.2, "pslr_range_theory_db": -13.26})
    assert [r["name"] for r in rows] == ["PSLR range (dB)"] and rows[0]["ok"]
