"""The truth former: the exact float64 matched filter, the reference every approximation is judged
against.

For every pixel x and pulse n, with dR = |x - p_n| - R_ref,n formed from small quantities
(:mod:`salkit.geometry.ranges`: exact at 560 km, where two float64 ranges differenced are not),

    I(x) = sum_n w_n sum_m v_m s(n, m) exp(+j 4 pi f_m dR / c) / (sum w)(sum v),

the same windows (w over the pulses, v over the frequencies) and normalisation as the ``bp``
former, and no interpolation: the sum over the uniform frequencies f_m = f_0 + m df is evaluated
by Horner's rule in z = exp(+j 4 pi df dR / c) in float64 (M complex multiply-adds a
pixel-pulse, error about M x 1e-16), then multiplied by exp(+j 4 pi f_0 dR / c). It costs
P x M x pixels: use it on small grids (``--algorithm exact`` is refused above
:data:`MAX_SECONDS` of estimated time, with the estimate).
"""
from __future__ import annotations

import math
import os

import numpy as np
from numba import get_num_threads, njit, prange

from ..errors import ScenarioError
from ..geometry.ranges import differential_range, range_offsets
from ..signals.windows import Window
from .formers import Accuracy, ImageGrid, ImageResult, Sizes, register_former
from .phasehistory import PhaseHistory
from ..tolerances import BP_UPSAMPLE

#: Longest estimated run the ``exact`` former accepts, s (environment ``SALKIT_EXACT_MAX_SECONDS``
#: overrides it).
MAX_SECONDS = 600.0
#: Complex multiply-adds a second per core of the Horner kernel, measured on a 2-core Zen 4 (AVX-512)
#: at 101^2 x 469 x 424: the basis of the time estimate (a slower machine takes longer than said).
RATE_PER_CORE = 1.5e9


@njit(parallel=True, cache=True, fastmath=False, error_model="numpy")
def _exact_kernel(s_re, s_im, f0, df, pos, ref, D, wa, row_origin, rdir, rg, out_re, out_im):
    nx = row_origin.shape[0]
    ny = rg.shape[0]
    P, M = s_re.shape
    k0 = 4.0 * math.pi / 299792458.0
    for i in prange(nx):
        acc_r = np.zeros(ny)
        acc_i = np.zeros(ny)
        zr = np.empty(ny)
        zi = np.empty(ny)
        br = np.empty(ny)
        bi = np.empty(ny)
        hr = np.empty(ny)
        hi = np.empty(ny)
        for n in range(P):
            w = wa[n]
            if w == 0.0:
                continue
            for j in range(ny):
                dR = differential_range(row_origin[i, 0] + rg[j] * rdir[0], row_origin[i, 1] + rg[j] * rdir[1],
                                        row_origin[i, 2] + rg[j] * rdir[2], pos[n, 0], pos[n, 1], pos[n, 2], ref[n],
                                        D[n])
                a = k0 * df * dR
                zr[j] = math.cos(a)
                zi[j] = math.sin(a)
                cyc = 2.0 * f0 * dR / 299792458.0
                b = 2.0 * math.pi * (cyc - np.floor(cyc))  # reduced in float64 before cos/sin
                br[j] = math.cos(b) * w
                bi[j] = math.sin(b) * w
                hr[j] = s_re[n, M - 1]
                hi[j] = s_im[n, M - 1]
            for m in range(M - 2, -1, -1):
                sr = s_re[n, m]
                si = s_im[n, m]
                for j in range(ny):
                    t = hr[j] * zr[j] - hi[j] * zi[j] + sr
                    hi[j] = hr[j] * zi[j] + hi[j] * zr[j] + si
                    hr[j] = t
            for j in range(ny):
                acc_r[j] += hr[j] * br[j] - hi[j] * bi[j]
                acc_i[j] += hr[j] * bi[j] + hi[j] * br[j]
        for j in range(ny):
            out_re[i, j] = acc_r[j]
            out_im[i, j] = acc_i[j]


def estimated_seconds(n_pulses: int, n_frequencies: int, n_pixels: int, cores: int | None = None) -> float:
    """Estimated run time of the exact former, s (at :data:`RATE_PER_CORE`).

    Parameters
    ----------
    n_pulses, n_frequencies, n_pixels : int
    cores : int, optional
        Default: the cores numba uses.

    Returns
    -------
    float
        s.

    Examples
    --------
    >>> round(estimated_seconds(469, 424, 101 * 101, cores=2), 1)
    0.7
    """
    if cores is None:
        cores = get_num_threads()
    return float(n_pulses) * n_frequencies * n_pixels / (RATE_PER_CORE * max(cores, 1))


def max_seconds() -> float:
    """The time limit of the ``exact`` former: ``SALKIT_EXACT_MAX_SECONDS`` or :data:`MAX_SECONDS`.

    Returns
    -------
    float
        s.

    Raises
    ------
    ScenarioError
        When the environment variable is not a number.
    """
    try:
        return float(os.environ.get("SALKIT_EXACT_MAX_SECONDS", MAX_SECONDS))
    except ValueError:
        raise ScenarioError("SALKIT_EXACT_MAX_SECONDS", os.environ["SALKIT_EXACT_MAX_SECONDS"],
                            "must be a number of seconds") from None


