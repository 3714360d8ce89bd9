"""`salkit run examples/downlooking_3d.yaml`: every output, the metrics keys, and bad input exiting 2."""
import json

import numpy as np
import pytest

from salkit.io import read_image

from ..conftest import EXAMPLES
from .conftest import KEYS, salkit

EX = EXAMPLES / "downlooking_3d.yaml"
SMALL = ["--set", "scene.extended.extent=[0.5,0.6]", "--set", "experiment.terrain.extent=[0.5,0.5]"]


def test_run_downlooking_example(tmp_path):
    out = tmp_path / "dl"
    r = salkit("run", EX, "--out", out, *SMALL)
    assert r.returncode == 0, r.stderr
    assert "warning" in r.stdout and "3.75 m" in r.stdout  # the seed's design sits on the sideband limit
    for f in ["raw_point.nc", "image_point.nc", "image_point_forward.nc", "image_scene.nc", "terrain.nc",
              "metrics.json", "scenario.yaml", "report.html", "image_point.png", "scene.png", "terrain.png",
              "disturbance.png", "raw_point.png"]:
        assert (out / f).is_file(), f
    m = json.loads((out / "metrics.json").read_text())
    assert all(isinstance(v, (int, float)) for v in m.values())
    for k in KEYS + ["fringe_period_m", "fringe_period_theory_m"]:
        assert k in m, k
    assert m["fringe_period_theory_m"] == pytest.approx(0.18)
    assert m["fringe_period_m"] == pytest.approx(0.18, rel=0.01)
    img = read_image(out / "image_point.nc")
    assert img["image"].dims == ("azimuth", "range")
    a = np.abs(img["image"].values)
    i, j = np.unravel_index(np.argmax(a), a.shape)
    assert img["range"].values[j] == pytest.approx(0.03, abs=0.01)  # cross track, m on the target
    assert "terrain.png" in (out / "report.html").read_text()


def test_simulate_and_focus_a_downlooking_raw_file(tmp_path):
    raw = tmp_path / "raw.nc"
    r = salkit("simulate", EX, "--out", raw)
    assert r.returncode == 0, r.stderr
    r = salkit("focus", raw, "--out", tmp_path / "f")
    assert r.returncode == 0, r.stderr
    img = read_image(tmp_path / "f" / "image.nc")
    a = np.abs(img["image"].values)
    j = np.unravel_index(np.argmax(a), a.shape)[1]
    assert img["range"].values[j] == pytest.approx(0.03, abs=0.01)


@pytest.mark.parametrize("sets,needle", [
    (["experiment.optics.bias_common=0.001"], "sideband condition"),
    (["experiment.scan.duration=0.02"], "inconsistent with the aperture"),
    (["experiment.track.spacing=0.01"], "Nyquist"),
    (["experiment.scan.samples=600"], "alias"),
])
def test_bad_downlooking_input_exits_2(tmp_path, sets, needle):
    args = [a for s in sets for a in ("--set", s)]
    r = salkit("run", EX, "--out", tmp_path / "x", *args)
    assert r.returncode == 2
    assert needle in (r.stderr + r.stdout)
    assert "Traceback" not in r.stderr
    assert not (tmp_path / "x" / "metrics.json").exists()
