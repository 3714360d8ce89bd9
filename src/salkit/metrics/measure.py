"""Measuring a salkit image: :func:`measure` (the brightest target's IPR against theory, its peak
phase, entropy and contrast) and :func:`image_phase_model` (the image's deterministic phase)."""
from __future__ import annotations


import numpy as np
import xarray as xr

from .image import contrast_from_moments, entropy_from_moments, scan
from .pointtarget import analyse_point
from ..signals.phase import wrap
from ..constants import SPEED_OF_LIGHT
from ..errors import DataFileError, ScenarioError, shown


def image_phase_model(image: xr.Dataset):
    """The deterministic phase (rad) of a salkit image at plane coordinates, from its attributes.

    ``aperture_centre`` (bp, pfa): 4 pi f_c (|X - p_c| - |p_c|)/c, p_c the aperture centre.
    ``track`` (omega-k): 4 pi f_c (d(X) - R_s)/c, d the distance from the straight track.
    Returns None when the attributes are missing.

    Parameters
    ----------
    image : xarray.Dataset

    Returns
    -------
    callable or None
        ``fn(az, rg) -> rad``.
    """
    at = image.attrs
    need = ("phase_reference", "aperture_center", "azimuth_axis", "range_axis", "carrier_frequency")
    if not all(k in at for k in need):
        return None
    k = 4 * np.pi * float(at["carrier_frequency"]) / SPEED_OF_LIGHT
    pc = np.asarray(at["aperture_center"], dtype=np.float64)
    a = np.asarray(at["azimuth_axis"], dtype=np.float64)
    r = np.asarray(at["range_axis"], dtype=np.float64)
    kind = str(at["phase_reference"])

    def fn(az, rg):
        X = np.asarray(az, np.float64)[..., None] * a + np.asarray(rg, np.float64)[..., None] * r
        rel = X - pc
        if kind == "track":
            d = np.linalg.norm(rel - (rel @ a)[..., None] * a, axis=-1)
            d0 = np.linalg.norm(-pc - (-pc @ a) * a)
            return k * (d - d0)
        return k * (np.linalg.norm(rel, axis=-1) - np.linalg.norm(pc))
    return fn


#: Dataset kinds that an image is formed from (``salkit_kind``).
_UNFOCUSED = ("raw", "raw_downlooking", "phase_history", "range_profiles")


def _described(obj) -> str:
    """What ``obj`` is, for the error of :func:`measure` given something other than an image."""
    if not isinstance(obj, xr.Dataset):
        return f"an object of type {type(obj).__name__}"
    kind = obj.attrs.get("salkit_kind")
    names = ", ".join(map(str, obj.data_vars)) or "no variables"
    text = f"a dataset of salkit_kind {kind!r} with {names}" if kind else f"a dataset with {names}"
    return text + ("; focus it first (salkit.focus)" if kind in _UNFOCUSED else "")


