"""Height from the self-interferogram of the down-looking SAL (seeds 000/003, oblique view).

The forward- and backward-scan images of one scene form the interferogram F B*; its phase is the
flat carrier (eq 25) plus what the terrain adds. Unwrapped and stripped of the carrier, the
residual phase is turned into height by the fringe-shift model (the image shifts by h sin(look)
across the fringes) and compared with the true surface.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import griddata
from scipy.ndimage import gaussian_filter
from scipy.stats import binned_statistic_2d

from .core import carrier_phase, height_from_fringe_shift, interferogram, unwrap_phase, wrap


def recover_height(forward: np.ndarray, backward: np.ndarray, y: np.ndarray, x: np.ndarray, magnification: float,
                   bias_common: float, fringe_period: float, look_angle_deg: float, unwrap: str,
                   resolution_x: float, truth_positions: np.ndarray, truth_heights: np.ndarray) -> dict:
    """Interferogram, unwrapping, residual phase and height of a terrain image pair, with their
    errors against the true surface.

    Parameters
    ----------
    forward, backward : complex (ny, nx)
        Forward- and backward-scan images on the same grid.
    y, x : float64
        Along-track and cross-track pixel coordinates on the target, m.
    magnification : float
        Of the design at the reference range.
    bias_common : float
        Common lens bias S_b, m.
    fringe_period : float
        Cross-track fringe period (eq 25), m.
    look_angle_deg : float
        Oblique look angle, deg.
    unwrap : str
        Unwrapping method (:func:`salkit.interferometry.unwrap_phase`).
    resolution_x : float
        Cross-track resolution, m (sets the smoothing of the height map: 3 cells).
    truth_positions : float64 (N, 2)
        Image position (along, cross) of each true scatterer, m.
    truth_heights : float64 (N,)
        Its height, m.

    Returns
    -------
    dict
        Arrays ``ifg``, ``wrapped``, ``residual_wrapped``, ``unwrapped``, ``residual`` (rad),
        ``h_rec``, ``h_true``, ``h_rec_map``, ``h_true_map`` (m), ``valid``; and ``metrics``
        (heights in m, phases in rad).
    """
    F, B = forward.astype(np.complex128), backward.astype(np.complex128)
    ifg = interferogram(F, B)
    wrapped = np.angle(ifg)
    carrier = carrier_phase(x, magnification, bias_common, fringe_period)[None, :]
    residual_wrapped = wrap(wrapped - carrier)
    unwrapped = unwrap_phase(wrapped, unwrap)
    residual = unwrapped - carrier
    mag = np.abs(ifg)
    good = mag > 0.05 * np.percentile(mag, 99)
    residual = residual - np.median(residual[good])
    h_rec = height_from_fringe_shift(residual, fringe_period, look_angle_deg)
    # the true height of the surface seen in each image pixel (scatterers gridded by image position)
    dy, dx = y[1] - y[0], x[1] - x[0]
    ey = np.concatenate([y - dy / 2, [y[-1] + dy / 2]])
    ex_ = np.concatenate([x - dx / 2, [x[-1] + dx / 2]])
    h_true = binned_statistic_2d(truth_positions[:, 0], truth_positions[:, 1], truth_heights, "mean",
                                 bins=[ey, ex_]).statistic
    valid = good & np.isfinite(h_true)
    err = h_rec[valid] - h_true[valid]
    # smooth surfaces for the contour map: the true height interpolated at the image positions, and
    # the recovered height by normalised convolution over the valid pixels (3 cells)
    YY, XX = np.meshgrid(y, x, indexing="ij")
    h_true_map = griddata(truth_positions, truth_heights, (YY, XX), method="linear")
    sig = 3 * resolution_x / dx
    wgt = gaussian_filter(valid.astype(float), sig)
    h_rec_map = np.where(wgt > 0.2, gaussian_filter(np.where(valid, h_rec, 0.0), sig) / np.maximum(wgt, 1e-12), np.nan)
    # how much interferogram phase per metre of height the SAL shows, against the projection model
    A = np.vstack([h_true[valid], np.ones(int(valid.sum()))]).T
    sens = float(np.linalg.lstsq(A, residual[valid], rcond=None)[0][0]) if valid.sum() > 2 else float("nan")
    corr = float(np.corrcoef(residual[valid], h_true[valid])[0, 1]) if valid.sum() > 2 else float("nan")
    th = math.radians(look_angle_deg)
    h_rms = float(np.sqrt(np.nanmean(h_true[valid] ** 2)))
    return {
        "ifg": ifg, "wrapped": wrapped, "h_true_map": h_true_map, "h_rec_map": h_rec_map,
        "residual_wrapped": residual_wrapped, "unwrapped": unwrapped, "residual": residual, "h_rec": h_rec,
        "h_true": h_true, "valid": valid,
        "metrics": {
            "terrain_height_rms_m": h_rms,
            "terrain_residual_phase_rms_rad": float(np.std(residual_wrapped[good])),
            "terrain_height_recovered_rms_m": float(np.sqrt(np.mean(h_rec[valid] ** 2))),
            "terrain_height_error_rms_m": float(np.sqrt(np.mean(err ** 2))),
            "terrain_height_error_over_height_rms": float(np.sqrt(np.mean(err ** 2)) / max(h_rms, 1e-12)),
            "terrain_residual_height_correlation": corr,
            "terrain_phase_per_height_rad_per_m": sens,
            "terrain_phase_per_height_model_rad_per_m": 2 * 2 * math.pi * math.sin(th) / fringe_period,
            "terrain_image_shift_per_height_theory": math.sin(th),
        },
    }
