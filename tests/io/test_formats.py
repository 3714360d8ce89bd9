"""CPHD (through sarkit) and the GOTCHA .mat layout: written, checked, read back, focused."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.errors import DataFileError
from salkit.focus import range_compress
from salkit.io import check_cphd, read_cphd, read_gotcha, read_phase_data, write_cphd, write_gotcha


def _ccorr(a, b):
    return float(abs(np.vdot(a, b)) / np.linalg.norm(a) / np.linalg.norm(b))


@pytest.fixture(scope="module")
def collection():
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.0, "y": 0.0}, {"x": 0.3, "y": -0.2, "amplitude": 0.7}]}))
    raw = simulate(sc)
    return sc, raw, focus(raw, sc.processing)["image"].values


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


def test_cphd_from_data_without_pulse_times(tmp_path, collection):
    """A GOTCHA file has no pulse times: the CPHD written from it (nominal 1 kHz) is still consistent."""
    sc, raw, img = collection
    ds = read_gotcha(write_gotcha(range_compress(raw), tmp_path / "p.mat"))
    p = write_cphd(ds, tmp_path / "p.cphd")
    assert check_cphd(p) == {"errors": [], "warnings": []}
    assert _ccorr(img, focus(read_cphd(p), sc.processing)["image"].values) >= 0.9999


def test_unusable_files_refused(tmp_path):
    from scipy.io import savemat
    savemat(tmp_path / "a.mat", {"data": {"fp": np.ones((4, 3)), "freq": np.arange(4.0)}})
    with pytest.raises(DataFileError, match=r"lacks the field\(s\) \['x', 'y', 'z', 'r0'\]"):
        read_gotcha(tmp_path / "a.mat")
    savemat(tmp_path / "b.mat", {"data": {"fp": np.ones((3, 4)), "freq": np.arange(4.0), "x": np.ones(3),
                                          "y": np.ones(3), "z": np.ones(3), "r0": np.ones(3)}})
    with pytest.raises(DataFileError, match=r"\[freq x pulse\]: transpose it"):
        read_gotcha(tmp_path / "b.mat")
    (tmp_path / "c.cphd").write_bytes(b"CPHD/1.0.1\nnonsense")
    with pytest.raises(DataFileError, match="cannot be read as CPHD"):
        read_cphd(tmp_path / "c.cphd")
    with pytest.raises(DataFileError, match="unknown suffix"):
        read_phase_data(tmp_path / "x.bin")


@pytest.mark.parametrize("case", ["spot", "ground", "strip", "right"])
def test_sicd_export_is_consistent(tmp_path, case):
    """SICD 1.3.0 from a focused image: sarkit's checker finds 0 errors and 0 warnings, and the
    pixels read back are the image's (rows = range, columns along the grid normal's convention)."""
    from salkit.io import check_sicd, read_sicd, write_sicd
    from salkit.io.sicd import sicd_xml
    from salkit.params import parse_scenario
    from ..conftest import SPOT, STRIP, merge
    d = {"spot": SPOT, "strip": STRIP, "right": merge(SPOT, platform__side="right"),
         "ground": merge(SPOT, processing__grid={"nx": 96, "ny": 64, "dx": 0.015, "dy": 0.02, "plane": "ground"})}[case]
    sc = parse_scenario(d)
    img = focus(simulate(sc), sc.processing)
    img.attrs["origin_llh"] = np.array([35.0, -106.5, 1600.0])
    p = write_sicd(img, tmp_path / "i.nitf")
    assert check_sicd(p) == {"errors": [], "warnings": []}
    pix, tree = read_sicd(p)
    _, info = sicd_xml(img)
    ref = img["image"].values.T
    np.testing.assert_array_equal(pix, ref[:, ::-1] if info["columns_flipped"] else ref)
    assert info["position_fit_residual"] < 1e-6
    assert tree.findtext("{*}Grid/{*}ImagePlane") == ("GROUND" if case == "ground" else "SLANT")


def test_sicd_refuses_a_horizontal_look(tmp_path, geo):
    from salkit.io import write_sicd
    img = focus(simulate(geo), geo.processing)
    with pytest.raises(DataFileError, match="above the scene's horizon"):
        write_sicd(img, tmp_path / "g.nitf")
    assert not list(tmp_path.iterdir())
