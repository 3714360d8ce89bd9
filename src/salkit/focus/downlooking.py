"""Image formation of the self-interferometric down-looking SAL (seed 000, section 4).

1. Cross-track focusing: FFT of each scan's real balanced current over fast time (eq 12-13),
   referenced to the scan centre t = 0.
2. Single-sideband selection: the positive-frequency band that holds the swath (eq 14-15);
   frequency maps to cross-track position x = xi / (2 v_x / (M lambda f_x)) - M S_b (eq 20).
3. Along-track matched filtering with the conjugate quadratic phase history (eq 17-18).
4. Coherent addition of each forward scan with the following backward scan (eq 16), giving
   the fringe cos(2 pi xi S_a / v_x) of eq 19.

A finding, from the fields: the detector current is real, 2 Re(e_V e_P*) = 2 cos(Phi_x + Phi_y),
not cos(Phi_x) exp(j Phi_y) as eqs 5-7 and 11 write it. Because the backward scan reverses the
sign of Phi_x, the positive sideband of a backward scan carries exp(-j 2 pi xi S_a / v_x) *and*
the conjugate along-track history exp(-j Phi_y). Adding the pairs before the along-track filter
(``order="paper"``, eq 16 then eq 17) therefore focuses only the forward scans; the backward ones
stay spread out and no fringe forms. Focusing each scan direction with its own chirp first and
then adding (``order="focus_then_add"``, the default) gives eq 19 exactly.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

import xarray as xr

from ..errors import DataFileError
from ..geometry.collection import ImagePlane
from ..geometry.downlooking import DLDesign, boresight_frame, design, jones
from ..io.datasets import make_image_dataset
from ..metrics.pointtarget import window_ipr
from ..params.scenario import stored_scenario


@dataclass(frozen=True)
class DLImages:
    """Focused DL-SAL images on one grid: along-track ``y`` (rows) x cross-track ``x`` (columns), m.

    ``forward`` and ``backward`` are the single-direction images (the plain DL-SAL image without
    self-interference is either one); ``combined`` is their coherent sum (eq 19) or, for
    ``order="paper"``, the eq-16-then-eq-17 image.
    """

    y: np.ndarray
    x: np.ndarray
    forward: np.ndarray
    backward: np.ndarray
    combined: np.ndarray
    order: str


def cross_track_focus(current: np.ndarray, design: DLDesign, exp, x_range: tuple[float, float] | None = None,
                      workers: int = -1) -> tuple[np.ndarray, np.ndarray]:
    """FFT over fast time and keep the positive sideband over the swath.

    Parameters
    ----------
    current : ndarray (n_scans, n_t)
        Balanced-detector output.
    design : DLDesign
    exp : DownlookingExperiment
    x_range : (float, float), optional
        Cross-track interval to keep, m (default the whole swath -M W_x/2 .. M W_x/2).

    Returns
    -------
    spectra : complex64 (n_scans, n_x)
        Cross-track-focused scans; a unit scatterer gives a peak of 1.
    x : float64 (n_x,)
        Cross-track positions (m) on the target at the reference distance.
    """
    n_t = current.shape[1]
    nfft = sfft.next_fast_len(exp.oversample * n_t, real=True)
    w = np.hamming(n_t) if exp.window == "hamming" else np.ones(n_t)
    spec = sfft.rfft(current * w[None, :], n=nfft, axis=1, workers=workers)
    f = np.arange(spec.shape[1]) * design.sample_rate / nfft
    x_all = f / design.xi_per_m - design.magnification * exp.optics.bias_common
    lo, hi = x_range if x_range is not None else (-0.5 * design.spot_x, 0.5 * design.spot_x)
    sel = np.flatnonzero((x_all >= lo) & (x_all <= hi) & (f > 0))
    t0 = -0.5 * exp.scan.duration
    phase_ref = np.exp(-2j * np.pi * f[sel] * t0)
    c, s = jones(exp.optics.hwp_angle_deg)
    gain = 1.0 / (abs(2 * c * s) * w.sum())  # the beat of a unit scatterer is 4cs cos(.): 2cs per sideband
    return (spec[:, sel] * (phase_ref * gain)[None, :]).astype(np.complex64), x_all[sel]


def _along_reference(offsets: np.ndarray, design: DLDesign, sign: float, window: str) -> np.ndarray:
    """Matched-filter taps exp(-sign j 2 pi u^2 / (M^2 lambda f_y)) over the footprint |u| <= M W_y/2."""
    half = 0.5 * design.spot_y
    lit = np.abs(offsets) <= half
    h = np.where(lit, np.exp(-sign * 1j * design.along_chirp * offsets ** 2), 0)
    if window == "hamming":
        h = h * np.where(lit, 0.54 + 0.46 * np.cos(np.pi * offsets / half), 0)
    return h


def along_track_focus(rows: np.ndarray, Y_rows: np.ndarray, y_out: np.ndarray, design: DLDesign, sign: float,
                      window: str = "none", workers: int = -1) -> np.ndarray:
    """Matched filtering of cross-track-focused scans along track (eq 17-18), by FFT convolution.

    Parameters
    ----------
    rows : complex (K, n_x)
        Scans of one kind, at uniformly spaced positions ``Y_rows`` (m).
    y_out : ndarray
        Output along-track positions, m: ``Y_rows`` shifted by a constant.
    sign : float
        +1 for scans carrying exp(+j Phi_y), -1 for the conjugate history.

    Returns
    -------
    complex64 (len(y_out), n_x)
        A unit scatterer focuses to 1.
    """
    K = rows.shape[0]
    d = float(Y_rows[1] - Y_rows[0])
    off = float(y_out[0] - Y_rows[0]) / d
    j0 = int(math.floor(off + 0.5))
    shift = (off - j0) * d
    L = int(math.ceil(0.5 * design.spot_y / d)) + 1
    m = np.arange(-L, L + 1)
    h = _along_reference(m * d + shift, design, sign, window)
    n_out = y_out.size
    nconv = sfft.next_fast_len(K + h.size - 1)
    R = sfft.fft(rows, n=nconv, axis=0, workers=workers)
    H = sfft.fft(h, n=nconv)
    full = sfft.ifft(R * H[:, None], axis=0, workers=workers)
    # out[j] = sum_k rows[k] h(y_out[j] - Y_k) = sum_k rows[k] h[(j - k) + L]  -> full index j + L
    if j0 + L < 0 or j0 + L + n_out > full.shape[0]:
        raise ValueError("y_out reaches beyond the scans")
    out = full[j0 + L: j0 + L + n_out]
    return (out / np.abs(h).sum()).astype(np.complex64)


def focus_downlooking(current: np.ndarray, Y: np.ndarray, design: DLDesign, exp,
                      y_range: tuple[float, float] | None = None,
                      x_range: tuple[float, float] | None = None, order: str | None = None,
                      workers: int = -1) -> DLImages:
    """Form forward, backward and combined DL-SAL images from the balanced-detector current.

    Parameters
    ----------
    current : ndarray (n_scans, n_t)
        Raw data; even rows forward scans, odd rows backward scans.
    Y : ndarray (n_scans,)
        Along-track platform position of each scan, m (uniform spacing Delta-Y).
    design : DLDesign
    exp : DownlookingExperiment
    y_range, x_range : (float, float), optional
        Along- and cross-track extent of the output, m.
    order : {"focus_then_add", "paper"}, optional
        Default ``exp.order``.

    Returns
    -------
    DLImages

    Examples
    --------
    >>> imgs = focus_downlooking(current, Y, design(exp), exp)  # doctest: +SKIP
    >>> fringe = imgs.combined.real  # doctest: +SKIP
    """
    order = order or exp.order
    if current.shape[0] % 2:
        current, Y = current[:-1], Y[:-1]
    spec, x = cross_track_focus(current, design, exp, x_range, workers)
    F, B = spec[0::2], spec[1::2]
    YF, YB = Y[0::2], Y[1::2]
    y_all = YF
    if y_range is not None:
        keep = (y_all >= y_range[0]) & (y_all <= y_range[1])
        y_out = y_all[keep]
    else:
        y_out = y_all
    imF = along_track_focus(F, YF, y_out, design, +1.0, exp.window, workers)
    imB = along_track_focus(B, YB, y_out, design, -1.0, exp.window, workers)
    if order == "paper":
        pairs = F + B  # eq 16: add each forward scan to the following backward one
        Yp = 0.5 * (YF + YB)  # the pair's mid-point
        comb = along_track_focus(pairs, Yp, y_out + (Yp[0] - YF[0]), design, +1.0, exp.window, workers)
    else:
        comb = imF + imB
    return DLImages(y_out, x, imF, imB, comb, order)


def image_attrs(d: DLDesign, exp, look_angle_deg: float, kind: str) -> dict:
    """Attributes of a DL-SAL image dataset (theory of the unweighted sinc PSF).

    Parameters
    ----------
    d : DLDesign
    exp : DownlookingExperiment
    look_angle_deg : float
        deg.
    kind : str
        What the image holds.

    Returns
    -------
    dict
        Resolutions and IRW theory (m), PSLR/ISLR theory (dB), fringe period (m).
    """
    wi = window_ipr(exp.window)
    return {
        "algorithm": f"downlooking:{exp.order}", "window": exp.window, "plane": "beam",
        "image_kind": kind, "wavelength": d.wavelength, "magnification": d.magnification,
        "look_angle_deg": look_angle_deg, "range_reference": d.range,
        "resolution_azimuth": d.resolution_y, "resolution_range": d.resolution_x,
        "irw_azimuth_theory": float(wi["irw_factor"]) * d.resolution_y,
        "irw_range_theory": float(wi["irw_factor"]) * d.resolution_x,
        "pslr_theory": wi["pslr_db"], "islr_theory": wi["islr_db"],
        "fringe_period_theory": d.fringe_period_x,
    }


def image_dataset(img: np.ndarray, imgs: DLImages, d: DLDesign, exp, look: float, kind: str,
                  truth: np.ndarray | None = None, scenario_text: str = "") -> xr.Dataset:
    """A DL-SAL image in the foundation image format (azimuth = along track, range = cross track).

    Parameters
    ----------
    img : complex (ny, nx)
    imgs : DLImages
        For the axes ``y``, ``x`` (m).
    d : DLDesign
    exp : DownlookingExperiment
    look : float
        Look angle, deg.
    kind : str
    truth : float (N, 2), optional
        True (along, cross) positions, m.
    scenario_text : str

    Returns
    -------
    xarray.Dataset
    """
    ex, ey, b = boresight_frame(look)
    plane = ImagePlane(origin=np.zeros(3), azimuth=ey, range=ex)
    at = image_attrs(d, exp, look, kind)
    at["scenario"] = scenario_text
    return make_image_dataset(img, imgs.y, imgs.x, plane, at, truth)


def focus_downlooking_raw(raw: xr.Dataset, progress=None) -> xr.Dataset:
    """Form the eq-19 image of a DL-SAL raw dataset (``salkit_kind = raw_downlooking``), with the
    design of the scenario it carries.

    Parameters
    ----------
    raw : xarray.Dataset
        ``current`` (scan, fast_time), ``along_track`` (scan) m, and the ``scenario`` attribute.
    progress : callable, optional
        ``progress(done, total)``, called at the end.

    Returns
    -------
    xarray.Dataset
        Image in the foundation format: ``azimuth`` = along track, ``range`` = cross track, m.

    Raises
    ------
    DataFileError
        For a file without its scenario, current or track, or with non-finite values.
    """
    sc = stored_scenario(raw.attrs)
    if sc is None or not sc.is_downlooking:
        raise DataFileError("not a complete salkit DL-SAL raw file (no down-looking scenario in its attributes)")
    try:
        cur = np.asarray(raw["current"].values, np.float64)
        Y = np.asarray(raw["along_track"].values, np.float64)
    except KeyError as err:
        raise DataFileError(f"not a complete salkit DL-SAL raw file (no {err})") from None
    if not np.all(np.isfinite(cur)):
        raise DataFileError("the raw current holds NaN or infinite values")
    exp = sc.experiment
    d = design(exp)
    imgs = focus_downlooking(cur, Y, d, exp)
    if progress:
        progress(Y.size, Y.size)
    return image_dataset(imgs.combined, imgs, d, exp, exp.track.look_angle_deg, "combined eq 19", None,
                         raw.attrs["scenario"])
