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


def test_a_flat_curve_is_not_zoomed_into_its_noise():
    """ISLR from -10.158 to -10.168 dB used to fill a panel: a level's axis spans at least 0.5 dB and
    any other value's at least 2 % of its magnitude."""
    import matplotlib.pyplot as plt

    from salkit.plot.studies import MIN_DB_SPAN, MIN_RELATIVE_SPAN, _floor_span
    fig, ax = plt.subplots()
    ax.plot([1, 2], [-10.158, -10.168])
    _floor_span(ax, [-10.158, -10.168], "dB")
    lo, hi = ax.get_ylim()
    assert hi - lo >= MIN_DB_SPAN
    ax.set_ylim(0.01779, 0.01781)
    _floor_span(ax, [0.01779, 0.01781], "m")
    lo, hi = ax.get_ylim()
    assert hi - lo >= MIN_RELATIVE_SPAN * 0.0178
    plt.close(fig)
