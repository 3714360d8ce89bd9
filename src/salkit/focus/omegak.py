"""Omega-k (wavenumber-domain) image formation for stripmap on a straight track.

With D(u, f) = exp(-j 2K (R(u) - R_0)), K = 2 pi f / c, a scatterer at along-track x_t and
closest-approach range R_t transforms (stationary phase) to exp(-j k_u x_t - j k_y R_t + j 2K R_0),
k_y = sqrt(4K^2 - k_u^2). Multiplying by exp(j k_y R_s - j 2K R_0) (the reference function at the
scene-centre range R_s) and resampling each k_u line onto a uniform k_y grid (Stolt) leaves
exp(-j k_u x_t - j k_y (R_t - R_s)); a 2-D inverse transform focuses it exactly, with no
approximation in range curvature. The processed Doppler band is the two-way 3 dB beam, equalised
by the beam pattern so the impulse response is the window's.
"""
from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from ..constants import FFT_WORKERS, SPEED_OF_LIGHT
from ..errors import ScenarioError
from ..geometry.collection import beam_gain, beam_gain_table, two_way_3db_sin
from ..signals.windows import Window
from .formers import Accuracy, ImageGrid, ImageResult, Sizes, register_former
from .interp import resample_rows
from .phasehistory import PhaseHistory
from ..tolerances import BP_UPSAMPLE

WORKERS = FFT_WORKERS


