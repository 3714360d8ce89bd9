"""Figures of studies: the chirp study's grids as heat maps (seed 002), a sweep's metric against its
varied fields (median, 5-95 % band, theory)."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.ticker
import numpy as np

from ..units import theory_name
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


def sweep_figure(ds, metric: str, path) -> Path:
    """A sweep's metric against its first varied field: the median over the realisations with the
    5-95 % band, one line per value of the second varied field, its theory dashed where the sweep
    holds one (an ensemble expectation: the mean over the realisations is drawn beside it, dotted),
    a log axis for a log sweep.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep (:func:`salkit.sweep`), not zipped.
    metric : str
        A variable of ``ds``.
    path : path
        PNG to write.

    Returns
    -------
    Path
    """
    dims = [d for d in ds[metric].dims if d != "realisation"]
    x = ds[dims[0]]
    fig, ax = _subplots(figsize=(6.4, 4.2))
    second = dims[1] if len(dims) > 1 else None
    groups = [(None, ds)] if second is None else [(v, ds.sel({second: v})) for v in ds[second].values]
    for gi, (v, sub) in enumerate(groups):
        a = sub[metric]
        other = [d for d in a.dims if d not in (dims[0], "realisation")]
        if other:  # a third axis and beyond: their first value
            a = a.isel({d: 0 for d in other})
        med = a.median("realisation", skipna=True)
        name = second.split(".")[-1] if second else ""
        label = "measured" if v is None else (f"{name} = {v:g}" if isinstance(v, (int, float, np.number))
                                               else f"{name} = {v}")
        line, = ax.plot(x.values, med.values, "o-", label=label)
        if a.sizes["realisation"] > 1:
            lo, hi = a.quantile(0.05, "realisation", skipna=True), a.quantile(0.95, "realisation", skipna=True)
            ax.fill_between(x.values, lo.values, hi.values, color=line.get_color(), alpha=0.2, lw=0)
        t = metric_theory(sub, metric)
        if t is not None:
            if other:
                t = t.isel({d: 0 for d in other if d in t.dims})
            ax.plot(x.values, t.median("realisation", skipna=True).values, "--", color=line.get_color(),
                    label="theory (dashed)" if gi == 0 else None)
            if a.sizes["realisation"] > 1:  # theories are ensemble expectations: the mean beside them
                ax.plot(x.values, a.mean("realisation", skipna=True).values, "x:", color=line.get_color(),
                        label="mean (dotted)" if gi == 0 else None)
    if x.attrs.get("scale") == "log":
        ax.set_xscale("log")
    unit = ds[metric].attrs.get("units", "1")
    xunit = x.attrs.get("units", "1")
    ax.set_xlabel(f"{dims[0]}" + (f" ({xunit})" if xunit not in ("", "1") else ""))
    ax.set_ylabel(metric + (f" ({unit})" if unit not in ("", "1") else ""))
    band = " (median, 5-95 % band)" if ds.sizes["realisation"] > 1 else ""
    ax.set_title(f"{metric}{band}", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    return _save(fig, path)


def metric_theory(ds, metric: str):
    """The theory variable of ``metric`` in a sweep, or None (``irw_range_m`` -> ``irw_range_theory_m``).

    Parameters
    ----------
    ds : xarray.Dataset
    metric : str

    Returns
    -------
    xarray.DataArray or None
    """
    name = theory_name(metric)
    return ds[name] if name in ds.data_vars else None
