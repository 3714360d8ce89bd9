"""A sweep written into its folder: sweep.nc, sweep.csv, a figure per metric with its theory,
metrics.json, a report whose links resolve, the checkpoint gone; a card on the index page."""
import json
import re

from salkit.params import parse_scenario
from salkit.report.index import headline, write_index
from salkit.report.sweeps import run_sweep
from salkit.studies.plan import check_points, make_plan
from salkit.studies.spec import parse_vary
from salkit.systems.preflight import preflight

from ..conftest import SPOT


def test_run_sweep_writes_its_folder(tmp_path):
    sc = parse_scenario(SPOT)
    plan = make_plan(sc, [parse_vary("waveform.bandwidth=5e9,7.5e9"), parse_vary("processing.window=none,taylor")],
                     metrics=["irw_range_m"])
    d = tmp_path / "run"
    d.mkdir()
    stages = []
    m = run_sweep(sc, plan, check_points(plan, preflight), d, workers=0, progress=lambda s, k, n: stages.append((s, k, n)))
    assert stages[-1] == ("runs", 4, 4)
    for f in ("sweep.nc", "sweep.csv", "metrics.json", "report.html", "scenario.yaml", "sweep_irw_range_m.png"):
        assert (d / f).is_file(), f
    assert not (d / "checkpoint").exists()
    assert json.loads((d / "metrics.json").read_text()) == m and m["sweep_points_ok"] == 4
    html = (d / "report.html").read_text()
    for ref in re.findall(r'(?:src|href)="([^"#:]+)"', html):
        assert (d / ref).is_file(), ref
    assert "waveform.bandwidth" in html and "processing.window" in html
    items = headline(m)
    assert items[0]["measured"] == "4 of 4" and any(i["label"] == "irw_range_m, worst point" and i["ok"] for i in items)
    write_index(tmp_path, [{"name": "run", "description": "d", "seconds": 1.0, "metrics": m}])
    assert 'src="run/sweep_irw_range_m.png"' in (tmp_path / "index.html").read_text()


def test_a_study_report_is_titled_by_its_study_and_draws_no_flags(tmp_path):
    """A sweep file's report carries the study's name (not the base scenario's); yes/no flags
    (extended_scene, image_out_of_core) and timings are not drawn as metrics; a metric with a theory
    has its deviation panel."""
    import yaml

    from salkit.report.sweeps import run_sweep
    from salkit.studies.spec import resolve_request
    from salkit.systems.study import prepare
    from ..conftest import SPOT
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(SPOT))
    (tmp_path / "my_study.yaml").write_text(yaml.safe_dump(
        {"sweep": 1, "scenario": "base.yaml", "vary": {"waveform.bandwidth": "5e9,7.5e9"},
         "set": ["processing.grid.dy=auto"], "description": "my study"}))
    request = resolve_request(tmp_path / "my_study.yaml")
    sc, plan, invalid = prepare(request)
    out = tmp_path / "out"
    out.mkdir()
    run_sweep(sc, plan, invalid, out, workers=0, name=request.name, description=request.description)
    html = (out / "report.html").read_text()
    assert "<title>salkit: study my_study (sweep of test_spot)</title>" in html
    pngs = {p.name for p in out.glob("sweep_*.png")}
    assert "sweep_irw_range_m.png" in pngs
    assert not {"sweep_extended_scene.png", "sweep_image_out_of_core.png", "sweep_focus_s.png",
                "sweep_target_index.png"} & pngs
