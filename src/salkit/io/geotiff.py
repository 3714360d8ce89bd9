"""A detected (magnitude) image as a Cloud-Optimised GeoTIFF (rioxarray, GDAL's COG driver), placed on
the earth by its corners' geodetic positions (image attributes ``corner_latitude`` and
``corner_longitude``, docs/data-format.md) in the WGS84 / UTM zone of its centre, with an affine
pixel-to-map transform (rotated: rows run along the image's azimuth axis)."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import rioxarray  # noqa: F401  (registers the .rio accessor)
import xarray as xr
from affine import Affine
from pyproj import CRS, Transformer

from ..errors import DataFileError
from .writing import atomic_path

#: Largest misfit (pixels) of the fourth corner to the affine map the other three define: beyond it
#: the image is not a plane map of the ground (a slant plane, a large or curved scene).
AFFINE_TOLERANCE_PIXELS = 0.05


def geotiff_crs(lat: float, lon: float) -> CRS:
    """The WGS84 / UTM zone holding ``lat``, ``lon`` (deg): an EPSG code every GIS reads from a GeoTIFF
    exactly (a local orthographic projection does not survive the GeoTIFF keys). Over an image's
    extent the map is affine to far below a pixel (its scale and convergence are constant there);
    :func:`write_geotiff` checks the fourth corner.

    Parameters
    ----------
    lat, lon : float
        deg.

    Returns
    -------
    pyproj.CRS

    Examples
    --------
    >>> geotiff_crs(48.86, 2.29).to_epsg(), geotiff_crs(-33.9, 151.2).to_epsg()
    (32631, 32756)
    """
    zone = int((lon + 180.0) % 360.0 // 6.0) + 1
    return CRS.from_epsg((32600 if lat >= 0 else 32700) + zone)


def write_geotiff(image: xr.Dataset, path: str | Path) -> dict:
    """Write ``|image|`` (float32) as a Cloud-Optimised GeoTIFF, atomically.

    Parameters
    ----------
    image : xarray.Dataset
        A salkit image in the ground plane with its geodetic corners (an image focused with
        ``scene.origin`` or ``--origin``).
    path : path
        ``.tif`` or ``.tiff``.

    Returns
    -------
    dict
        ``crs`` (PROJ string), ``transform`` (the affine, 6 numbers), ``misfit_pixels`` (the fourth
        corner against the affine).

    Raises
    ------
    DataFileError
        An image without a geographic reference, or not in the ground plane.
    """
    a = image.attrs
    if "corner_latitude" not in a:
        raise DataFileError("a GeoTIFF needs the image's geographic reference (corner_latitude/longitude): "
                            "focus with scene.origin or --origin LAT,LON,HAE")
    if str(a.get("plane", "slant")) != "ground":
        raise DataFileError(f"a GeoTIFF maps the ground: this image is in the {a.get('plane', 'slant')} plane; "
                            "focus it with --plane ground")
    nx, ny = image.sizes["azimuth"], image.sizes["range"]
    lat, lon = np.asarray(a["corner_latitude"], float), np.asarray(a["corner_longitude"], float)
    clat, clon = float(a["center_latitude"]), float(a["center_longitude"])
    crs = geotiff_crs(clat, clon)
    x, y = Transformer.from_crs("EPSG:4326", crs, always_xy=True).transform(lon, lat)
    x, y = np.asarray(x, float), np.asarray(y, float)
    # corners: (first azimuth, first range), (first, last), (last, first), (last, last); rows are
    # azimuth pixels, columns range pixels; the affine maps pixel corners (pixel centres + 0.5)
    ca = ((x[1] - x[0]) / (ny - 1), (y[1] - y[0]) / (ny - 1))  # per column
    ra = ((x[2] - x[0]) / (nx - 1), (y[2] - y[0]) / (nx - 1))  # per row
    t = Affine(ca[0], ra[0], x[0] - 0.5 * (ca[0] + ra[0]), ca[1], ra[1], y[0] - 0.5 * (ca[1] + ra[1]))
    pred = t @ (ny - 0.5, nx - 0.5)
    px = np.hypot(*ca)
    misfit = float(np.hypot(pred[0] - x[3], pred[1] - y[3]) / px)
    if misfit > AFFINE_TOLERANCE_PIXELS:
        raise DataFileError(f"the image's corners depart {misfit:.3g} pixels from a plane map of the ground "
                            f"(at most {AFFINE_TOLERANCE_PIXELS}): not written as a GeoTIFF")
    amp = np.abs(np.asarray(image["image"].values)).astype(np.float32)
    da = xr.DataArray(amp, dims=("y", "x"), name="amplitude",
                      attrs={"long_name": "image magnitude |I| (reflectivity amplitude)", "units": "1"})
    with warnings.catch_warnings():  # rioxarray notes it cannot derive coordinates of a rotated grid
        warnings.simplefilter("ignore")
        da = da.rio.write_crs(crs).rio.write_transform(t)
        with atomic_path(path, suffix=".tif") as tmp:
            da.rio.to_raster(tmp, driver="COG")
    return {"crs": f"EPSG:{crs.to_epsg()}", "transform": list(t)[:6], "misfit_pixels": misfit}
