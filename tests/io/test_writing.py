"""Writing salkit files atomically: a failed write leaves the old file intact and nothing else."""

import numpy as np
import pytest
import xarray as xr

from salkit.io import write_dataset


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


