"""Polar format algorithm (PFA) for spotlight collections.

The phase history of a scatterer at x' (relative to the scene centre, motion-compensated to it)
is P(f, n) ~ exp(+j k_n(f) . x'), k = (4 pi f / c) u_n, u_n the unit vector from the scene centre
to the antenna. Projected on the image plane (azimuth a, range r) the samples lie on a polar
raster; a range (keystone) interpolation then an azimuth interpolation put them on a rectangle,
and a 2-D FFT forms the image on exactly the requested grid (dk = 2 pi / (n d)).

Phase: the plane-wave model leaves each scatterer with the wavefront-curvature phase
exp(-j 4 pi f_c q(x)/c), q(x) = |x - p_c| - |p_c| + u_c . x at the aperture centre p_c. It is
removed pixel by pixel, so PFA images carry the same phase as backprojection.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import scipy.fft as sfft
from numba import njit, prange

from ..constants import FFT_WORKERS, SPEED_OF_LIGHT
from ..errors import ScenarioError
from ..geometry.collection import angle_between, first_null_sin
from ..signals.windows import Window
from ..signals.phase import sincos_cycles as _sincos_cycles
from .formers import Accuracy, ImageGrid, ImageResult, Sizes, register_former
from .phasehistory import PhaseHistory
from .interp import azimuth_pass, interp_rows_linear, kernel_table
from ..resources import check_memory
from ..tolerances import BP_UPSAMPLE

WORKERS = FFT_WORKERS

#: Largest grid (pixels) PFA forms to cover the illuminated scene before cropping (2 GiB complex64).
MAX_COVER_PIXELS = 2 ** 28
#: Plane-wave limits: residual (defocusing) phase of the wavefront curvature over the aperture, rad,
#: and the position distortion, pixels, at the grid's corners; above either PFA warns.
PLANE_WAVE_PHASE_RAD = math.pi / 4
PLANE_WAVE_SHIFT_PX = 0.5


def plane_wave_error(freq: np.ndarray, positions: np.ndarray, plane, az: np.ndarray, rg: np.ndarray) -> dict:
    """How far PFA's plane-wave model departs from the spherical wave over a grid.

    At each of the grid's corners and edge midpoints x, the two-way phase the data carry,
    k_c (|x - p_n| - |p_n|), differs from the plane-wave model's -k_c u_n . x by e(n). PFA
    removes e at the aperture centre (the curvature phase, pixel by pixel) at the carrier only;
    what varies over the aperture remains. Its part linear in the azimuth wavenumber
    k_x,n = k_c u_n . e_a moves the point in azimuth (de/dk_x metres), the rest defocuses it; over
    the band the centre's e scales with k, which moves the point in range by e_c / k_c along the
    line of sight (e_c / (k_c |u_c . e_r|) along the plane's range axis).

    Parameters
    ----------
    freq : float64 (M,)
        Hz.
    positions : float64 (P, 3)
        m, scene centre at the origin.
    plane : ImagePlane
    az, rg : float64
        Pixel axes, m.

    Returns
    -------
    dict
        ``pfa_defocus_rad`` (largest residual phase after a constant and a linear term),
        ``pfa_distortion_azimuth_m``, ``pfa_distortion_range_m`` (largest displacements) and
        ``pfa_distortion_px`` (the larger over the pixel spacing).
    """
    pos = np.asarray(positions, np.float64)
    R = np.linalg.norm(pos, axis=1)
    u = pos / R[:, None]
    kc = 4.0 * math.pi * float(freq[freq.size // 2]) / SPEED_OF_LIGHT
    kx = kc * (u @ plane.azimuth)
    kx = kx - kx.mean()
    scale = max(float(np.max(np.abs(kx))), 1e-300)
    worst_q, worst_s, worst_r = 0.0, 0.0, 0.0
    c = positions.shape[0] // 2
    cos_r = max(abs(float(u[c] @ plane.range)), 1e-3)
    for a in (az[0], az[az.size // 2], az[-1]):
        for g in (rg[0], rg[rg.size // 2], rg[-1]):
            x = plane.points(a, g)
            e = kc * (np.linalg.norm(x - pos, axis=1) - R) + kc * (u @ x)
            c1 = np.polyfit(kx / scale, e, 1)
            worst_q = max(worst_q, float(np.max(np.abs(e - np.polyval(c1, kx / scale)))))
            worst_s = max(worst_s, abs(float(c1[0])) / scale)
            worst_r = max(worst_r, abs(float(e[c])) / kc / cos_r)
    dx = abs(float(az[1] - az[0])) if az.size > 1 else 1.0
    dy = abs(float(rg[1] - rg[0])) if rg.size > 1 else 1.0
    return {"pfa_defocus_rad": worst_q, "pfa_distortion_azimuth_m": worst_s, "pfa_distortion_range_m": worst_r,
            "pfa_distortion_px": max(worst_s / dx, worst_r / dy)}


def illuminated_extent(freq: np.ndarray, positions: np.ndarray, plane, real_aperture: float = 0.0) -> dict:
    """Extent of the scene that contributes to a spotlight phase history, in the image plane.

    Per axis the smaller of what the data can hold unambiguously (range c/(2 df) from the frequency
    step; azimuth lambda_min/(2 dtheta) from the angle between pulses) and, when the telescope
    diameter is known, the null-to-null beam footprint on the ground (azimuth 2 R s, s the sine of
    the first-null half-angle; range 2 R s / tan(grazing) in the slant plane, 2 R s / sin(grazing)
    in the ground plane).

    Parameters
    ----------
    freq : float64 (M,)
        Uniform frequency samples, Hz.
    positions : float64 (P, 3)
        Antenna positions, scene centre at the origin, m.
    plane : ImagePlane
        Image plane (unit ``azimuth`` and ``range`` axes).
    real_aperture : float
        Telescope diameter, m; 0 when unknown.

    Returns
    -------
    dict
        ``azimuth`` and ``range`` extents (m) and ``limited_by`` ("data" or "beam") per axis.
    """
    c = SPEED_OF_LIGHT
    P = positions.shape[0]
    u = positions / np.linalg.norm(positions, axis=1, keepdims=True)
    dtheta = angle_between(u[0], u[-1]) / max(P - 1, 1)
    lam_min = c / float(np.max(freq))
    pc = positions[P // 2]
    R = float(np.linalg.norm(pc))
    look = -pc / R
    cos_r = max(abs(float(look @ plane.range)), 1e-6)
    rg_data = c / (2.0 * abs(float(freq[1] - freq[0]))) / cos_r
    az_data = lam_min / (2.0 * dtheta) if dtheta > 0 else math.inf
    out = {"azimuth": az_data, "range": rg_data, "limited_by": {"azimuth": "data", "range": "data"}}
    if real_aperture > 0:
        s = first_null_sin(c / float(np.min(freq)), real_aperture)
        d = 2.0 * R * s
        sin_g = max(abs(float(look[2])), 1e-6)
        cos_g = math.sqrt(max(1.0 - sin_g ** 2, 0.0))
        rg_beam = d / sin_g if abs(float(plane.range[2])) < 1e-9 else d * max(cos_g, 1e-6) / sin_g
        rg_beam = max(rg_beam, d)
        if d < out["azimuth"]:
            out["azimuth"], out["limited_by"]["azimuth"] = d, "beam"
        if rg_beam < out["range"]:
            out["range"], out["limited_by"]["range"] = rg_beam, "beam"
    return out


def cover_axes(az: np.ndarray, rg: np.ndarray, extent: dict, margin: int = 8):
    """Axes on the spacing of ``az``/``rg`` that hold the requested ones and the illuminated extent.

    Returns
    -------
    az2, rg2 : ndarray
        Extended axes (m).
    (i0, j0) : tuple of int
        Index of ``az[0]``, ``rg[0]`` in the extended axes.

    Parameters
    ----------
    az, rg : float64
        Requested axes, m.
    extent : dict
        :func:`illuminated_extent`.
    margin : int
        Extra pixels on each side.
    """
    def one(x, ext):
        n = x.size
        d = float(x[1] - x[0])
        c0 = float(x[n // 2])
        half = max(abs(c0) + ext / 2.0, (n // 2 + 1) * d)
        n2 = max(n, 2 * int(math.ceil(half / d)) + 1 + 2 * margin)
        n2 = sfft.next_fast_len(n2)
        x2 = c0 + (np.arange(n2) - n2 // 2) * d
        return x2, n2 // 2 - n // 2
    az2, i0 = one(az, extent["azimuth"])
    rg2, j0 = one(rg, extent["range"])
    return az2, rg2, (i0, j0)


@njit(parallel=True, cache=True, fastmath=True)
def _finalise(img, az, rg, a, r, pc, kx_c, ky_c, k_c, scale):
    """In place: img *= scale * exp(-j (kx_c az + ky_c rg)) * exp(+j k_c q(x)), where
    q(x) = |x - p_c| - |p_c| + u_c . x is the wavefront curvature at the aperture centre p_c.
    Geometry and phase in float64 (reduced to cycles), sin/cos in float32."""
    nx, ny = img.shape
    rc = math.sqrt(pc[0] * pc[0] + pc[1] * pc[1] + pc[2] * pc[2])
    ux, uy, uz = pc[0] / rc, pc[1] / rc, pc[2] / rc
    inv2pi = 1.0 / (2.0 * math.pi)
    for i in prange(nx):
        for j in range(ny):
            X0 = az[i] * a[0] + rg[j] * r[0]
            X1 = az[i] * a[1] + rg[j] * r[1]
            X2 = az[i] * a[2] + rg[j] * r[2]
            d0, d1, d2 = X0 - pc[0], X1 - pc[1], X2 - pc[2]
            q = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) - rc + (X0 * ux + X1 * uy + X2 * uz)
            cyc = (k_c * q - kx_c * az[i] - ky_c * rg[j]) * inv2pi
            y = np.float32(cyc - np.float64(np.int64(cyc)))
            y = y - np.float32(np.int32(y + np.float32(0.5) * (np.float32(y >= 0) - np.float32(y < 0))))
            s, c = _sincos_cycles(y)
            v = img[i, j]
            re = v.real * c - v.imag * s
            im = v.real * s + v.imag * c
            img[i, j] = complex(re * scale, im * scale)


def pfa(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray,
        plane, az: np.ndarray, rg: np.ndarray, win_az, win_rg, half: int = 4,
        real_aperture: float = 0.0, cover: bool = True) -> tuple[np.ndarray, dict]:
    """Form a spotlight image with the polar format algorithm, never aliased.

    A grid smaller than the illuminated scene (:func:`illuminated_extent`) would fold the scene
    outside it back in, since the K-space samples are spaced for the grid's extent. With ``cover``
    the image is formed on axes of the same spacing that hold the whole scene
    (:func:`cover_axes`) and cropped to ``az`` x ``rg``; a cover larger than
    :data:`MAX_COVER_PIXELS` is refused with the numbers. See :func:`pfa_on_grid` for the other
    parameters.

    Parameters
    ----------
    ph : complex (P, M)
    freq : float64 (M,)
        Hz.
    positions : float64 (P, 3)
        m.
    ref_range : float64 (P,)
        m.
    plane : ImagePlane
    az, rg : float64
        Pixel axes, m.
    win_az, win_rg : callable
        ``w(n)`` windows.
    half : int
        Interpolation kernel half-width.
    real_aperture : float
        m (bounds the illuminated extent).
    cover : bool
        Form on the illuminated extent and crop.

    Returns
    -------
    (complex64 (az, rg), dict)
        Normalised image and its support figures.
    """
    info = {"cover_azimuth": az.size, "cover_range": rg.size}
    pw = plane_wave_error(freq, positions, plane, az, rg)
    info.update(pw)
    if pw["pfa_defocus_rad"] > PLANE_WAVE_PHASE_RAD or pw["pfa_distortion_px"] > PLANE_WAVE_SHIFT_PX:
        warnings.warn(f"processing.algorithm = pfa: the plane-wave model breaks on this grid: at its edges the "
                      f"wavefront curvature leaves {pw['pfa_defocus_rad']:.3g} rad of defocus (limit "
                      f"{PLANE_WAVE_PHASE_RAD:.3g}) and moves points by {pw['pfa_distortion_azimuth_m']:.3g} m in "
                      f"azimuth and {pw['pfa_distortion_range_m']:.3g} m in range, up to "
                      f"{pw['pfa_distortion_px']:.3g} pixels (limit {PLANE_WAVE_SHIFT_PX}); use bp or ffbp",
                      stacklevel=2)
    if not cover:
        img, inf = pfa_on_grid(ph, freq, positions, ref_range, plane, az, rg, win_az, win_rg, half)
        info.update(inf)
        return img, info
    ext = illuminated_extent(freq, positions, plane, real_aperture)
    az2, rg2, (i0, j0) = cover_axes(az, rg, ext)
    if az2.size * rg2.size > MAX_COVER_PIXELS:
        raise ScenarioError("processing.grid", f"{az.size} x {rg.size} pixels",
                            f"PFA must form {az2.size} x {rg2.size} pixels to hold the illuminated scene "
                            f"({ext['azimuth']:.4g} m x {ext['range']:.4g} m, limited by "
                            f"{ext['limited_by']['azimuth']}/{ext['limited_by']['range']}) and crop, more "
                            f"than {MAX_COVER_PIXELS} pixels; use --algorithm bp or a coarser grid")
    check_memory(24.0 * az2.size * rg2.size + 16.0 * ph.size, f"PFA on {az2.size} x {rg2.size} pixels (the "
                 f"{ext['azimuth']:.4g} m x {ext['range']:.4g} m illuminated scene at the grid's spacing)",
                 "use --algorithm bp or a coarser grid")
    img, inf = pfa_on_grid(ph, freq, positions, ref_range, plane, az2, rg2, win_az, win_rg, half)
    info.update(inf)
    info.update({"cover_azimuth": az2.size, "cover_range": rg2.size,
                 "illuminated_azimuth": ext["azimuth"], "illuminated_range": ext["range"]})
    return np.ascontiguousarray(img[i0:i0 + az.size, j0:j0 + rg.size]), info


def pfa_on_grid(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray,
                plane, az: np.ndarray, rg: np.ndarray, win_az, win_rg, half: int = 4) -> tuple[np.ndarray, dict]:
    """Form a spotlight image with the polar format algorithm on exactly ``az`` x ``rg``.

    The scene outside the grid folds in: use :func:`pfa` unless the grid holds the scene.

    Parameters
    ----------
    ph : complex (P, M)
        Phase history with uniform, increasing ``freq`` (Hz).
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre (origin), m.
    ref_range : float64 (P,)
        Reference range per pulse, m (re-referenced to |p| here if different).
    plane : ImagePlane
    az, rg : float64
        Pixel coordinates, m, uniform: az[i] = az_c + (i - nx//2) dx, likewise rg.
    win_az, win_rg : callable(n) -> ndarray
        Amplitude windows over the K-space support.
    half : int
        Half-width of the interpolation kernel, samples.

    Returns
    -------
    image : complex64 (nx, ny), normalised so a unit scatterer peaks near 1.
    info : dict
        K-space support sizes: samples (``support_azimuth``, ``support_range``) and the inscribed
        rectangle's extents, rad/m (``support_azimuth_extent``, ``support_range_extent``: the
        image's IRW is the window's factor times 2 pi over them).
    """
    c = SPEED_OF_LIGHT
    P, M = ph.shape
    nx, ny = az.size, rg.size
    dx, dy = az[1] - az[0], rg[1] - rg[0]
    az_c, rg_c = az[nx // 2], rg[ny // 2]
    rng_c = np.linalg.norm(positions, axis=1)
    if np.max(np.abs(ref_range - rng_c)) > 1e-9:  # re-reference to the scene centre
        corr = np.exp(-1j * 4 * np.pi * np.outer(ref_range - rng_c, freq) / c)
        data = (ph * corr).astype(np.complex64)
    else:
        data = np.ascontiguousarray(ph, dtype=np.complex64)
    u = positions / rng_c[:, None]
    ua = u @ plane.azimuth
    ur = u @ plane.range
    f0, df = freq[0], freq[1] - freq[0]
    kmin, kmax = 4 * np.pi * freq[0] / c, 4 * np.pi * freq[-1] / c
    # range (keystone) interpolation onto a common uniform ky grid
    ends = np.stack([kmin * ur, kmax * ur], axis=1)
    ky_lo, ky_hi = np.max(ends.min(axis=1)), np.min(ends.max(axis=1))
    dky = 2 * np.pi / (ny * dy)
    nky = min(int(np.floor((ky_hi - ky_lo) / dky)), ny)  # every sample inside the data
    if nky < 2:  # a wide aperture's annulus: its pulses' bands share no range frequencies
        a_lo, a_hi = float(np.abs(ur).min()), float(np.abs(ur).max())
        raise ScenarioError("processing.algorithm", "pfa",
                            f"the pulses' K-space samples share no band of range frequencies to form the image "
                            f"from (an inscribed rectangle of {max(nky, 0)} rows where the grid asks {ny}): their "
                            f"direction cosines along the range axis span {a_lo:.4g} to {a_hi:.4g} in size, a "
                            f"ratio of {a_hi / max(a_lo, 1e-300):.4g} where the band's frequencies span a ratio of "
                            f"{freq[-1] / freq[0]:.4g}; use --algorithm bp or ffbp, or a narrower aperture")
    ky_c = 0.5 * (ky_lo + ky_hi)
    ky = ky_c + (np.arange(nky) - nky // 2) * dky
    # input index of ky[j] on pulse n is linear in j: x0[n] + j * step[n]
    x0 = (ky[0] * c / (4 * np.pi * ur) - f0) / df
    step = dky * c / (4 * np.pi * ur) / df
    d1 = np.empty((P, nky), np.complex64)
    interp_rows_linear(data, x0, step, half, kernel_table(half), d1)
    # azimuth interpolation onto a uniform kx grid
    t = ua / ur  # kx = ky * t
    if t[-1] < t[0]:  # make pulses run with increasing t
        t, d1 = t[::-1], d1[::-1]
    if np.any(np.diff(t) <= 0):
        raise ValueError("PFA needs the look angle to change monotonically over the aperture")
    # P pulses span P intervals (as in direct backprojection): half an interval past each end
    t_ends = (t[0] - 0.5 * (t[1] - t[0]), t[-1] + 0.5 * (t[-1] - t[-2])) if P > 1 else (t[0], t[-1])
    kx_ends = np.stack([ky * t_ends[0], ky * t_ends[1]], axis=1)
    kx_lo, kx_hi = np.max(kx_ends.min(axis=1)), np.min(kx_ends.max(axis=1))
    dkx = 2 * np.pi / (nx * dx)
    nkx = min(int(np.floor((kx_hi - kx_lo) / dkx)), nx)
    kx_c = 0.5 * (kx_lo + kx_hi)
    kx = kx_c + (np.arange(nkx) - nkx // 2) * dkx
    w_a = np.asarray(win_az(nkx), np.float64)
    w_r = np.asarray(win_rg(nky), np.float64)
    # windows and the grid-centre ramps as two 1-D vectors; azimuth pass writes the FFT buffer
    v_a = (w_a * np.exp(-1j * (np.arange(nkx) - nkx // 2) * dkx * az_c)).astype(np.complex64)
    v_r = (w_r * np.exp(-1j * (np.arange(nky) - nky // 2) * dky * rg_c)).astype(np.complex64)
    buf = np.zeros((nx, ny), np.complex64)
    ia = ((np.arange(nkx) - nkx // 2) % nx).astype(np.int64)
    ir = ((np.arange(nky) - nky // 2) % ny).astype(np.int64)
    # fftshift of the output = (-1)^index on the input for even sizes: fold it into the vectors
    if nx % 2 == 0:
        v_a = v_a * np.where(ia % 2 == 0, 1, -1).astype(np.complex64)
    if ny % 2 == 0:
        v_r = v_r * np.where(ir % 2 == 0, 1, -1).astype(np.complex64)
    azimuth_pass(np.ascontiguousarray(d1.T), np.ascontiguousarray(t), kx, ky, v_a, v_r, half,
                 kernel_table(half), buf, ia, ir)
    img = sfft.fft2(buf, workers=WORKERS, overwrite_x=True)
    if nx % 2 or ny % 2:
        img = sfft.fftshift(img, axes=tuple(ax for ax, n in ((0, nx), (1, ny)) if n % 2))
    pc = positions[P // 2]
    _finalise(img, np.ascontiguousarray(az, np.float64), np.ascontiguousarray(rg, np.float64),
              plane.azimuth, plane.range, pc, kx_c, ky_c, 4 * np.pi * freq[M // 2] / c,
              np.float32(1.0 / (w_a.sum() * w_r.sum())))
    return img.astype(np.complex64, copy=False), {"support_azimuth": nkx, "support_range": nky,
                                                  "support_azimuth_extent": nkx * dkx, "support_range_extent": nky * dky}


def pfa_memory(sizes: Sizes) -> float:
    """Bytes the polar format algorithm adds: its formed (cover) grid and K-space buffer.

    Parameters
    ----------
    sizes : Sizes

    Returns
    -------
    float
    """
    return 24.0 * max(sizes.cover, sizes.nx * sizes.ny) + 8.0 * sizes.pulses * sizes.samples


@register_former(
    "pfa", summary="polar format: plane-wave model, K-space resampled onto an inscribed rectangle, FFT",
    modes=("spotlight",), tracks="any", phase_reference="aperture_centre", tiles=False, tile_overlap=0, blocks=None,
    memory=pfa_memory, support="rectangle",
    accuracy={"standard": Accuracy("8-tap Kaiser sinc resampling", None,
                                   "-27 dB at the seed geometries; warns where the wavefront curvature breaks it"),
              "high": Accuracy("as standard", None, "as standard")})
def form_pfa(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
             accuracy: str = "standard", progress=None) -> ImageResult:
    """Polar format image of a spotlight collection (the ``pfa`` former).

    Parameters
    ----------
    ph : PhaseHistory
        Spotlight collection.
    grid : ImageGrid
    window : Window
        Applied in azimuth and range.
    upsample : int
        Unused (PFA interpolates with 8-tap kernels).
    accuracy : {"standard", "high"}
        Not used.
    progress : callable, optional
        ``progress(done, total)``, called once at the end.

    Returns
    -------
    ImageResult

    Raises
    ------
    ScenarioError
        For stripmap data, or a cover grid too large (:func:`pfa`).
    """
    if ph.mode != "spotlight":
        raise ScenarioError("processing.algorithm", "pfa", form_pfa.spec.refusal(ph.mode, True))
    img, info = pfa(ph.data, ph.freq, ph.positions, ph.reference_range, grid.plane, grid.azimuth, grid.range,
                    window, window, real_aperture=ph.real_aperture)
    if progress:
        progress(ph.data.shape[0], ph.data.shape[0])
    return ImageResult(img, info)
