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


def test_expected_positions_outside_a_narrow_strip_are_not_drawn_beyond_its_axes(tmp_path, monkeypatch):
    """A 512 x 64 strip of the scene: the axes stay the image's extent, and only the targets the
    strip holds are marked (before, the others stretched the axes far past the image)."""
    import xarray as xr
    import salkit.plot.images as I
    az = np.linspace(-5.0, 5.0, 512)
    rg = np.linspace(0.0, 0.3, 64)
    ds = xr.Dataset({"image": (("azimuth", "range"), np.ones((512, 64), np.complex64))},
                    coords={"azimuth": az, "range": rg})
    seen = {}
    save = I._save

    def keep(fig, path):
        ax = fig.axes[0]
        seen["lims"] = ax.get_xlim() + ax.get_ylim()
        seen["marked"] = [np.column_stack(line.get_data()) for line in ax.get_lines()]
        return save(fig, path)

    monkeypatch.setattr(I, "_save", keep)
    truth = np.array([[0.0, 0.1], [1.0, 2.5], [-4.0, -1.0], [3.0, 0.2]])
    I.image_db(ds, tmp_path / "strip.png", truth=truth)
    assert np.allclose(seen["lims"], (-5.0, 5.0, 0.0, 0.3))
    assert len(seen["marked"]) == 1 and np.allclose(seen["marked"][0], truth[[0, 3]])
    I.image_db(ds, tmp_path / "none.png", truth=truth[[1, 2]])  # none inside: no marks, no legend
    assert seen["marked"] == [] and np.allclose(seen["lims"], (-5.0, 5.0, 0.0, 0.3))
