"""Figures of the turbulence system: each is a PNG, written from the objects the workflow hands over."""
import numpy as np

from salkit.atmosphere.path import build_path
from salkit.autofocus import pga
from salkit.plot import autofocus_history, pga_steps_figure, screens_figure, structure_function_figure

from .test_canvas import PNG


def test_turbulence_figures(tmp_path, small_image):
    rng = np.random.default_rng(0)
    img = small_image["image"].values * np.exp(1j * 0.8 * np.linspace(-1, 1, small_image.sizes["azimuth"]) ** 2)[:, None]
    res = pga(img, max_iter=3)
    r = np.geomspace(0.01, 0.3, 8)
    path = build_path(1e-14, 1e3, 1.55e-6, 3, 32, 0.01, np.array([0, 0, 1.0]), np.array([1.0, 0, 0]), seed=1)
    written = [autofocus_history(res, tmp_path / "h.png", title="t"),
               screens_figure(path, tmp_path / "s.png"),
               structure_function_figure(r, 6.88 * (r / 0.05) ** (5 / 3), 0.1 + 0 * r, 6.88 * (r / 0.05) ** (5 / 3),
                                         tmp_path / "d.png", title="D(r)"),
               pga_steps_figure(small_image, {"after": small_image, "noise": small_image.assign(
                   image=(("azimuth", "range"), rng.standard_normal(img.shape) + 0j))}, tmp_path / "p.png")]
    for p in written:
        assert p.read_bytes()[:8] == PNG
