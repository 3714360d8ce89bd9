"""Figures of the chirp study (seed 002): Table 3's grids as heat maps."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.ticker
import numpy as np

from .canvas import _save, _subplots


def sweep_heatmaps(rows, cols, grids, irws, out, labels) -> Path:
    """Compression ratio (colour, log) and IRW/ideal per method over a two-parameter sweep.

    Parameters
    ----------
    rows, cols : sequence of float
    grids, irws : dict
        Method -> (rows, cols) compression ratio and IRW (m).
    out : path
    labels : (str, str)
        Row and column axis labels.

    Returns
    -------
    Path
    """
    meths = [m for m in grids if m != "none"]
    fig, axes = _subplots(2, len(meths), figsize=(3.6 * len(meths), 7.0), squeeze=False)
    for j, m in enumerate(meths):
        for i, (data, t, kw) in enumerate(((grids[m], "compression ratio", {"norm": matplotlib.colors.LogNorm(0.5, 100)}),
                                          (irws[m] / irws["ideal"], "IRW / ideal", {"vmin": 0.9, "vmax": 3}))):
            ax = axes[i, j]
            ax.set_facecolor("0.85")
            ax.patch.set_hatch("xx")
            ax.patch.set_edgecolor("0.6")
            im = ax.imshow(np.ma.masked_invalid(data), origin="lower", aspect="auto", cmap="viridis", **kw)
            ax.set_xticks(range(len(cols)), [f"{c:g}" for c in cols], fontsize=8, rotation=90)
            ax.set_yticks(range(len(rows)), [f"{r:g}" for r in rows], fontsize=8)
            ax.set_title(f"{m}: {t}", fontsize=9)
            ax.set_xlabel(labels[1], fontsize=9)
            ax.set_ylabel(labels[0], fontsize=9)
            fig.colorbar(im, ax=ax)
    if any(np.isnan(np.asarray(g, float)).any() for g in grids.values()):
        fig.suptitle("hatched cells: no result where d_r = d_rlo (a zero-length reference: its beat is zero "
                     "and carries no chirp error)", fontsize=9)
    return _save(fig, out)
