"""Phase-screen files: variable ``phase`` (rad) with dims (screen, y, x), coordinates in metres."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .writing import write_dataset
from .. import __version__


def screens_dataset(phi: np.ndarray, dx: float, **attrs) -> xr.Dataset:
    """Labelled dataset of screens (K, n, n) with spacing ``dx`` (m) and generation parameters.

    Parameters
    ----------
    phi : float (K, n, n)
        rad.
    dx : float
        m.
    **attrs
        Generation parameters.

    Returns
    -------
    xarray.Dataset
    """
    K, ny, nx = phi.shape
    a = {k: v for k, v in attrs.items() if v is not None}
    a.update({"salkit_kind": "phase_screens", "salkit_version": __version__, "dx": dx,
              "generator": "FFT (aliased, cell-integrated) + split near-DC cells + 8 subharmonic levels "
                           "+ residual tilt"})
    return xr.Dataset({"phase": (("screen", "y", "x"), phi, {"units": "rad", "long_name": "phase"})},
                      coords={"screen": np.arange(K), "y": ("y", np.arange(ny) * dx, {"units": "m"}),
                              "x": ("x", np.arange(nx) * dx, {"units": "m"})}, attrs=a)


def write_screens(phi: np.ndarray, dx: float, path: str | Path, **attrs) -> Path:
    """Write screens to NetCDF (atomically).

    Parameters
    ----------
    phi : float (K, n, n)
        rad.
    dx : float
        m.
    path : path
        NetCDF file.
    **attrs
        Generation parameters.

    Returns
    -------
    Path
    """
    path = Path(path)
    write_dataset(screens_dataset(phi, dx, **attrs), path)
    return path
