"""The README's data commands as a new user types them: simulate, convert to CPHD, focus outside data
into a SICD. A CPHD or SICD needs a geographic scene centre and the shipped examples carry none, so
the README's lines must give ``--origin`` (without it they exit 2: the README once showed them so)."""
import os
import shlex
from pathlib import Path

from .conftest import salkit

README = Path(__file__).resolve().parents[2] / "README.md"


def _line(start: str) -> list[str]:
    """The README's command line that starts with ``start``, split as a shell would, without its
    comment and the leading ``salkit``."""
    lines = [ln for ln in README.read_text().splitlines() if ln.startswith(start)]
    assert len(lines) == 1, f"README: {len(lines)} lines start with {start!r}"
    return shlex.split(lines[0], comments=True)[1:]


def test_readme_simulate_convert_and_sicd_lines_run(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    os.symlink(README.parent / "examples", tmp_path / "examples")
    r = salkit(*_line("salkit simulate examples/stripmap_scene.yaml"))
    assert r.returncode == 0, r.stderr
    r = salkit(*_line("salkit convert raw.nc raw.cphd"))
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "raw.cphd").is_file()
    assert salkit("convert", "raw.nc", "pass.mat").returncode == 0  # "also .mat (GOTCHA layout)"
    r = salkit(*_line("salkit focus pass.mat"))
    assert r.returncode == 0, r.stderr
    assert list((tmp_path / "out3").glob("*.nitf")), sorted(p.name for p in (tmp_path / "out3").iterdir())
