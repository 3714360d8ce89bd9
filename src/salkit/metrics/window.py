"""Measuring an image larger than memory: the window that :func:`salkit.metrics.measure` reads around
the brightest pixel, and the whole image's intensity moments, found in one pass a block at a time."""
from __future__ import annotations

import xarray as xr

from ..io.reading import lazy_reads
from .image import scan
from .pointtarget import analysis_extent


def brightest_window(image: xr.Dataset, rows: int | None = None) -> tuple[xr.Dataset, dict]:
    """The window of ``image`` that the point-target analysis reads around its brightest pixel, and
    the whole image's intensity moments, from one pass over the image a block of rows at a time: an
    image larger than memory (opened lazily) is read once, one block in memory at a time.

    The window is the analysis' own neighbourhood (:func:`salkit.metrics.pointtarget.analysis_extent`:
    +-15 resolution cells, plus a pixel), so :func:`salkit.metrics.measure` of the window with the
    moments gives the figures of the whole image in memory.

    Parameters
    ----------
    image : xarray.Dataset
        A salkit image (``image`` (azimuth, range); ``resolution_azimuth`` and ``resolution_range``
        attributes, m).
    rows : int, optional
        Rows read at a time; default about 4 MiB of pixels.

    Returns
    -------
    (xarray.Dataset, dict)
        ``image.isel(...)`` around the brightest pixel, loaded, with the image's attributes and
        coordinates; and :func:`salkit.metrics.image.intensity_moments` of the whole image.
    """
    v = image["image"]
    nx, ny = v.shape
    at, moments = scan(v, rows)
    az, rg = image["azimuth"].values, image["range"].values
    at_ = image.attrs
    dx = float(az[1] - az[0]) if nx > 1 else 1.0
    dy = float(rg[1] - rg[0]) if ny > 1 else 1.0
    ext = analysis_extent(dx, dy, float(at_.get("resolution_azimuth", 2 * dx)),
                          float(at_.get("resolution_range", 2 * dy)))
    px, py = ext["pixels"][0] + 1, ext["pixels"][1] + 1
    sub = image.isel(azimuth=slice(max(0, at[0] - px), min(nx, at[0] + px)),
                     range=slice(max(0, at[1] - py), min(ny, at[1] + py)))
    sub = sub.drop_vars([m for m in ("collection_position", "collection_time") if m in sub])
    with lazy_reads("image", v.encoding.get("source") or image.encoding.get("source")):
        sub = sub.load()
    return sub, moments
