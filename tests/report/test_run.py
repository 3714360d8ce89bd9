"""Writing a run: a scenario run written as a complete folder whose report links resolve, its
scenario.yaml written once."""
import re

from salkit.params import parse_scenario
from salkit.report import run_scenario

from ..conftest import SPOT


def test_run_scenario_writes_a_complete_report(tmp_path):
    m = run_scenario(parse_scenario(SPOT), tmp_path)
    html = (tmp_path / "report.html").read_text()
    for ref in re.findall(r'(?:src|href)="([^"#:]+)"', html):
        assert (tmp_path / ref).is_file(), ref
    for f in ("scenario.yaml", "raw.nc", "image.nc", "metrics.json", "image.png", "cuts.png"):
        assert (tmp_path / f).is_file(), f
    assert m["irw_range_m"] > 0


def test_scenario_yaml_written_once(tmp_path, monkeypatch):
    import salkit.report.run as run_module
    writes = []
    real = run_module.write_text_atomic

    def counting(path, text):
        writes.append(path.name)
        return real(path, text)

    monkeypatch.setattr(run_module, "write_text_atomic", counting)
    run_scenario(parse_scenario(SPOT), tmp_path)
    assert writes.count("scenario.yaml") == 1
