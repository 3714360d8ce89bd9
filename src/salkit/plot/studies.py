"""Figures of studies: the chirp study's grids as heat maps (seed 002), a sweep's metric against its
varied fields (median, 5-95 % band, theory)."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.ticker
import numpy as np

from ..units import display_scale, theory_name
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


#: The narrowest span a sweep figure's value axis shows, as a fraction of the values' magnitude (and
#: in dB for levels): a flat curve is drawn flat, not zoomed into its numerical noise.
MIN_RELATIVE_SPAN = 0.02
MIN_DB_SPAN = 0.5


def _floor_span(ax, values, unit: str, relative: float = MIN_RELATIVE_SPAN, db: float = MIN_DB_SPAN) -> None:
    """Widen the value axis to at least the smallest span worth reading (about the middle)."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if not v.size:
        return
    lo, hi = float(v.min()), float(v.max())
    mid = 0.5 * (lo + hi)
    need = db if unit == "dB" else relative * max(abs(mid), abs(lo), abs(hi))
    if need > 0 and hi - lo < need:
        ax.set_ylim(mid - need / 2 - 0.05 * need, mid + need / 2 + 0.05 * need)


def sweep_figure(ds, metric: str, path) -> Path:
    """A sweep's metric against its first varied field: the median over the realisations with the
    5-95 % band, one line per value of the second varied field, its theory dashed where the sweep
    holds one (an ensemble expectation: the mean over the realisations is drawn beside it, dotted),
    a log axis for a log sweep. Values and fields are drawn in engineering units (GHz, cm); a metric
    with a theory has a second panel with its deviation from theory (%, or dB for a level), where a
    small deviation can be read; no axis zooms into numerical noise (:data:`MIN_RELATIVE_SPAN`).

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
    numeric_x = np.issubdtype(np.asarray(x.values).dtype, np.number)
    xunit = x.attrs.get("units", "1")
    xf, xu = display_scale(xunit, x.values) if numeric_x else (1.0, xunit)
    xs = np.asarray(x.values) / xf if numeric_x else x.values
    unit = ds[metric].attrs.get("units", "1")
    yf, yu = display_scale(unit, ds[metric].values)
    has_theory = metric_theory(ds, metric) is not None
    if has_theory:
        fig, (ax, dax) = _subplots(2, 1, figsize=(6.4, 5.6), sharex=True, gridspec_kw={"height_ratios": [2.2, 1]})
    else:
        fig, ax = _subplots(figsize=(6.4, 4.2))
        dax = None
    second = dims[1] if len(dims) > 1 else None
    groups = [(None, ds)] if second is None else [(v, ds.sel({second: v})) for v in ds[second].values]
    drawn, devs = [], []
    for gi, (v, sub) in enumerate(groups):
        a = sub[metric]
        other = [d for d in a.dims if d not in (dims[0], "realisation")]
        if other:  # a third axis and beyond: their first value
            a = a.isel({d: 0 for d in other})
        med = a.median("realisation", skipna=True)
        name = second.split(".")[-1] if second else ""
        label = "measured" if v is None else (f"{name} = {v:g}" if isinstance(v, (int, float, np.number))
                                               else f"{name} = {v}")
        line, = ax.plot(xs, med.values / yf, "o-", label=label)
        drawn.append(med.values / yf)
        if a.sizes["realisation"] > 1:
            lo, hi = a.quantile(0.05, "realisation", skipna=True), a.quantile(0.95, "realisation", skipna=True)
            ax.fill_between(xs, lo.values / yf, hi.values / yf, color=line.get_color(), alpha=0.2, lw=0)
            drawn += [lo.values / yf, hi.values / yf]
        t = metric_theory(sub, metric)
        if t is not None:
            if other:
                t = t.isel({d: 0 for d in other if d in t.dims})
            tm = t.median("realisation", skipna=True).values
            ax.plot(xs, tm / yf, "--", color=line.get_color(), label="theory (dashed)" if gi == 0 else None)
            drawn.append(tm / yf)
            if a.sizes["realisation"] > 1:  # theories are ensemble expectations: the mean beside them
                ax.plot(xs, a.mean("realisation", skipna=True).values / yf, "x:", color=line.get_color(),
                        label="mean (dotted)" if gi == 0 else None)
            with np.errstate(divide="ignore", invalid="ignore"):
                dev = med.values - tm if unit == "dB" else 100 * (med.values / tm - 1)
            dax.plot(xs, dev, "o-", color=line.get_color())
            devs.append(dev)
    if x.attrs.get("scale") == "log":
        ax.set_xscale("log")
    _floor_span(ax, np.concatenate([np.ravel(d) for d in drawn]) if drawn else [], yu if unit != "dB" else "dB")
    bottom = dax if dax is not None else ax
    bottom.set_xlabel(f"{dims[0]}" + (f" ({xu})" if xu not in ("", "1") else ""))
    bare = next((metric[: -len(sfx)] for sfx in ("_m", "_db", "_s", "_rad", "_hz") if metric.endswith(sfx)), metric)
    ax.set_ylabel(bare + (f" ({yu})" if yu not in ("", "1") else ""))
    if dax is not None:
        dax.axhline(0.0, color="0.4", lw=0.8)
        dax.set_ylabel("measured - theory (dB)" if unit == "dB" else "measured / theory - 1 (%)", fontsize=8)
        if devs:
            _floor_span(dax, np.concatenate([np.ravel(d) for d in devs]) if devs else [], "dB" if unit == "dB" else "%",
                        relative=0.0, db=0.5 if unit == "dB" else 0.0)
            if unit != "dB":  # at least +-1 % shown: a deviation of a few 0.01 % is not a gap
                lo, hi = dax.get_ylim()
                dax.set_ylim(min(lo, -1.0), max(hi, 1.0))
        dax.grid(alpha=0.3, which="both")
    for a_ in (ax,) + ((dax,) if dax is not None else ()):
        a_.ticklabel_format(axis="y", useOffset=False, style="plain") if a_.get_yscale() == "linear" else None
        if numeric_x and a_.get_xscale() == "linear":
            a_.ticklabel_format(axis="x", useOffset=False, style="plain")
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
