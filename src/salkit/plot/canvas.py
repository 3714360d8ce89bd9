"""The figures' canvas: matplotlib on the Agg backend, constrained-layout axes, atomic PNG saves,
log-log ticks, and intensities in dB against a reference."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np

from ..io.datasets import atomic_path


def _subplots(*args, **kwargs):
    """``plt.subplots`` with constrained layout: titles, labels and colourbars never overlap."""
    kwargs.setdefault("layout", "constrained")
    return plt.subplots(*args, **kwargs)


def _save(fig, path: str | Path) -> Path:
    try:
        with atomic_path(path, suffix=".png") as tmp:
            fig.savefig(tmp, dpi=110, bbox_inches="tight")
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