def omegak(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray, plane,
           az: np.ndarray, rg: np.ndarray, track: np.ndarray, center_position: np.ndarray,
           beam_table, beam_dsin: float, band_sin: float, win_az, win_rg,
           half: int = 4) -> tuple[np.ndarray, dict]:
    """Form a stripmap image with the omega-k algorithm.

    Parameters
    ----------
    ph : complex (P, M)
        Phase history, increasing uniform ``freq`` (Hz), pulses uniformly spaced along ``track``.
    positions : float64 (P, 3)
        Antenna positions relative to the scene centre, m.
    ref_range : float64 (P,)
        Reference range per pulse, m.
    plane : ImagePlane
    az, rg : float64
        Pixel coordinates in the plane, m.
    track : (3,) unit vector; center_position : (3,) aperture centre, m.
    beam_table, beam_dsin :
        Two-way amplitude pattern table (see :func:`beam_gain_table`).
    band_sin : float
        sin of the half-angle of the processed Doppler band.
    win_az, win_rg : callable(n) -> ndarray
    half : int
        Stolt interpolation kernel half-width.

    Returns
    -------
    image : complex64 (nx, ny), normalised so a unit scatterer peaks near 1.
    info : dict
    """
    c = SPEED_OF_LIGHT
    P, M = ph.shape
    R0 = float(np.mean(ref_range))
    data = ph * np.exp(-1j * 4 * np.pi * np.outer(ref_range - R0, freq) / c)
    u = positions @ track
    du = float(np.mean(np.diff(u)))
    if np.max(np.abs(np.diff(u) - du)) > 1e-3 * abs(du):
        raise ValueError("omega-k needs uniformly spaced pulses along a straight track")
    # perpendicular distance of the scene centre from the track line
    pc = center_position
    perp = -pc - np.dot(-pc, track) * track
    Rs = float(np.linalg.norm(perp))
    Kc = 2 * np.pi * freq[M // 2] / c
    rel = -pc  # aperture centre -> scene centre
    kuc = 2 * Kc * np.dot(rel, track) / np.linalg.norm(rel)
    # zero-pad slow time so the periodic image replica (period n_u * du) lies beyond the grid
    x_ext = float(np.ptp(az)) + 2 * abs(du)
    n_u = sfft.next_fast_len(P + int(np.ceil(x_ext / abs(du))))
    S = sfft.fft(data.astype(np.complex64), n=n_u, axis=0, workers=WORKERS)
    ku_raw = 2 * np.pi * sfft.fftfreq(n_u, du)
    span = 2 * np.pi / abs(du)
    ku = kuc + np.mod(ku_raw - kuc + span / 2, span) - span / 2
    S *= np.exp(-1j * ku * u[0])[:, None].astype(np.complex64)
    # processed Doppler band and beam equalisation
    half_band = 2 * Kc * band_sin
    sel = np.abs(ku - kuc) <= half_band
    order = np.argsort(ku[sel])
    ku_s = ku[sel][order]
    S = S[sel][order]
    K = 2 * np.pi * freq / c
    S *= np.exp(-1j * 2 * K[None, :] * R0).astype(np.complex64)
    # Stolt mapping onto a uniform ky grid over the common support
    ky_lo = np.sqrt(4 * K[0] ** 2 - np.min(ku_s ** 2))
    ky_hi = np.sqrt(4 * K[-1] ** 2 - np.max(ku_s ** 2))
    nky = M
    ky = np.linspace(ky_lo, ky_hi, nky)
    fneed = c * np.sqrt(ky[None, :] ** 2 + ku_s[:, None] ** 2) / (4 * np.pi)
    fpos = (fneed - freq[0]) / (freq[1] - freq[0])
    # reference function at Rs, applied on the original K grid before Stolt:
    # exp(j ky Rs) with ky = sqrt(4K^2 - ku^2)
    kyK = np.sqrt(np.maximum(4 * K[None, :] ** 2 - ku_s[:, None] ** 2, 0.0))
    S *= np.exp(1j * kyK * Rs).astype(np.complex64)
    D = resample_rows(S, fpos, half=half)  # (nku, nky)
    sin_off = (ku_s - kuc) / (2 * Kc)
    g = beam_gain(beam_table, beam_dsin, sin_off)
    w_a = np.asarray(win_az(ku_s.size), np.float64) / np.maximum(g, 1e-3)
    w_r = np.asarray(win_rg(nky), np.float64)
    D = D * w_a[:, None] * w_r[None, :]
    # separable inverse transforms onto the requested plane coordinates
    X = plane.points(az[:, None], rg[None, :])
    x_pix = X[:, 0, :] @ track
    Xr = X[0] - pc
    dist = np.linalg.norm(Xr - (Xr @ track)[:, None] * track[None, :], axis=1)
    rho = dist - Rs
    Ex = np.exp(1j * np.outer(x_pix, ku_s))  # (nx, nku)
    Ey = np.exp(1j * np.outer(ky, rho))  # (nky, ny)
    img = (Ex @ D.astype(np.complex128)) @ Ey
    # stationary-phase gain and phase of the azimuth transform: sqrt(pi Rs / Kc) / du, exp(-j pi/4)
    gain = np.sum(np.asarray(win_az(ku_s.size))) * np.sum(w_r) * np.sqrt(np.pi * Rs / Kc) / abs(du)
    img *= np.exp(1j * np.pi / 4) / gain
    return img.astype(np.complex64), {"support_azimuth": int(ku_s.size), "support_range": nky,
                                      "reference_range_scene": Rs}


def omegak_memory(sizes: Sizes) -> float:
    """Bytes omega-k adds: its Stolt-interpolated spectrum.

    Parameters
    ----------
    sizes : Sizes

    Returns
    -------
    float
    """
    return 4 * 8.0 * sizes.pulses * sizes.samples + 16.0 * sizes.nx * sizes.ny


@register_former(
    "omegak", summary="omega-k (wavenumber domain): Stolt interpolation, beam equalised",
    modes=("stripmap",), tracks="straight", phase_reference="track", tiles=False, tile_overlap=0, blocks=None,
    memory=omegak_memory,
    accuracy={"standard": Accuracy("8-tap Kaiser sinc Stolt interpolation", None,
                                   "the exact former is spotlight's; judged by its IPR against theory"),
              "high": Accuracy("as standard", None, "as standard")})
def form_omegak(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
                accuracy: str = "standard", progress=None) -> ImageResult:
    """Omega-k image of a stripmap collection on a straight track (the ``omegak`` former).

    Parameters
    ----------
    ph : PhaseHistory
        Stripmap collection with a known ``real_aperture``.
    grid : ImageGrid
    window : Window
        Applied over the processed Doppler band and in range.
    upsample : int
        Unused.
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
        For spotlight data or an unknown aperture.
    """
    if ph.mode != "stripmap":
        raise ScenarioError("processing.algorithm", "omegak", form_omegak.spec.refusal(ph.mode, True))
    if ph.real_aperture <= 0:
        raise ScenarioError("processing.algorithm", "omegak", "omega-k equalises the beam: it needs the telescope's "
                            f"real_aperture (the data give {ph.real_aperture!r})")
    table, dsin = beam_gain_table(ph.wavelength, ph.real_aperture)
    img, info = omegak(ph.data, ph.freq, ph.positions, ph.reference_range, grid.plane, grid.azimuth, grid.range,
                       ph.track, ph.center_position, table, dsin, two_way_3db_sin(ph.wavelength, ph.real_aperture),
                       window, window)
    if progress:
        progress(ph.data.shape[0], ph.data.shape[0])
    return ImageResult(img, info)
