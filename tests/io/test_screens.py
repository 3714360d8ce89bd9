"""Phase screens on disk: NetCDF with units, read back exactly."""
import numpy as np
import xarray as xr

from salkit.io.screens import write_screens


def test_write_and_read_back(tmp_path):
    phi = np.random.default_rng(0).standard_normal((2, 32, 32)).astype(np.float32)
    nc = write_screens(phi, 0.01, tmp_path / "s.nc", r0=0.05, seed=0)
    assert [p.name for p in tmp_path.iterdir()] == ["s.nc"]
    ds = xr.open_dataset(nc)
    np.testing.assert_array_equal(ds["phase"].values, phi)
    assert ds["phase"].attrs["units"] == "rad" and float(ds["x"][1] - ds["x"][0]) == 0.01
    assert ds.attrs["r0"] == 0.05
    ds.close()
