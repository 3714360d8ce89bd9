"""make demo's driver: one example into a results folder with its index page."""
from salkit.cli.demo import main


def test_demo_one_example(tmp_path):
    assert main(["--out", str(tmp_path), "--only", "geo_range_point"]) == 0
    index = (tmp_path / "index.html").read_text()
    assert 'href="geo_range_point/report.html"' in index
    assert (tmp_path / "geo_range_point" / "manifest.json").is_file()


def test_every_demo_report_resolves(tmp_path):
    """make demo end to end: every report's images and links resolve, every image has alt text,
    every page names the salkit version and has its Files section, the index links every run."""
    import re
    from salkit import __version__
    from salkit.cli.options import _examples_dir
    assert main(["--out", str(tmp_path), "--sweep-realisations", "1"]) == 0  # the sweeps' files, not their statistics
    names = sorted(f.stem for f in _examples_dir().glob("*.yaml"))
    names += sorted(f"sweep_{f.stem}" for f in (_examples_dir() / "sweeps").glob("*.yaml"))
    index = (tmp_path / "index.html").read_text()
    for ref in re.findall(r'(?:src|href)="([^"#:]+)"', index):
        assert (tmp_path / ref).is_file(), f"index.html -> {ref}"
    for name in names:
        assert f'href="{name}/report.html"' in index
        page = tmp_path / name / "report.html"
        html = page.read_text()
        for ref in re.findall(r'(?:src|href)="([^"#:]+)"', html):
            assert (page.parent / ref).is_file() or (ref.endswith("/") and (page.parent / ref).is_dir()), \
                f"{name}/report.html -> {ref}"
        for img in re.findall(r"<img [^>]*>", html):
            assert re.search(r'alt="[^"]{10,}"', img), f"{name}: image without alt text: {img}"
        assert f"salkit {__version__}" in html and "<h2>Files</h2>" in html, name
        assert "<details><summary>Resolved scenario" in html, name
    # the README quotes this run: its generated blocks (captions, files per example) must match it
    from pathlib import Path
    from salkit.report.docs import blocks, read_blocks
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    assert read_blocks(readme) == blocks(tmp_path), "README is stale: run make docs-figures"
