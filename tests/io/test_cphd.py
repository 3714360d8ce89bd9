"""CPHD through sarkit: written, checked by its consistency checker, read back, focused."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.errors import DataFileError
from salkit.focus import range_compress
from salkit.io import check_cphd, read_cphd, read_gotcha, read_phase_data, write_cphd, write_gotcha

from .conftest import _ccorr


def test_cphd_round_trip_and_consistency(tmp_path, collection):
    sc, raw, img = collection
    p = write_cphd(range_compress(raw), tmp_path / "c.cphd", origin=(35.0, -106.5, 1600.0))
    res = check_cphd(p)
    assert res == {"errors": [], "warnings": []}
    back = read_cphd(p)
    assert back.attrs["origin_llh"] == pytest.approx([35.0, -106.5, 1600.0])
    np.testing.assert_allclose(back["position"].values, raw["position"].values, atol=1e-6)
    np.testing.assert_allclose(back["reference_range"].values, raw["reference_range"].values, rtol=0, atol=1e-6)
    assert _ccorr(img, focus(back, sc.processing)["image"].values) >= 0.9999
    assert [f.name for f in tmp_path.iterdir()] == ["c.cphd"]  # written atomically


def test_cphd_from_data_without_pulse_times(tmp_path, collection):
    """A GOTCHA file has no pulse times: the CPHD written from it (nominal 1 kHz) is still consistent."""
    sc, raw, img = collection
    ds = read_gotcha(write_gotcha(range_compress(raw), tmp_path / "p.mat"))
    p = write_cphd(ds, tmp_path / "p.cphd")
    assert check_cphd(p) == {"errors": [], "warnings": []}
    assert _ccorr(img, focus(read_cphd(p), sc.processing)["image"].values) >= 0.9999


def test_unreadable_cphd_refused(tmp_path):
    (tmp_path / "c.cphd").write_bytes(b"CPHD/1.0.1\nnonsense")
    with pytest.raises(DataFileError, match="cannot be read as CPHD"):
        read_cphd(tmp_path / "c.cphd")


def test_cphd_read_lazily_in_vector_blocks(tmp_path, collection):
    """lazy=True: the signal stays in the file and is read a block of vectors at a time (sarkit's
    start/stop vectors); every slice equals the eager read, and bp focuses it in pulse blocks to
    the same image bit for bit."""
    from salkit.focus import memory_estimate
    sc, raw, img = collection
    p = write_cphd(range_compress(raw), tmp_path / "c.cphd", origin=(35.0, -106.5, 1600.0))
    eager, lazy = read_cphd(p), read_phase_data(p, lazy=True)
    assert not lazy["signal"].variable._in_memory and lazy.encoding["source"] == str(p)
    for sl in (slice(0, 7), slice(50, 51), slice(100, None), slice(3, 90, 4)):
        np.testing.assert_array_equal(lazy["signal"][sl].values, eager["signal"][sl].values)
    P, M = eager["signal"].shape
    whole = focus(eager, sc.processing, algorithm="bp")
    blocks = focus(lazy, sc.processing, algorithm="bp",
                   memory_limit=0.85 * memory_estimate(P, M, sc.processing.grid.nx, sc.processing.grid.ny, raw=False)[0])
    assert blocks.attrs["pulse_block"] < P
    np.testing.assert_array_equal(blocks["image"].values, whole["image"].values)
