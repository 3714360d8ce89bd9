"""Figures: written atomically as PNGs, every figure closed afterwards."""
import matplotlib.pyplot as plt
import numpy as np

from salkit import focus, simulate
from salkit import plot
from salkit.params import parse_scenario

from ..conftest import SPOT


def test_image_and_raw_figures(tmp_path):
    sc = parse_scenario(SPOT)
    raw = simulate(sc)
    img = focus(raw, sc.processing)
    before = len(plt.get_fignums())
    for p in (plot.image_db(img, tmp_path / "i.png", title="t"), plot.raw_phase_history(raw, tmp_path / "r.png"),
              plot.screen_image(np.zeros((8, 8)), 0.01, tmp_path / "s.png")):
        assert p.is_file() and p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(plt.get_fignums()) == before
    assert not [f for f in tmp_path.iterdir() if f.name.startswith(".")]  # no temporary left


def test_the_model_figure(tmp_path):
    from salkit.params.models import SceneObject
    from salkit.simulate.views import model_view
    scene = [SceneObject(shape="plate", size=(4, 4)), SceneObject(shape="vehicle", size=(2, 1, 1), position=(0, 0, 0.5))]
    view = model_view(scene, np.array([0.0, -4000.0, 3000.0]), 0.05)
    p = plot.model_view_figure(view, tmp_path / "model.png", title="a car")
    assert p.stat().st_size > 10_000 and plt.get_fignums() == []
