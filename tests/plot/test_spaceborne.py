"""Figures of the space-borne system: the sub-images, the stack and its SNR curve, the coherent
stack, resolution against squint and the trajectory study, each a PNG."""
import numpy as np

from salkit.plot import coherent_stack_figure, resolution_squint_figure, spaceborne_figures, trajectory_figure

from .test_canvas import PNG


def test_spaceborne_figures(tmp_path):
    rng = np.random.default_rng(0)
    az, rg = np.linspace(-1, 1, 24), np.linspace(-1, 1, 20)
    img = lambda: np.abs(rng.standard_normal((24, 20)))  # noqa: E731
    spaceborne_figures(img(), {-5.0: (img(), img()), 5.0: (img(), img())}, img(), img(), [1, 4, 16],
                       [0.3, 0.6, 1.2], 0.33, az, rg, tmp_path)
    for name in ("subimages.png", "stack.png", "snr_vs_p.png"):
        assert (tmp_path / name).read_bytes()[:8] == PNG
    res = {"counts": [1, 2, 4], "irw_m": [0.04, 0.02, 0.01], "irw_theory_m": [0.04, 0.02, 0.01]}
    q = np.linspace(-10, 10, 5)
    study = {"squints": q, **{k: {"peak": np.ones(5), "pslr": -13.0 * np.ones(5)} for k in ("true", "tangent", "line")}}
    for p in (coherent_stack_figure(img() + 0j, img(), az, rg, res, tmp_path / "c.png"),
              resolution_squint_figure(q, 0.01 / np.cos(np.radians(q)), q, 0.01 / np.cos(np.radians(q)), 8.0,
                                       tmp_path / "r.png"),
              trajectory_figure(study, tmp_path / "t.png")):
        assert p.read_bytes()[:8] == PNG