def measure(image: xr.Dataset, truth: np.ndarray | None = None, reflectivity_phase=None,
            details: bool = False, moments: dict | None = None) -> dict:
    """Measure a focused image against theory.

    Parameters
    ----------
    image : xarray.Dataset
        A salkit image (``image`` variable, ``azimuth``/``range`` coordinates in m, resolution
        and theory attributes as written by :func:`salkit.focus`).
    truth : array_like (T, 2) or (2,), optional
        Expected target positions (azimuth, range), m (one pair: one target); default the file's
        ``target_*`` variables.
    reflectivity_phase : float or sequence of float, optional
        Phase (rad) of the brightest target's reflectivity; the processor should return it at the
        peak. A sequence gives one phase per truth target, and the phase of the target nearest the
        peak is used (so the image is analysed once).
    details : bool
        Also return the upsampled cuts (keys starting with ``_``) for plotting.
    moments : dict, optional
        :func:`salkit.metrics.image.intensity_moments` of the whole image, when ``image`` is a
        window of a larger one (an image written tile by tile): entropy and contrast are then the
        whole image's, as in memory.

    Returns
    -------
    dict
        Flat numbers: ``irw_range_m``, ``irw_azimuth_m``, ``pslr_*_db``, ``islr_*_db``,
        ``peak_offset_*_m`` and each ``*_theory_*`` counterpart, plus entropy and contrast; the two
        phases (:mod:`salkit.metrics.table`): ``image_phase_at_peak_rad``, the image's phase at its
        upsampled peak, and, given the truth, ``peak_phase_rad``, the target's phase (the image's
        deterministic phase restored at the true position) and ``peak_phase_error_rad``.
    """
    if not isinstance(image, xr.Dataset) or "image" not in image or not {"azimuth", "range"} <= set(image.coords):
        raise DataFileError("measure: needs a focused image (an 'image' variable on azimuth and range coordinates in m, "
                            f"as salkit.focus returns); this is {_described(image)}")
    if truth is not None:  # (T, 2) pairs; one pair alone is one target
        try:
            arr = np.asarray(truth, dtype=np.float64)
        except (TypeError, ValueError):  # text, ragged lists
            arr = np.empty((0,))
        if arr.shape == (2,):
            arr = arr[None]
        if arr.ndim != 2 or arr.shape[1] != 2:
            raise ScenarioError("truth", shown(truth), "must be (azimuth, range) pairs in m, an array of shape (T, 2)")
        truth = arr
    if reflectivity_phase is not None:
        try:
            rp = np.asarray(reflectivity_phase, dtype=np.float64)
        except (TypeError, ValueError):
            rp = np.array([np.nan])
        if rp.ndim > 1 or not np.all(np.isfinite(rp)):
            raise ScenarioError("reflectivity_phase", shown(reflectivity_phase),
                                "must be a finite phase in rad, or one per truth target")
    img = np.asarray(image["image"].values)
    az = np.asarray(image["azimuth"].values, dtype=np.float64)
    rg = np.asarray(image["range"].values, dtype=np.float64)
    at = image.attrs
    res_az = float(at.get("resolution_azimuth", 2 * (az[1] - az[0])))
    res_rg = float(at.get("resolution_range", 2 * (rg[1] - rg[0])))
    phase_fn = image_phase_model(image)
    peak, own = scan(img)  # the brightest pixel and the intensity moments, in one pass
    m = analyse_point(img, az, rg, res_az, res_rg, peak=peak, phase_fn=phase_fn)
    out = {k: v for k, v in m.items() if details or not k.startswith("_")}
    if truth is None and "target_azimuth" in image:
        truth = np.stack([image["target_azimuth"].values, image["target_range"].values], axis=1)
    if truth is not None and len(truth):
        d = np.hypot(truth[:, 0] - m["peak_azimuth_m"], truth[:, 1] - m["peak_range_m"])
        t = truth[int(np.argmin(d))]
        out["peak_offset_azimuth_m"] = m["peak_azimuth_m"] - float(t[0])
        out["peak_offset_range_m"] = m["peak_range_m"] - float(t[1])
        out["peak_offset_azimuth_theory_m"] = 0.0
        out["peak_offset_range_theory_m"] = 0.0
        out["target_index"] = int(np.argmin(d))
        out["target_azimuth_m"] = float(t[0])
        out["target_range_m"] = float(t[1])
    if truth is not None and len(truth) and phase_fn is not None:
        # The deterministic image phase changes by 4 pi/lambda per metre of range, so the phase is
        # read at the true target position: flattened peak phase plus the model phase there.
        out["peak_phase_rad"] = float(wrap(m["peak_phase_flat_rad"] + float(phase_fn(out["target_azimuth_m"],
                                                                                  out["target_range_m"]))))
    out.pop("peak_phase_flat_rad", None)
    if reflectivity_phase is not None and not np.isscalar(reflectivity_phase):
        reflectivity_phase = (float(np.asarray(reflectivity_phase)[out["target_index"]])
                              if "target_index" in out else None)
    if reflectivity_phase is not None and "peak_phase_rad" in out:
        out["peak_phase_error_rad"] = float(wrap(out["peak_phase_rad"] - reflectivity_phase))
        out["peak_phase_error_theory_rad"] = 0.0
    for ax in ("range", "azimuth"):
        if f"irw_{ax}_theory" in at:
            out[f"irw_{ax}_theory_m"] = float(at[f"irw_{ax}_theory"])
        if f"pslr_{ax}_theory" in at:  # this axis' own (the collection's support, 0.27 on)
            out[f"pslr_{ax}_theory_db"] = float(at[f"pslr_{ax}_theory"])
            out[f"islr_{ax}_theory_db"] = float(at[f"islr_{ax}_theory"])
        elif "pslr_theory" in at:  # the window's, the same on both axes
            out[f"pslr_{ax}_theory_db"] = float(at["pslr_theory"])
            out[f"islr_{ax}_theory_db"] = float(at["islr_theory"])
        out[f"resolution_{ax}_theory_m"] = float(at.get(f"resolution_{ax}", float("nan")))
    mom = moments if moments is not None else own
    out["entropy"] = entropy_from_moments(mom)
    out["contrast"] = contrast_from_moments(mom)
    # plain Python numbers (numpy's scalars print as np.float64(...)); the details' arrays kept
    return {k: v.item() if isinstance(v, np.generic) else v for k, v in out.items()}
