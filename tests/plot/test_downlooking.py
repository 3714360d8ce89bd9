"""Down-looking figures: the raw current picture."""
import numpy as np

from salkit.plot.downlooking import raw_current


def test_raw_current_png(tmp_path):
    cur = np.random.default_rng(0).standard_normal((8, 64))
    p = raw_current(cur, np.arange(8) * 0.01, np.linspace(-1e-3, 1e-3, 64), tmp_path / "c.png")
    assert p.is_file() and p.stat().st_size > 1000
