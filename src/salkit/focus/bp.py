"""Backprojection formers: ``bp`` and its variants, time-domain backprojection for any trajectory.

Spotlight collections are backprojected pulse by pulse by the kernel
(:func:`salkit.focus.bp_kernel.backproject`) with the window over the pulses and the range
samples, the pulses in blocks when a job is cut to fit memory (:mod:`salkit.focus.tiles`);
stripmap collections use full-beam backprojection with Doppler-domain beam equalisation
(:func:`salkit.focus.stripmap_bp.stripmap_backprojection`), which keeps the response
shift-invariant. The interpolation that reads the range profiles between bins is a parameter
(:data:`salkit.focus.profiles.INTERPOLATIONS`): :func:`backprojection_former` makes the former of
one interpolation, so a variant is one declaration::

    form, blocks = backprojection_former("nearest")
    register_former("bp_nearest", form=..., blocks=blocks, ...)(form)
"""
from __future__ import annotations

import numpy as np

from ..signals.windows import Window
from ..tolerances import BP_DEFAULT_HIGH_UPSAMPLE, BP_DEFAULT_UPSAMPLE, BP_UPSAMPLE
from .bp_kernel import backproject, profile_block
from .formers import Accuracy, ImageGrid, ImageResult, Sizes, register_former
from .phasehistory import PhaseHistory
from .profiles import interpolation_of, profile_length
from .stripmap_bp import stripmap_backprojection


class _Whole:
    """A phase history in memory as a source of one block of pulses (all of them)."""

    def __init__(self, ph: PhaseHistory):
        self.ph = ph
        self.n_pulses = ph.data.shape[0]

    def block(self, a: int, b: int) -> PhaseHistory:
        return self.ph


def spotlight_backprojection(pulses, grid: ImageGrid, window: Window, ranges, *, upsample: int = BP_UPSAMPLE,
                             interpolation: str = "linear", progress=None) -> np.ndarray:
    """Spotlight backprojection of ``grid``, the pulses a block at a time into one pair of float32
    accumulators, normalised by the window sums (a unit point at the beam centre peaks near 1).

    Parameters
    ----------
    pulses : object
        ``n_pulses`` and ``block(a, b) -> PhaseHistory`` (:class:`salkit.focus.tiles.InMemoryPulses`,
        :class:`salkit.focus.tiles.DatasetPulses`).
    grid : ImageGrid
    window : Window
        Over all the pulses and over the range samples.
    ranges : list of (int, int)
        The pulse blocks, in order (any lengths: each pixel sums its pulses in order).
    upsample : int
        Range-profile upsampling.
    interpolation : {"linear", "nearest", "cubic", "fitted"}
        How the profiles are read between bins.
    progress : callable, optional
        ``progress(done, total)`` in pulses (one block).

    Returns
    -------
    complex64 (nx, ny)
    """
    interpolation_of(interpolation)
    P = pulses.n_pulses
    nx, ny = grid.shape
    wa = window(P).astype(np.float32)
    re, im = np.zeros((nx, ny), np.float32), np.zeros((nx, ny), np.float32)
    row_origin = grid.plane.points(grid.azimuth, np.zeros_like(grid.azimuth))
    wr = None
    for a, b in ranges:
        ph = pulses.block(a, b)
        if wr is None:
            wr = window(ph.freq.size)
        W = np.broadcast_to(wa[None, a:b], (nx, b - a))
        backproject(ph.data, ph.freq, ph.positions, ph.reference_range, row_origin, grid.plane.range, grid.range,
                    W, wr, upsample=upsample, out=(re, im), interpolation=interpolation,
                    progress=progress if len(ranges) == 1 else None)
    norm = np.maximum(np.broadcast_to(wa[None, :], (nx, P)).sum(axis=1), 1e-30) * wr.sum()
    scale = (1.0 / norm).astype(np.float32)[:, None]
    img = np.empty((nx, ny), np.complex64)  # no complex128 temporaries: 8 bytes a pixel beside the sums
    np.multiply(re, scale, out=img.real)
    np.multiply(im, scale, out=img.imag)
    return img


