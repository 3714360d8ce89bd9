"""The GOTCHA .mat layout: written, read back, focused, autofocus corrections applied."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.errors import DataFileError
from salkit.focus import range_compress
from salkit.io import check_cphd, read_cphd, read_gotcha, read_phase_data, write_cphd, write_gotcha

from .conftest import _ccorr


def test_gotcha_mat_focuses_like_the_simulation(tmp_path, collection):
    """A .mat in the published layout, written by the test from a salkit simulation."""
    sc, raw, img = collection
    p = write_gotcha(range_compress(raw), tmp_path / "pass1.mat")
    ds = read_gotcha(p)
    assert ds.attrs["slow_time_units"] == "pulse" and ds.attrs["af_applied"] == 1
    assert _ccorr(img, focus(ds, sc.processing)["image"].values) >= 0.9999


def test_gotcha_af_corrections_applied(tmp_path, collection):
    from scipy.io import loadmat, savemat
    sc, raw, img = collection
    p = write_gotcha(range_compress(raw), tmp_path / "p.mat")
    m = loadmat(p, squeeze_me=True, struct_as_record=False)["data"]
    P = m.x.size
    err = np.random.default_rng(0).uniform(-np.pi, np.pi, P)
    d = {k: getattr(m, k) for k in ("freq", "x", "y", "z", "r0", "th", "phi")}
    d["fp"] = m.fp * np.exp(-1j * err)[None, :]
    d["af"] = {"r_correct": np.zeros(P), "ph_correct": err}
    savemat(tmp_path / "q.mat", {"data": d})
    assert _ccorr(img, focus(read_gotcha(tmp_path / "q.mat"), sc.processing)["image"].values) >= 0.9999
    assert _ccorr(img, focus(read_gotcha(tmp_path / "q.mat", apply_af=False), sc.processing)["image"].values) < 0.5


def test_unusable_mat_files_refused(tmp_path):
    from scipy.io import savemat
    savemat(tmp_path / "a.mat", {"data": {"fp": np.ones((4, 3)), "freq": np.arange(4.0)}})
    with pytest.raises(DataFileError, match=r"lacks the field\(s\) \['x', 'y', 'z', 'r0'\]"):
        read_gotcha(tmp_path / "a.mat")
    savemat(tmp_path / "b.mat", {"data": {"fp": np.ones((3, 4)), "freq": np.arange(4.0), "x": np.ones(3),
                                          "y": np.ones(3), "z": np.ones(3), "r0": np.ones(3)}})
    with pytest.raises(DataFileError, match=r"\[freq x pulse\]: transpose it"):
        read_gotcha(tmp_path / "b.mat")
