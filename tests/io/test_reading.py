"""Reading salkit files: complex data plain xarray can read; NaN, truncation, a wrong kind and a
missing variable refused with the file and the variable named."""

import numpy as np
import pytest
import xarray as xr

from salkit.errors import DataFileError
from salkit.io import read_image, read_raw, write_dataset


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




@pytest.mark.parametrize("name,value,words", [
    ("chirp_rate", "abc", "chirp_rate = 'abc': must be a finite number non-zero"),
    ("chirp_rate", 0.0, "chirp_rate = 0.0: must be a finite number non-zero"),
    ("wavelength", -1.55e-6, "wavelength = -1.55e-06: must be a finite number > 0"),
    ("adc_rate", float("nan"), "adc_rate = nan: must be a finite number > 0"),
    ("real_aperture", -0.1, "real_aperture = -0.1: must be a finite number >= 0"),
])
def test_a_raw_files_numbers_are_checked(tmp_path, files, name, value, words):
    """A raw file's numeric attribute that is text, zero, negative or NaN is refused naming it (a
    text chirp rate was an internal error: "could not convert string to float")."""
    rp, ip, raw, img = files
    bad = raw.copy()
    bad.attrs[name] = value
    p = write_dataset(bad, tmp_path / "bad.nc")
    with pytest.raises(DataFileError, match=f"attribute {words}".replace("(", r"\(")):
        read_raw(p)
