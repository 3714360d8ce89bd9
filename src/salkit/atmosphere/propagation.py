"""``salkit propagate``'s experiment: an ensemble of plane or spherical waves propagated through
turbulence, measured against theory (:func:`propagation_result`).
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..errors import SamplingError
from .scintillation import inner_scale_q, scintillation_index, scintillation_theory, scintillation_theory_inner_scale
from .spherical import plan_spherical, spherical_wave_ensemble
from .turbulence import r0_from_cn2, rytov_variance
from .waveoptics import plan_sampling, plane_wave_ensemble


def propagation_result(wave: str, wavelength: float, cn2: float, distance: float, count: int, seed: int = 0,
                       layers: int | None = None, inner_scale: float | None = None) -> tuple[xr.Dataset, dict]:
    """An ensemble propagated and measured: the received fields as a dataset and the figures
    against theory (what ``salkit propagate`` writes).

    Parameters
    ----------
    wave : {"plane", "spherical"}
        A spherical wave is a point source on a grid whose spacing grows to the receiver, with an
        absorbing boundary; its field is stored divided by the vacuum field over the receiver region.
    wavelength, distance : float
        m.
    cn2 : float
        m^(-2/3).
    count : int
        Realisations.
    seed : int
    layers : int, optional
        Phase screens (default: :func:`plan_sampling`'s).
    inner_scale : float, optional
        l0 of the modified atmospheric spectrum, m (plane waves).

    Returns
    -------
    (xarray.Dataset, dict)
        ``field`` (realisation, y, x) complex64 with coordinates in m, and metrics:
        ``rytov_variance``, ``scintillation_index``, ``scintillation_index_theory`` (Andrews-Phillips,
        with the inner scale where one is given: then also ``inner_scale_q`` and
        ``scintillation_index_theory_zero_inner_scale``), ``r0_plane_m``, ``r0_spherical_m``, the
        sampling.

    Raises
    ------
    SamplingError
        For a case that cannot be sampled (:func:`plan_sampling`, :func:`plan_spherical`).
    """
    if wave == "plane":
        s = plan_sampling(wavelength, distance, cn2, layers=layers, inner_scale=inner_scale)
        fields, s = plane_wave_ensemble(wavelength, distance, cn2, count, seed=seed, sampling=s,
                                        inner_scale=inner_scale)
        x = (np.arange(s.n) - s.n // 2) * s.dx
        grid = {"grid_n": s.n, "grid_dx_m": s.dx, "layers": s.layers, "layer_r0_m": s.layer_r0}
        si = scintillation_index(fields)
    elif wave == "spherical":
        s = plan_spherical(wavelength, distance, cn2, layers=layers)
        fields, s = spherical_wave_ensemble(wavelength, distance, cn2, count, seed=seed, sampling=s)
        half = fields.shape[-1] // 2
        x = np.arange(-half, half + 1) * s.deltan
        grid = {"grid_n": s.n, "grid_dx_m": s.deltan, "source_dx_m": s.delta1, "layers": len(s.z) - 2,
                "layer_r0_m": s.layer_r0, "receiver_m": s.receiver}
        si = scintillation_index(fields[np.isfinite(fields.real)])
    else:
        raise SamplingError("--wave", wave, "must be plane or spherical")
    sig = float(rytov_variance(cn2, distance, wavelength, wave)) if cn2 > 0 else 0.0
    theory = {"scintillation_index_theory": scintillation_theory(sig, wave)}
    if inner_scale and wave == "plane":
        q = inner_scale_q(wavelength, distance, inner_scale)
        theory = {"scintillation_index_theory": scintillation_theory_inner_scale(sig, q), "inner_scale_m": inner_scale,
                  "inner_scale_q": q, "scintillation_index_theory_zero_inner_scale": scintillation_theory(sig, wave)}
    metrics = {"rytov_variance": sig, "scintillation_index": si, **theory,
               "r0_plane_m": float(r0_from_cn2(cn2, distance, wavelength)) if cn2 > 0 else math.inf,
               "r0_spherical_m": float(r0_from_cn2(cn2, distance, wavelength, "spherical")) if cn2 > 0 else math.inf,
               **grid, "realisations": count}
    ds = xr.Dataset({"field": (("realisation", "y", "x"), fields)},
                    coords={"realisation": np.arange(count), "y": x, "x": x},
                    attrs={"salkit_kind": "propagated_field", "wave": wave, "wavelength": wavelength, "cn2": cn2,
                           "distance": distance, "seed": seed, "layers": grid["layers"], "grid_dx": grid["grid_dx_m"],
                           "description": ("complex field at the receiver plane, unit plane wave transmitted, "
                                           "split-step angular spectrum through periodic Kolmogorov screens"
                                           if wave == "plane" else "point source's field over the receiver region "
                                           "divided by the vacuum field (nan outside the region's disc)")})
    ds["x"].attrs["units"] = ds["y"].attrs["units"] = "m"
    return ds, metrics
