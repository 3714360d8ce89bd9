"""The figures' canvas: matplotlib on the Agg backend, constrained-layout axes, atomic PNG saves,
log-log ticks, and intensities in dB against a reference."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np

from ..io.reading import blocks
from ..io.writing import atomic_path

PREVIEW_PIXELS = 512  # an image figure shows at most this many pixels a side (about what its PNG shows)


def _subplots(*args, **kwargs):
    """``plt.subplots`` with constrained layout: titles, labels and colourbars never overlap."""
    kwargs.setdefault("layout", "constrained")
    return plt.subplots(*args, **kwargs)


SAVE_DPI = 110  # the figures' resolution, dots per inch


def _save(fig, path: str | Path) -> Path:
    """Save ``fig`` as a PNG (atomically) and close it. The constrained layout is computed once, at
    the saving resolution, and frozen before saving: ``savefig`` with a layout engine draws the
    figure twice and lays it out each time, and the layout (text extents of every tick label) was
    half of a figure's 1.3 s, 40 % of ``make demo``'s time. The layout engine runs on its own, not
    inside a draw: a draw would also resample every image once more (the same PNG, 12 % less time)."""
    try:
        with atomic_path(path, suffix=".png") as tmp:
            engine = fig.get_layout_engine()
            if engine is not None:
                fig.set_dpi(SAVE_DPI)
                engine.execute(fig)  # lays the figure out (text extents at the saving resolution)
                fig.set_layout_engine(None)  # keeps those positions: savefig draws once
            fig.savefig(tmp, dpi=SAVE_DPI)
    finally:
        plt.close(fig)
    return Path(path)


def _log_ticks(ax) -> None:
    """1-2-5 ticks with plain numbers on a log-log axes (no run-together 2x10^0 labels)."""
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(matplotlib.ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        axis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def _db(img, ref):
    """Magnitude of ``img`` in dB against the amplitude ``ref``, floored at -80 dB."""
    a = np.abs(img) / max(ref, 1e-30)
    return 20 * np.log10(np.maximum(a, 1e-4))


def preview_step(shape, max_pixels: int = PREVIEW_PIXELS) -> int:
    """The side k of the k x k pixel blocks an image of ``shape`` is shown in (1: every pixel).

    Parameters
    ----------
    shape : tuple of int
    max_pixels : int
        Most pixels shown a side.

    Returns
    -------
    int
    """
    return max(1, -(-max(shape) // max_pixels))


def peak_magnitude(image, max_pixels: int = PREVIEW_PIXELS) -> tuple[np.ndarray, int]:
    """|image| for a figure: the brightest pixel of each k x k block, at most ``max_pixels`` a side,
    read k rows at a time (an image in memory or opened lazily; bounded memory at any size). A point
    target keeps its peak, as every k-th pixel would not.

    Parameters
    ----------
    image : complex array-like (nx, ny)
    max_pixels : int

    Returns
    -------
    (ndarray float32, int)
        The magnitudes and k.

    Examples
    --------
    >>> m, k = peak_magnitude(np.arange(16.0).reshape(4, 4), max_pixels=2)
    >>> k, m.tolist()
    (2, [[5.0, 7.0], [13.0, 15.0]])
    """
    nx, ny = image.shape
    k = preview_step((nx, ny), max_pixels)
    if k == 1:
        return np.abs(np.asarray(image)).astype(np.float32), 1
    mx, my = -(-nx // k), -(-ny // k)
    out = np.zeros((mx, my), np.float32)
    for a, b, big in blocks(image, multiple=k):
        w = -(-big.shape[1] // k)
        for c in range(0, big.shape[0], k):
            blk = np.abs(big[c:c + k]).astype(np.float32)
            pad = w * k - blk.shape[1]
            if pad:
                blk = np.pad(blk, ((0, 0), (0, pad)))
            out[(a + c) // k, b // k:b // k + w] = blk.reshape(blk.shape[0], w, k).max(axis=(0, 2))
    return out, k
