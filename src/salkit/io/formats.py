"""Reading a raw or phase-history file of any supported format by its suffix
(:func:`read_phase_data`), and xarray's NetCDF engine order (h5netcdf first: it decodes salkit's
complex variables)."""
from pathlib import Path as _P

import xarray as _xr

from ..errors import DataFileError as _E
from .cphd import read_cphd
from .reading import read_raw, scenario_hint
from .gotcha import read_gotcha

PHASE_SUFFIXES = {".nc": "NetCDF", ".h5": "NetCDF", ".cphd": "CPHD", ".mat": "GOTCHA .mat"}
#: Suffixes read as salkit NetCDF/HDF5 (what ``salkit simulate`` may write).
NETCDF_SUFFIXES = (".nc", ".h5", ".nc4", ".hdf5")


def read_phase_data(path, lazy: bool = False) -> "_xr.Dataset":
    """Read a raw or phase-history file of any supported format, chosen by the suffix:
    ``.nc``/``.h5`` (salkit NetCDF), ``.cphd`` (CPHD 1.0), ``.mat`` (GOTCHA layout).

    Parameters
    ----------
    path : str or Path
    lazy : bool
        NetCDF and CPHD: leave the signal on disk until it is indexed (:func:`salkit.io.read_raw`,
        :func:`salkit.io.read_cphd`), read a block of pulses at a time by focusing.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind`` "raw" or "phase_history".

    Raises
    ------
    DataFileError
        Unknown suffix or an unusable file.
    """
    suf = _P(path).suffix.lower()
    if suf == ".cphd":
        return read_cphd(path, lazy=lazy)
    if suf == ".mat":
        return read_gotcha(path)
    if suf in NETCDF_SUFFIXES:
        return read_raw(path, lazy=lazy)
    raise _E(f"{path}: unknown suffix {suf!r}; salkit reads {', '.join(PHASE_SUFFIXES)}{scenario_hint(path)}")


# Complex variables are HDF5 compound types that only the h5netcdf engine decodes as complex.
# When netCDF4-python is also installed, make plain xarray.open_dataset try h5netcdf first.
try:  # pragma: no cover - depends on the xarray version
    _order = _xr.get_options().get("netcdf_engine_order")
    if _order and _order[0] != "h5netcdf":
        _xr.set_options(netcdf_engine_order=("h5netcdf",) + tuple(e for e in _order if e != "h5netcdf"))
except Exception:  # noqa: BLE001
    pass