def backprojection_former(interpolation: str, default_upsample: int = BP_UPSAMPLE):
    """The former, and the pulse-block former, of backprojection whose profiles are read by
    ``interpolation``.

    Parameters
    ----------
    interpolation : {"linear", "nearest", "cubic", "fitted"}
    default_upsample : int
        The former's ``upsample`` when it is called without one (the pipeline always passes one:
        :func:`salkit.focus.pipeline.range_upsample`).

    Returns
    -------
    (callable, callable)
        ``form(ph, grid, window, *, upsample, accuracy, progress) -> ImageResult`` and
        ``blocks(pulses, grid, window, ranges, upsample, accuracy) -> (image, info)`` (the
        declaration's ``blocks``).
    """
    interpolation_of(interpolation)

    def form(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = default_upsample,
             accuracy: str = "standard", progress=None) -> ImageResult:
        """Backprojection image.

        Parameters
        ----------
        ph : PhaseHistory
        grid : ImageGrid
        window : Window
            Over the pulses (spotlight) or the Doppler band (stripmap), and in range.
        upsample : int
            Range-profile upsampling before the profiles are interpolated (their mean response
            divided out, :mod:`salkit.focus.profiles`).
        accuracy : {"standard", "high"}
            Not used: backprojection takes its accuracy from ``upsample`` (the pipeline passes the
            former's declared upsampling for the level, :func:`salkit.focus.pipeline.range_upsample`).
        progress : callable, optional
            ``progress(done, total)`` in pulses.

        Returns
        -------
        ImageResult
            Normalised by the window sums, so that a unit point at the beam centre peaks near 1.
        """
        P, M = ph.data.shape
        info = {"support_azimuth": P, "support_range": M}
        if ph.beam_limited:
            img = stripmap_backprojection(ph, grid.plane, grid.azimuth, grid.range, window, upsample=upsample,
                                          progress=progress, interpolation=interpolation)
            return ImageResult(img, info)
        return ImageResult(spotlight_backprojection(_Whole(ph), grid, window, [(0, P)], upsample=upsample,
                                                    interpolation=interpolation, progress=progress), info)

    def blocks(pulses, grid: ImageGrid, window: Window, ranges, upsample: int, accuracy: str):
        """A spotlight tile backprojected a block of pulses at a time (:func:`spotlight_backprojection`).

        Parameters
        ----------
        pulses : object
            ``n_pulses``, ``probe`` and ``block(a, b)``.
        grid : ImageGrid
        window : Window
        ranges : list of (int, int)
        upsample : int
        accuracy : str
            Not used.

        Returns
        -------
        (complex64 ndarray, dict)
        """
        img = spotlight_backprojection(pulses, grid, window, ranges, upsample=upsample, interpolation=interpolation)
        return img, {"support_azimuth": pulses.n_pulses, "support_range": pulses.probe.freq.size}

    return form, blocks


def bp_memory(sizes: Sizes) -> float:
    """Bytes backprojection adds: one kernel call's upsampled range profiles (its pulses
    :func:`salkit.focus.bp_kernel.profile_block`, or the block's if fewer) at the sizes' upsampling,
    16 bytes a bin: the complex64 buffer every block of the call is transformed into in place, in
    the layout the kernel reads (:func:`salkit.focus.profiles.range_profiles_into`), counted twice
    (until 0.29.2 the four-tap kernels read a padded copy; the second half is now margin).

    Parameters
    ----------
    sizes : Sizes

    Returns
    -------
    float
    """
    up = max(int(sizes.upsample), 1)
    pulses = min(profile_block(sizes.samples, up), max(int(sizes.pulses), 1))  # a block of fewer takes fewer
    return pulses * 16.0 * profile_length(sizes.samples, up)


