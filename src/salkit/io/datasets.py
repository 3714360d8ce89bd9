"""Labelled datasets (xarray) for raw phase histories and focused images: their builders and
attributes. Writing them (atomic, chunked, streamed) is :mod:`salkit.io.writing`; reading and
checking them, :mod:`salkit.io.reading`.

See ``docs/data-format.md`` for the specification. Complex data are stored as the HDF5 compound
type {r, i} (the nc-complex convention), which ``xarray.open_dataset`` reads back as complex
through the h5netcdf engine.
"""
from __future__ import annotations


import lazy_loader as _lazy
import numpy as np
import xarray as xr

from .. import __version__
from ..params.scenario import dump_scenario

_h5netcdf = _lazy.load("h5netcdf", suppress_warning=True)

#: Version of the salkit data format (docs/data-format.md).
FORMAT_VERSION = "1.0"


RAW_KINDS = ("raw", "phase_history")


def clean_attrs(attrs: dict) -> dict:
    """Attributes NetCDF can store: None dropped, booleans as 0/1, sequences as float64 arrays.

    Parameters
    ----------
    attrs : dict

    Returns
    -------
    dict
    """
    out = {}
    for k, v in attrs.items():
        if v is None:
            continue
        if isinstance(v, bool):
            v = int(v)
        if isinstance(v, (list, tuple)):
            v = np.asarray(v, dtype=np.float64)
        out[k] = v
    return out


def salkit_version() -> str:
    """The installed salkit version (for file attributes).

    Returns
    -------
    str
    """
    return __version__


def make_raw_dataset(signal: np.ndarray, collection, fast_time: np.ndarray, scenario,
                     signal_units: str = "reflectivity", noise: bool = False) -> xr.Dataset:
    """Build the raw (dechirped fast-time) dataset of a simulated collection.

    Parameters
    ----------
    signal : ndarray (P, N) complex64
        Dechirped samples; ``fast_time`` is relative to the reference delay 2*R_ref/c.
    collection : Collection
    fast_time : ndarray (N,)
        s.
    scenario : Scenario
    signal_units : {"reflectivity", "shot_noise"}
    noise : bool
        Whether noise was added.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind = raw`` (docs/data-format.md).
    """

    w, rx = scenario.waveform, scenario.receiver
    ds = xr.Dataset(
        data_vars={
            "signal": (("slow_time", "fast_time"), signal.astype(np.complex64, copy=False),
                       {"long_name": "dechirped I/Q signal", "units": signal_units}),
            "position": (("slow_time", "xyz"), collection.positions,
                         {"long_name": "antenna phase centre", "units": "m"}),
            "velocity": (("slow_time", "xyz"), collection.velocity, {"units": "m/s"}),
            "reference_range": (("slow_time",), collection.reference_range,
                                {"long_name": "dechirp reference range (one way)", "units": "m"}),
            "boresight": (("slow_time", "xyz"), collection.boresight, {"units": "1"}),
        },
        coords={
            "slow_time": ("slow_time", collection.slow_time, {"units": "s"}),
            "fast_time": ("fast_time", fast_time, {"units": "s",
                                                   "long_name": "time after the reference delay"}),
            "xyz": ("xyz", ["x", "y", "z"]),
        },
        attrs=clean_attrs({
            "salkit_kind": "raw",
            "salkit_format": FORMAT_VERSION,
            "salkit_version": salkit_version(),
            "wavelength": w.wavelength,
            "carrier_frequency": w.carrier_frequency,
            "chirp_rate": w.rate,
            "bandwidth": w.bandwidth,
            "pulse_width": w.pulse_width,
            "prf": w.prf,
            "nonlinearity": list(w.nonlinearity) if w.nonlinearity else None,
            "adc_rate": rx.adc_rate,
            "iq": rx.iq,
            "rvp_removed": 0,
            "mode": scenario.platform.mode,
            "real_aperture": scenario.platform.real_aperture,
            "track": collection.track,
            "center_position": collection.center_position,
            "scene_center": [0.0, 0.0, 0.0],
            "signal_units": signal_units,
            "noise_added": noise,
            "origin_llh": list(scenario.scene.origin) if scenario.scene.origin is not None else None,
            "scenario": dump_scenario(scenario),
        }),
    )
    return ds


def make_image_dataset(image: np.ndarray, az: np.ndarray, rg: np.ndarray, plane, attrs: dict,
                       truth: np.ndarray | None = None) -> xr.Dataset:
    """Build a focused-image dataset.

    Parameters
    ----------
    image : ndarray (n_az, n_rg) complex
    az, rg : ndarray
        Azimuth and range coordinates of the pixels in the image plane, m, from the scene centre.
    plane : ImagePlane
        Origin and unit axes of the image plane in the scene frame.
    attrs : dict
        Parameters to carry (algorithm, window, wavelength, resolutions, scenario...).
    truth : ndarray (T, 2), optional
        Expected azimuth/range positions of point targets, m.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind = image`` (docs/data-format.md).
    """
    data = {"image": (("azimuth", "range"), image.astype(np.complex64, copy=False),
                      {"long_name": "focused complex image", "units": "1"})}
    if truth is not None and len(truth):
        data["target_azimuth"] = (("target",), truth[:, 0], {"units": "m"})
        data["target_range"] = (("target",), truth[:, 1], {"units": "m"})
    a = dict(attrs)
    a.update({"salkit_kind": "image", "salkit_format": FORMAT_VERSION, "salkit_version": salkit_version(),
              "plane_origin": plane.origin - (plane.origin @ plane.azimuth) * plane.azimuth
              - (plane.origin @ plane.range) * plane.range,
              "azimuth_axis": plane.azimuth, "range_axis": plane.range})
    return xr.Dataset(
        data_vars=data,
        coords={"azimuth": ("azimuth", np.asarray(az, np.float64), {"units": "m"}),
                "range": ("range", np.asarray(rg, np.float64), {"units": "m"})},
        attrs=clean_attrs(a),
    )
