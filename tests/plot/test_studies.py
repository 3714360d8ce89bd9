"""The chirp study's heat maps: a PNG, cells without a result hatched and explained."""
import numpy as np

from salkit.plot import sweep_heatmaps

from .test_canvas import PNG


def test_sweep_heatmaps_with_missing_cells(tmp_path):
    rows, cols = [1.0, 2.0, 3.0], [10.0, 20.0]
    ratio = np.array([[1.0, 2.0], [np.nan, 50.0], [3.0, 4.0]])
    grids = {"none": ratio, "paper": ratio, "resample": ratio / 2}
    irws = {"ideal": np.ones((3, 2)), "paper": 1.5 * np.ones((3, 2)), "resample": np.ones((3, 2))}
    p = sweep_heatmaps(rows, cols, grids, irws, tmp_path / "t.png", ("R2 (m)", "R1 (m)"))
    assert p.read_bytes()[:8] == PNG
