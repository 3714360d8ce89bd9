"""NetCDF4/HDF5 reading and writing of salkit datasets (atomic writes, validated reads)."""
import xarray as _xr

from .datasets import (describe, make_image_dataset, make_raw_dataset, open_dataset, read_image,
                       read_raw, write_dataset, write_json_atomic, write_text_atomic)

# Complex variables are HDF5 compound types that only the h5netcdf engine decodes as complex.
# When netCDF4-python is also installed, make plain xarray.open_dataset try h5netcdf first.
try:  # pragma: no cover - depends on the xarray version
    _order = _xr.get_options().get("netcdf_engine_order")
    if _order and _order[0] != "h5netcdf":
        _xr.set_options(netcdf_engine_order=("h5netcdf",) + tuple(e for e in _order if e != "h5netcdf"))
except Exception:  # noqa: BLE001
    pass

__all__ = ["describe", "make_image_dataset", "make_raw_dataset", "open_dataset", "read_image",
           "read_raw", "write_dataset", "write_json_atomic", "write_text_atomic"]
