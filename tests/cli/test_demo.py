"""make demo's driver: one example into a results folder with its index page."""
from salkit.cli.demo import main


def test_demo_one_example(tmp_path):
    assert main(["--out", str(tmp_path), "--only", "geo_range_point"]) == 0
    index = (tmp_path / "index.html").read_text()
    assert 'href="geo_range_point/report.html"' in index
    assert (tmp_path / "geo_range_point" / "manifest.json").is_file()
