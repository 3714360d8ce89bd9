"""The ``bp`` former: time-domain backprojection for any trajectory.

Spotlight collections are backprojected pulse by pulse (:func:`.backprojection.backproject`) with
the window over the pulses and the range samples; stripmap collections use full-beam
backprojection with Doppler-domain beam equalisation
(:func:`.stripmap_bp.stripmap_backprojection`), which keeps the response shift-invariant.
"""
from __future__ import annotations

import numpy as np

from ..signals.windows import Window
from .backprojection import backproject
from .formers import ImageGrid, ImageResult, register_former
from .phasehistory import PhaseHistory
from .stripmap_bp import stripmap_backprojection
from ..tolerances import BP_UPSAMPLE


@register_former("bp")
def form_bp(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
            accuracy: str = "standard", progress=None) -> ImageResult:
    """Backprojection image (the registered ``bp`` former).

    Parameters
    ----------
    ph : PhaseHistory
    grid : ImageGrid
    window : Window
        Over the pulses (spotlight) or the Doppler band (stripmap), and in range.
    upsample : int
        Range-profile upsampling before the kernel's linear interpolation of the profiles (its
        error compensated, :mod:`salkit.focus.backprojection`).
    accuracy : {"standard", "high"}
        Not used: ``bp`` takes its accuracy from ``upsample`` (the caller passes 32 for "high").
    progress : callable, optional
        ``progress(done, total)`` in pulses.

    Returns
    -------
    ImageResult
        Normalised by the window sums, so that a unit point at the beam centre peaks near 1.
    """
    P, M = ph.data.shape
    info = {"support_azimuth": P, "support_range": M}
    if ph.mode == "stripmap" and ph.real_aperture > 0:
        img = stripmap_backprojection(ph, grid.plane, grid.azimuth, grid.range, window, upsample=upsample,
                                      progress=progress)
        return ImageResult(img, info)
    az = grid.azimuth
    W = np.broadcast_to(window(P).astype(np.float32)[None, :], (az.size, P))
    wr = window(M)
    row_origin = grid.plane.points(az, np.zeros_like(az))
    img = backproject(ph.data, ph.freq, ph.positions, ph.reference_range, row_origin, grid.plane.range,
                      grid.range, W, wr, upsample=upsample, progress=progress)
    norm = np.maximum(W.sum(axis=1), 1e-30) * wr.sum()
    return ImageResult((img / norm[:, None]).astype(np.complex64), info)
