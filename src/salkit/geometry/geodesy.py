"""Placing the scene frame on the earth: local east-north-up metres about a geodetic origin (WGS84
latitude, longitude, height above the ellipsoid) to geodetic coordinates, through pyproj (EPSG:4979
geodetic 3-D and EPSG:4978 earth-centred Cartesian), in float64."""
from __future__ import annotations

from functools import lru_cache

import lazy_loader as _lazy
import numpy as np

from .collection import ImagePlane

_pyproj = _lazy.load("pyproj", suppress_warning=True)  # on first use, not at every process's start


@lru_cache(maxsize=2)
def _transformer(to_ecef: bool) -> "_pyproj.Transformer":
    src, dst = ("EPSG:4979", "EPSG:4978") if to_ecef else ("EPSG:4978", "EPSG:4979")
    return _pyproj.Transformer.from_crs(src, dst, always_xy=True)


def check_origin(origin_llh) -> np.ndarray:
    """A geodetic origin as float64 (lat deg, lon deg, height m), or ValueError saying what is wrong.

    Parameters
    ----------
    origin_llh : sequence of 3 float

    Returns
    -------
    ndarray (3,)
    """
    llh = np.asarray(origin_llh, dtype=np.float64).ravel()
    if llh.size != 3 or not np.isfinite(llh).all() or abs(llh[0]) > 90 or not -180 <= llh[1] <= 360:
        raise ValueError("must be [latitude deg, longitude deg, height m] with |latitude| <= 90 and "
                         "longitude in [-180, 360]")
    return llh


def enu_to_geodetic(enu, origin_llh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local east, north, up coordinates (m) about ``origin_llh`` to WGS84 latitude, longitude (deg)
    and height above the ellipsoid (m).

    Parameters
    ----------
    enu : array (..., 3)
        m.
    origin_llh : (lat deg, lon deg, height m)

    Returns
    -------
    (ndarray, ndarray, ndarray)
        Latitude (deg), longitude (deg), height (m), of shape ``enu.shape[:-1]``.

    Examples
    --------
    >>> lat, lon, h = enu_to_geodetic([0.0, 1000.0, 0.0], (45.0, 7.0, 0.0))
    >>> round(float(lat) - 45.0, 6), round(float(lon) - 7.0, 9), round(float(h), 3)  # 1 km north
    (0.008998, 0.0, 0.079)
    """
    llh = check_origin(origin_llh)
    lat, lon = np.radians(llh[0]), np.radians(llh[1])
    east = np.array([-np.sin(lon), np.cos(lon), 0.0])
    north = np.array([-np.sin(lat) * np.cos(lon), -np.sin(lat) * np.sin(lon), np.cos(lat)])
    up = np.array([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])
    o = np.array(_transformer(True).transform(llh[1], llh[0], llh[2]), dtype=np.float64)
    p = np.asarray(enu, dtype=np.float64)
    ecef = o + p[..., 0:1] * east + p[..., 1:2] * north + p[..., 2:3] * up
    lo, la, h = _transformer(False).transform(ecef[..., 0], ecef[..., 1], ecef[..., 2])
    return np.asarray(la, np.float64), np.asarray(lo, np.float64), np.asarray(h, np.float64)


def geolocate_image(image, origin_llh) -> dict:
    """:func:`image_geolocation` of a salkit image from its own attributes (``plane_origin``,
    ``azimuth_axis``, ``range_axis``) and coordinates, for an origin given after it was formed.

    Parameters
    ----------
    image : xarray.Dataset
        A salkit image.
    origin_llh : (lat deg, lon deg, height m)

    Returns
    -------
    dict
        ``origin_llh`` and the corner and centre positions of :func:`image_geolocation`.
    """
    a = image.attrs
    plane = ImagePlane(np.asarray(a["plane_origin"], np.float64), np.asarray(a["azimuth_axis"], np.float64),
                       np.asarray(a["range_axis"], np.float64))
    return {"origin_llh": check_origin(origin_llh),
            **image_geolocation(origin_llh, plane, image["azimuth"].values, image["range"].values)}


def image_geolocation(origin_llh, plane, azimuth, rng) -> dict:
    """Geodetic positions of an image's corners and centre, for its attributes.

    Parameters
    ----------
    origin_llh : (lat deg, lon deg, height m)
        Where the scene frame's origin (x east, y north, z up) lies on the earth.
    plane : ImagePlane
        The image plane (``origin``, ``azimuth``, ``range`` in the scene frame).
    azimuth, rng : ndarray
        The image's pixel coordinates, m.

    Returns
    -------
    dict
        ``corner_latitude``, ``corner_longitude``, ``corner_height`` (4: first azimuth and first
        range, first azimuth and last range, last and first, last and last; deg, deg, m) and
        ``center_latitude``, ``center_longitude``, ``center_height`` (the middle pixel).
    """
    a, r = np.asarray(plane.azimuth, np.float64), np.asarray(plane.range, np.float64)
    o = np.asarray(plane.origin, np.float64)
    base = o - (o @ a) * a - (o @ r) * r
    az, rg = np.asarray(azimuth, np.float64), np.asarray(rng, np.float64)
    pts = [(az[0], rg[0]), (az[0], rg[-1]), (az[-1], rg[0]), (az[-1], rg[-1]), (az[az.size // 2], rg[rg.size // 2])]
    enu = np.array([base + x * a + y * r for x, y in pts])
    lat, lon, h = enu_to_geodetic(enu, origin_llh)
    return {"corner_latitude": lat[:4], "corner_longitude": lon[:4], "corner_height": h[:4],
            "center_latitude": float(lat[4]), "center_longitude": float(lon[4]), "center_height": float(h[4])}
