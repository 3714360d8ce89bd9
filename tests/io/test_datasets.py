import os

import numpy as np
import pytest
import xarray as xr

from salkit import focus, simulate
from salkit.errors import DataFileError
from salkit.io import read_image, read_raw, write_dataset


@pytest.fixture
def files(tmp_path, spot):
    raw = simulate(spot)
    img = focus(raw, spot.processing)
    return write_dataset(raw, tmp_path / "raw.nc"), write_dataset(img, tmp_path / "image.nc"), raw, img


def test_plain_xarray_reads_complex(files):
    rp, ip, raw, img = files
    with xr.open_dataset(ip) as ds:  # no engine, no salkit call
        assert np.iscomplexobj(ds["image"].values)
        assert ds["image"].dims == ("azimuth", "range")
        assert ds["azimuth"].attrs["units"] == "m"
        np.testing.assert_array_equal(ds["image"].values, img["image"].values)
    with xr.open_dataset(rp) as ds:
        assert ds["signal"].dtype == np.complex64
        assert ds["position"].dtype == np.float64
        np.testing.assert_array_equal(ds["signal"].values, raw["signal"].values)
        assert ds.attrs["wavelength"] == pytest.approx(1.55e-6)
        assert "waveform:" in ds.attrs["scenario"]


def test_focus_from_file_is_identical(files, spot):
    rp, ip, raw, img = files
    again = focus(read_raw(rp), spot.processing)
    np.testing.assert_array_equal(again["image"].values, img["image"].values)


def test_nan_in_data_detected(tmp_path, files):
    rp, ip, raw, img = files
    bad = raw.copy(deep=True)
    bad["signal"].values[3, 7] = np.nan
    p = write_dataset(bad, tmp_path / "bad.nc")
    with pytest.raises(DataFileError, match=r"'signal' holds 1 non-finite value.*\(3, 7\)"):
        read_raw(p)


def test_truncated_file_detected(tmp_path, files):
    rp, ip, raw, img = files
    data = open(ip, "rb").read()
    t = tmp_path / "trunc.nc"
    t.write_bytes(data[: len(data) // 3])
    with pytest.raises(DataFileError, match="truncated or corrupt"):
        read_image(t)


def test_wrong_kind_and_missing_variable(tmp_path, files):
    rp, ip, raw, img = files
    with pytest.raises(DataFileError, match="salkit_kind"):
        read_raw(ip)
    p = write_dataset(raw.drop_vars("reference_range"), tmp_path / "nore.nc")
    with pytest.raises(DataFileError, match="reference_range"):
        read_raw(p)


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    class Boom(Exception):
        pass
    ds = xr.Dataset({"a": ("x", np.arange(3.0))})
    target = tmp_path / "out.nc"
    write_dataset(ds, target)
    before = target.read_bytes()

    orig = xr.Dataset.to_netcdf

    def failing(self, path, *a, **k):  # the HDF5 image is made in memory, then copied
        (path.write(b"partial") if hasattr(path, "write") else open(path, "wb").write(b"partial"))
        raise Boom()
    xr.Dataset.to_netcdf = failing
    try:
        with pytest.raises(Boom):
            write_dataset(ds, target)
    finally:
        xr.Dataset.to_netcdf = orig
    assert target.read_bytes() == before  # old file intact
    assert [p.name for p in tmp_path.iterdir()] == ["out.nc"]  # no temporary left behind


def test_outside_phase_history_focuses(tmp_path, spot):
    """A frequency-domain phase history with per-pulse positions (the GOTCHA-like form of
    docs/data-format.md) focuses with salkit focus, without any scenario."""
    from salkit.focus import range_compress
    ph = range_compress(simulate(spot))
    outside = xr.Dataset(
        {"signal": (("slow_time", "frequency"), ph["signal"].values),
         "position": (("slow_time", "xyz"), ph["position"].values),
         "reference_range": (("slow_time",), ph["reference_range"].values)},
        coords={"frequency": ph["frequency"].values, "slow_time": ph["slow_time"].values, "xyz": ["x", "y", "z"]},
        attrs={"salkit_kind": "phase_history"})
    p = write_dataset(outside, tmp_path / "outside.nc")
    img = focus(read_raw(p), algorithm="bp")
    a = np.abs(img["image"].values)
    i, j = np.unravel_index(np.argmax(a), a.shape)
    assert abs(img["azimuth"].values[i]) < 0.01 and abs(img["range"].values[j]) < 0.01
    assert a.max() == pytest.approx(1.0, rel=0.02)
