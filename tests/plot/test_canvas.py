"""The canvas: PNGs saved atomically (no temporary left, the figure closed, a failed save leaves
nothing), dB against a reference."""
import matplotlib.pyplot as plt
import numpy as np
import pytest

from salkit.plot.canvas import _db, _log_ticks, _save, _subplots

PNG = b"\x89PNG\r\n\x1a\n"


def test_save_is_atomic_and_closes_the_figure(tmp_path):
    before = len(plt.get_fignums())
    fig, ax = _subplots()
    ax.plot([1, 2], [3, 4])
    p = _save(fig, tmp_path / "a.png")
    assert p.read_bytes()[:8] == PNG
    assert len(plt.get_fignums()) == before
    assert [f.name for f in tmp_path.iterdir()] == ["a.png"]


def test_failed_save_leaves_nothing(tmp_path):
    fig, ax = _subplots()
    before = len(plt.get_fignums())

    def broken(path, **kw):
        open(path, "wb").write(PNG)  # half a file, then the failure
        raise OSError("disk full")

    fig.savefig = broken
    with pytest.raises(OSError, match="disk full"):
        _save(fig, tmp_path / "a.png")
    assert not list(tmp_path.iterdir())
    assert len(plt.get_fignums()) == before - 1  # closed all the same


def test_db_against_reference_and_log_ticks():
    img = np.array([1.0, 0.1, 0.0])
    db = _db(img, 1.0)
    assert db[0] == pytest.approx(0.0) and db[1] == pytest.approx(-20.0) and np.isfinite(db[2])
    fig, ax = _subplots()
    ax.loglog([1, 100], [1, 100])
    _log_ticks(ax)
    fig.canvas.draw()
    labels = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
    assert "2" in labels and "50" in labels  # plain 1-2-5 numbers
    plt.close(fig)
