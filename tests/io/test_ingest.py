"""Outside phase histories: float32 frequency axes, sign conventions, transposed arrays."""
import numpy as np
import pytest
import xarray as xr

from salkit import focus, simulate
from salkit.errors import DataFileError
from salkit.focus import range_compress
from salkit.io import read_raw, write_dataset
from salkit.io.ingest import FREQUENCY_FIT_TOLERANCE, regularise_axis


def test_float32_uniform_axis_accepted_with_residual():
    f = 9.3e9 + 1.47e6 * np.arange(512)
    f32 = f.astype(np.float32)
    axis, res, res_abs = regularise_axis(f32)
    assert res < FREQUENCY_FIT_TOLERANCE and res_abs > 10  # float32 rounding: hundreds of Hz
    np.testing.assert_allclose(axis, f, rtol=0, atol=2e-4 * 1.47e6)


def test_nonuniform_and_nonmonotonic_refused_with_numbers():
    f = 1e9 + 1e6 * np.arange(64.0)
    f[10] += 5e3  # 5e-3 of a step
    with pytest.raises(DataFileError, match=r"not uniformly spaced.*4816.*0.00482 of the 999995 step"):
        regularise_axis(f)
    g = 1e9 + 1e6 * np.arange(64.0)
    g[20] = g[18]
    with pytest.raises(DataFileError, match="strictly monotonic: sample 19"):
        regularise_axis(g)


def _outside(spot, sign=-1, transpose=False, dtype=np.float32):
    ph = range_compress(simulate(spot))
    sig = ph["signal"].values
    if sign == 1:
        sig = np.conj(sig)
    dims = ("slow_time", "frequency")
    if transpose:
        sig, dims = sig.T, ("frequency", "slow_time")
    return xr.Dataset(
        {"signal": (dims, sig.astype(np.complex128)),
         "position": (("slow_time", "xyz"), ph["position"].values.astype(dtype)),
         "reference_range": (("slow_time",), ph["reference_range"].values)},
        coords={"frequency": ph["frequency"].values.astype(dtype), "xyz": ["x", "y", "z"]},
        attrs={"salkit_kind": "phase_history", "phase_sign": sign})


@pytest.mark.parametrize("sign,transpose", [(-1, False), (1, True)])
def test_outside_file_as_it_comes_focuses(tmp_path, spot, sign, transpose):
    """float32 axes (193 THz in float32 is quantised to 16.8 MHz, 0.22 of the 37.5 MHz step), complex128, the other sign
    convention declared by phase_sign = +1, transposed, no slow_time: the point lands at the centre."""
    p = write_dataset(_outside(spot, sign, transpose), tmp_path / "o.nc")
    ds = read_raw(p)
    fmax = np.float32(ds["frequency"].values.max())
    assert 0 < ds.attrs["frequency_fit_residual"] <= 1.05 * 0.5 * float(np.spacing(fmax))  # float32 rounding
    assert ds["signal"].dims == ("slow_time", "frequency") and ds["signal"].dtype == np.complex64
    assert ds.attrs.get("phase_sign_converted", 0) == (1 if sign == 1 else 0)
    img = focus(ds, algorithm="bp")
    a = np.abs(img["image"].values)
    i, j = np.unravel_index(np.argmax(a), a.shape)
    assert abs(img["azimuth"].values[i]) < 0.01 and abs(img["range"].values[j]) < 0.01
    assert a.max() == pytest.approx(1.0, rel=0.03)


def test_wrong_sign_mirrors_an_offset_point(spot):
    """The documented check: with the sign convention wrong, a point off the centre shows up
    mirrored through the scene centre (both coordinates change sign)."""
    from salkit.params import parse_scenario
    from ..conftest import SPOT, merge
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.3, "y": 0.2}]},
                              processing__grid={"nx": 128, "ny": 128, "dx": 0.01, "dy": 0.01}))
    ph = range_compress(simulate(sc))
    g = sc.processing.grid
    for conj, expect in ((False, (0.3, 1)), (True, (-0.3, -1))):
        d = ph.copy(deep=True)
        if conj:
            d["signal"].values[:] = np.conj(d["signal"].values)
        img = focus(d, algorithm="bp", grid=g)
        a = np.abs(img["image"].values)
        i, j = np.unravel_index(np.argmax(a), a.shape)
        assert img["azimuth"].values[i] == pytest.approx(expect[0], abs=0.03)
        assert np.sign(img["range"].values[j]) == expect[1]


def test_bad_shapes_refused(tmp_path, spot):
    ds = _outside(spot)
    bad = ds.assign(reference_range=(("r",), ds["reference_range"].values[:-1]))
    with pytest.raises(DataFileError, match=r"'reference_range' has shape \(\d+,\); expected"):
        read_raw(write_dataset(bad, tmp_path / "b.nc"))
    bad = ds.assign(signal=(("slow_time", "frequency"), np.abs(ds["signal"].values)))
    with pytest.raises(DataFileError, match="must be complex"):
        read_raw(write_dataset(bad, tmp_path / "c.nc"))