_form_default, _blocks_default = backprojection_former("fitted", BP_DEFAULT_UPSAMPLE)

#: The ``bp`` former, the default: backprojection, its profiles upsampled 6x (8x at ``accuracy:
#: high``) and read by four taps fitted to the profile's band (``bp_fitted``'s kernel at its fastest
#: settings that hold -85 dB). Until 0.19.0 ``bp`` read 16x profiles by linear interpolation: -65 dB,
#: slower, its kernel reading 2.7 times the bytes (linear interpolation stays in the library:
#: :func:`salkit.focus.bp_kernel.backproject` ``interpolation="linear"``).
form_bp = register_former(
    "bp", summary=f"backprojection, any trajectory (the default): range profiles upsampled {BP_DEFAULT_UPSAMPLE}x "
    "and read by four taps fitted to the profile's band",
    modes=("spotlight", "stripmap"), tracks="any", phase_reference="aperture_centre", tiles=True, tile_overlap=0,
    blocks=_blocks_default, memory=bp_memory,
    accuracy={"standard": Accuracy(f"{BP_DEFAULT_UPSAMPLE}x profiles, fitted taps", -80.0,
                                   "-87.1 to -89.2 dB measured"),
              "high": Accuracy(f"{BP_DEFAULT_HIGH_UPSAMPLE}x profiles, fitted taps", -90.0,
                               "-97.5 to -99.9 dB measured; for interferometry")},
    upsample={"standard": BP_DEFAULT_UPSAMPLE, "high": BP_DEFAULT_HIGH_UPSAMPLE},
)(_form_default)


_form_cubic, _blocks_cubic = backprojection_former("cubic")

#: The ``bp_cubic`` former: backprojection, its profiles read by Keys' cubic convolution (four bins,
#: its mean response divided out): 20 to 25 dB closer to the truth than linear interpolation at the
#: same upsampling, 15 to 25 dB further from it than the fitted taps.
form_bp_cubic = register_former(
    "bp_cubic", summary="backprojection, any trajectory: range profiles upsampled and read by Keys cubic convolution",
    modes=("spotlight", "stripmap"), tracks="any", phase_reference="aperture_centre", tiles=True, tile_overlap=0,
    blocks=_blocks_cubic, memory=bp_memory,
    accuracy={"standard": Accuracy(f"{BP_UPSAMPLE}x profiles", -85.0, "-89 to -95 dB measured"),
              "high": Accuracy("32x profiles", -100.0, "-106 to -108.7 dB measured")})(_form_cubic)


_form_fitted, _blocks_fitted = backprojection_former("fitted")

#: The ``bp_fitted`` former: ``bp``'s kernel at 16x profiles (32x at ``accuracy: high``), four taps
#: whose weights (cubics in the fraction) are fitted by least squares to the band the profile occupies
#: (:func:`salkit.focus.profiles.fitted_coefficients`): at the cost of ``bp_cubic`` (the kernel's time
#: hardly depends on the upsampling), -74 dB at 4x upsampling, -87 to -89 dB at 6x, -97 to -99 dB at 8x,
#: -110 to -113.5 dB at 16x on the accuracy tests' geometries (X band to 560 km at 1.55 um).
form_bp_fitted = register_former(
    "bp_fitted", summary="backprojection, any trajectory: range profiles upsampled and read by four taps fitted "
    "to the profile's band",
    modes=("spotlight", "stripmap"), tracks="any", phase_reference="aperture_centre", tiles=True, tile_overlap=0,
    blocks=_blocks_fitted, memory=bp_memory,
    accuracy={"standard": Accuracy(f"{BP_UPSAMPLE}x profiles", -105.0, "-110.2 to -113.5 dB measured"),
              "high": Accuracy("32x profiles", -105.0, "-110.4 to -113.7 dB measured: the float32 profiles and sums, "
                               "not the interpolation, bound it")})(_form_fitted)