def exact_image(data: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray,
                row_origin: np.ndarray, rdir: np.ndarray, rg: np.ndarray, azimuth_window: np.ndarray | None = None,
                range_window: np.ndarray | None = None) -> np.ndarray:
    """The exact matched-filter image, complex128, normalised by the window sums.

    Parameters
    ----------
    data : complex (P, M)
        Phase history, exp(-j 4 pi f (R - R_ref) / c) per unit scatterer.
    freq : float64 (M,)
        Uniform, increasing frequencies, Hz.
    positions : float64 (P, 3)
        Antenna positions, m.
    ref_range : float64 (P,)
        Reference ranges, m.
    row_origin : float64 (nx, 3)
        Point of range coordinate 0 of each azimuth row, m.
    rdir : float64 (3,)
        Range axis (any vector: pixels are row_origin + rg rdir).
    rg : float64 (ny,)
        Range coordinates, m.
    azimuth_window : float (P,), optional
        Weights over the pulses (default 1).
    range_window : float (M,), optional
        Weights over the frequencies (default 1).

    Returns
    -------
    complex128 (nx, ny)
        A unit scatterer at a pixel gives 1 there.

    Examples
    --------
    >>> import numpy as np
    >>> from salkit.simulate.analytic import analytic_phase_history
    >>> pos = np.stack([np.linspace(-50, 50, 16), np.full(16, -1e3), np.full(16, 1e3)], axis=1)
    >>> f = 1e10 + 1e6 * np.arange(32)
    >>> s = analytic_phase_history(pos, np.linalg.norm(pos, axis=1), f, np.zeros((1, 3)))
    >>> img = exact_image(s, f, pos, np.linalg.norm(pos, axis=1), np.zeros((1, 3)), np.array([0.0, 1.0, 0.0]),
    ...                   np.array([0.0]))
    >>> bool(abs(img[0, 0] - 1) < 1e-9)
    True
    """
    P, M = data.shape
    f = np.asarray(freq, np.float64)
    wa = np.ones(P) if azimuth_window is None else np.asarray(azimuth_window, np.float64)
    wr = np.ones(M) if range_window is None else np.asarray(range_window, np.float64)
    s = np.asarray(data, np.complex128) * wr[None, :]
    nx, ny = row_origin.shape[0], np.asarray(rg).size
    out_re = np.empty((nx, ny))
    out_im = np.empty((nx, ny))
    _exact_kernel(np.ascontiguousarray(s.real), np.ascontiguousarray(s.imag), float(f[0]), float(f[1] - f[0]),
                  np.ascontiguousarray(positions, np.float64), np.ascontiguousarray(ref_range, np.float64),
                  range_offsets(positions, ref_range), wa,
                  np.ascontiguousarray(row_origin, np.float64), np.ascontiguousarray(rdir, np.float64),
                  np.ascontiguousarray(rg, np.float64), out_re, out_im)
    norm = max(float(wa.sum()), 1e-300) * float(wr.sum())
    return (out_re + 1j * out_im) / norm


def exact_memory(sizes: Sizes) -> float:
    """Bytes the exact matched filter adds: its float64 accumulators (16 bytes a pixel).

    Parameters
    ----------
    sizes : Sizes

    Returns
    -------
    float
    """
    return 16.0 * sizes.nx * sizes.ny


@register_former(
    "exact", summary="the exact float64 matched filter, any trajectory (the truth; small grids)",
    modes=("spotlight",), tracks="any", phase_reference="aperture_centre", tiles=False, tile_overlap=0, blocks=None,
    memory=exact_memory,
    accuracy={"standard": Accuracy("float64, nothing interpolated", None, "the truth the others are judged against"),
              "high": Accuracy("as standard", None, "as standard")})
def form_exact(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
               accuracy: str = "standard", progress=None) -> ImageResult:
    """The exact float64 matched filter (the ``exact`` former), normalised as ``bp``.

    Parameters
    ----------
    ph : PhaseHistory
        Spotlight collection, any trajectory.
    grid : ImageGrid
    window : Window
        Over the pulses and the frequencies.
    upsample : int
        Not used (nothing is interpolated).
    accuracy : {"standard", "high"}
        Not used (exact).
    progress : callable, optional
        ``progress(done, total)`` in pulses (called once, at the end).

    Returns
    -------
    ImageResult
        complex64 image (computed in float64).

    Raises
    ------
    ScenarioError
        For stripmap data (its beam equalisation is ``bp``'s), or an estimated time above
        :func:`max_seconds`.
    """
    if ph.beam_limited:
        raise ScenarioError("processing.algorithm", "exact", form_exact.spec.refusal("stripmap", True))
    P, M = ph.data.shape
    nx, ny = grid.shape
    est = estimated_seconds(P, M, nx * ny)
    limit = max_seconds()
    if est > limit:
        raise ScenarioError("processing.algorithm", "exact",
                            f"{P} pulses x {M} frequencies x {nx} x {ny} pixels would take about {est:.0f} s "
                            f"(limit {limit:.0f} s, SALKIT_EXACT_MAX_SECONDS): use a smaller grid or bp")
    az = grid.azimuth
    row_origin = grid.plane.points(az, np.zeros_like(az))
    img = exact_image(ph.data, ph.freq, ph.positions, ph.reference_range, row_origin, grid.plane.range,
                      grid.range, window(P), window(M))
    if progress is not None:
        progress(P, P)
    return ImageResult(img.astype(np.complex64), {"support_azimuth": P, "support_range": M})
