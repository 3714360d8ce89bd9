"""Figures of images and raw data: an image in dB with its truth, point-target cuts, the raw phase
history, images side by side, range profiles, impulse-response classes, 3-D models seen from the
sensor."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .canvas import _db, _save, _subplots, peak_magnitude, plt


def image_db(image_ds, path, title: str = "", dynamic_range: float = 40.0, truth=None) -> Path:
    """The image magnitude in dB (peak 0 dB), axes in metres, expected target positions marked.

    An image larger than :data:`~salkit.plot.canvas.PREVIEW_PIXELS` a side is shown by the
    brightest pixel of each k x k block (:func:`~salkit.plot.canvas.peak_magnitude`, read a block
    at a time, so an image opened lazily is never whole in memory); the title says k.

    Parameters
    ----------
    image_ds : xarray.Dataset
        salkit image.
    path : path
        PNG to write.
    title : str
    dynamic_range : float
        dB shown below the peak.
    truth : float (T, 2), optional
        Expected (azimuth, range) positions, m.

    Returns
    -------
    Path
    """
    img, k = peak_magnitude(image_ds["image"])
    az = image_ds["azimuth"].values
    rg = image_ds["range"].values
    if k > 1:
        az = az[: img.shape[0] * k: k] + (k - 1) / 2 * (az[1] - az[0])
        rg = rg[: img.shape[1] * k: k] + (k - 1) / 2 * (rg[1] - rg[0])
        title = f"{title}, each pixel the brightest of {k} x {k}" if title else ""
    db = 20 * np.log10(np.maximum(img / max(img.max(), 1e-30), 1e-12))
    fig, ax = _subplots(figsize=(6.4, 5.2))
    ext = [az[0], az[-1], rg[0], rg[-1]]
    im = ax.imshow(db.T, origin="lower", extent=ext, cmap="gray", vmin=-dynamic_range, vmax=0,
                   aspect="equal", interpolation="nearest")
    if truth is not None and len(truth):  # the targets the image holds: none drawn beyond its axes
        truth = np.asarray(truth, np.float64)
        inside = ((truth[:, 0] >= min(ext[:2])) & (truth[:, 0] <= max(ext[:2])) & (truth[:, 1] >= min(ext[2:]))
                  & (truth[:, 1] <= max(ext[2:])))
        if inside.any():
            ax.plot(truth[inside, 0], truth[inside, 1], "o", mfc="none", mec="tab:red", ms=10, mew=1.0,
                    label="expected position")
            ax.legend(loc="upper right", fontsize=8)
    ax.set_xlim(ext[0], ext[1])
    ax.set_ylim(ext[2], ext[3])
    ax.set_xlabel("azimuth (m)")
    ax.set_ylabel(f"{image_ds.attrs.get('plane', 'slant')} range (m)")
    ax.set_title(title or f"{image_ds.attrs.get('algorithm', '')} image")
    fig.colorbar(im, ax=ax, label="dB")
    return _save(fig, path)


def cuts(curves: dict, metrics: dict, path) -> Path:
    """Range and azimuth cuts through the brightest target against the theoretical response.

    ``curves`` is :func:`salkit.metrics.pointtarget.cut_curves`: per axis (x m, measured dB, theory dB).

    Parameters
    ----------
    curves : dict
    metrics : dict
        Measured and theoretical IRW (m), PSLR (dB), for the legend.
    path : path

    Returns
    -------
    Path
    """
    fig, axes = _subplots(1, 2, figsize=(11, 3.8))
    for ax, name in ((axes[0], "range"), (axes[1], "azimuth")):
        x, meas, th = curves[name]
        ax.plot(x * 100, meas, label="measured")
        ax.plot(x * 100, th, "--", label="theory")
        ax.set_ylim(-50, 3)
        ax.set_xlabel(f"{name} offset (cm)")
        ax.set_ylabel("dB")
        ax.grid(alpha=0.3)
        ax.set_title(f"{name}: IRW {metrics[f'irw_{name}_m'] * 100:.3f} cm "
                     f"(theory {metrics.get(f'irw_{name}_theory_m', np.nan) * 100:.3f}), "
                     f"PSLR {metrics[f'pslr_{name}_db']:.2f} dB", fontsize=9)
        ax.legend(fontsize=8)
    return _save(fig, path)


def raw_phase_history(raw_ds, path) -> Path:
    """Magnitude of the raw dechirped samples (slow time vs fast time).

    A history larger than :data:`~salkit.plot.canvas.PREVIEW_PIXELS` a side is shown by the largest
    magnitude of each k x k block (:func:`~salkit.plot.canvas.peak_magnitude`; bounded memory).

    Parameters
    ----------
    raw_ds : xarray.Dataset
    path : path

    Returns
    -------
    Path
    """
    s, _ = peak_magnitude(raw_ds["signal"])
    t = raw_ds["fast_time"].values * 1e6
    st = raw_ds["slow_time"].values
    fig, ax = _subplots(figsize=(6.4, 4.0))
    im = ax.imshow(s.T, origin="lower", aspect="auto", cmap="viridis",
                   extent=[st[0], st[-1], t[0], t[-1]])
    ax.set_xlabel("slow time (s)")
    ax.set_ylabel("fast time (us)")
    ax.set_title("raw dechirped signal magnitude")
    fig.colorbar(im, ax=ax, label="|signal| (arb. units)")
    return _save(fig, path)


def ipr_classes_figure(cuts, out) -> Path:
    """Seed 004 fig 4: azimuth IPR of the point target per class, before and after PGA.

    Parameters
    ----------
    cuts : dict
        Class -> (measure details before PGA, after PGA).
    out : path

    Returns
    -------
    Path
    """
    fig, axes = _subplots(1, 2, figsize=(11, 3.8), sharey=True)
    for ax, idx, t in ((axes[0], 0, "focused (PFA)"), (axes[1], 1, "after PGA")):
        for name, pair in cuts.items():
            m = pair[idx]
            y = m["_cut_azimuth"] ** 2
            y = y / max(cuts[list(cuts)[0]][0]["_cut_azimuth"].max() ** 2, 1e-30)
            x = m["_cut_origin_az"] + np.arange(y.size) * m["_cut_dx"]
            ax.plot(x * 100, 10 * np.log10(np.maximum(y, 1e-6)), label=name)
        ax.set_xlabel("azimuth (cm)")
        ax.set_title(t)
        ax.set_ylim(-40, 3)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel("dB (re. no turbulence)")
    return _save(fig, out)


def image_grid_figure(images, out) -> Path:
    """Seed 004 fig 5: the I target under each class, before (top) and after PGA (bottom).

    Parameters
    ----------
    images : dict
        Class -> (image before PGA, after PGA), xarray.Dataset.
    out : path

    Returns
    -------
    Path
    """
    names = list(images)
    fig, axes = _subplots(2, len(names), figsize=(3.0 * len(names) + 1.0, 6.4), squeeze=False)
    im = None
    for j, name in enumerate(names):
        for i, ds in enumerate(images[name]):
            img = ds["image"].values
            az, rg = ds["azimuth"].values, ds["range"].values
            keep_a, keep_r = np.abs(az) <= 0.5, np.abs(rg) <= 0.5
            sub = img[np.ix_(keep_a, keep_r)]
            im = axes[i, j].imshow(_db(sub, np.abs(sub).max()).T, origin="lower", cmap="gray", vmin=-30, vmax=0,
                                   extent=[az[keep_a][0], az[keep_a][-1], rg[keep_r][0], rg[keep_r][-1]])
            axes[i, j].set_title(f"{name}{' + PGA' if i else ''}", fontsize=9)
            axes[i, j].set_xlabel("azimuth (m)", fontsize=8)
            axes[i, j].set_ylabel("range (m)", fontsize=8)
            axes[i, j].tick_params(labelsize=7)
    fig.colorbar(im, ax=axes, shrink=0.8, label="dB (each panel's peak = 0)")
    return _save(fig, out)


def range_profiles_figure(ds, out) -> Path:
    """Range profiles of every point for every method (dB, peak of the ideal = 0).

    Parameters
    ----------
    ds : xarray.Dataset
        Range profiles (point, range), m.
    out : path

    Returns
    -------
    Path
    """
    pts = list(ds["point"].values)
    fig, axes = _subplots(1, len(pts), figsize=(4.2 * len(pts), 3.6), squeeze=False)
    r = ds["range"].values
    for j, p in enumerate(pts):
        ref = np.nanmax(np.abs(ds["ideal"].sel(point=p).values))
        centre = r[int(np.nanargmax(np.abs(ds["ideal"].sel(point=p).values)))]
        keep = np.abs(r - centre) < 1.0
        for m in ds.data_vars:
            y = np.abs(ds[m].sel(point=p).values)[keep]
            axes[0, j].plot(r[keep], 20 * np.log10(np.maximum(y / ref, 1e-5)), label=m, lw=1)
        axes[0, j].set_ylim(-40, 3)
        axes[0, j].set_title(f"point {p}", fontsize=9)
        axes[0, j].set_xlabel("range (m)")
        axes[0, j].legend(fontsize=7)
    axes[0, 0].set_ylabel("dB")
    return _save(fig, out)


def model_view_figure(view: dict, path, title: str = "") -> Path:
    """The 3-D objects as the sensor sees them (seen surfaces shaded by their Lambertian brightness)
    and from above, the parts hidden from the sensor (shadowed) in red; facing-away surfaces are not
    drawn from above where a seen or shadowed one lies over them.

    Parameters
    ----------
    view : dict
        :func:`salkit.simulate.targets.model_view`.
    path : path
    title : str

    Returns
    -------
    Path
    """
    fig, (ax, top) = _subplots(1, 2, figsize=(11, 4.6))
    seen = view["state"] == 0
    z = view["z"]
    norm = plt.Normalize(float(z.min()), float(max(z.max(), z.min() + 1e-9)))
    # hundreds of thousands of samples: drawn as an image of points (the highest sample of each
    # cell on top), where a scatter of markers took seconds to draw
    rgba = plt.cm.viridis(norm(z[seen]))
    _points_image(ax, view["h"][seen], view["v"][seen], z[seen], rgba)
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="viridis"), ax=ax, label="height (m)")
    ax.set_xlabel("across the line of sight, horizontal (m)")
    ax.set_ylabel("across the line of sight, vertical (m)")
    ax.set_title("seen from the sensor")
    front = view["state"] < 2  # from above: each cell shows its highest seen or shadowed sample
    colour = plt.cm.viridis(norm(z[front]))
    colour[view["state"][front] == 1] = (0.84, 0.15, 0.16, 1.0)
    _points_image(top, view["x"][front], view["y"][front], z[front], colour)
    top.scatter([], [], color=plt.cm.viridis(0.5), s=20, label="seen by the sensor (height)")
    top.scatter([], [], color=(0.84, 0.15, 0.16), s=20, label="hidden from it (shadowed)")
    top.set_xlabel("x, azimuth (m)")
    top.set_ylabel("y, ground range (m)")
    top.set_title("from above (the sensor towards -y)")
    top.legend(loc="upper right", fontsize=8)
    fig.suptitle(title or "the 3-D model")
    return _save(fig, path)


#: Cells across the longer side of a point image (about the panel's pixels at the figures' 110 dpi).
POINT_CELLS = 480


def _points_image(ax, x, y, z, rgba, cells: int = POINT_CELLS):
    """Draw points (x, y) coloured ``rgba`` (N, 4) as an image on equal axes: a grid ``cells``
    wide along the longer side, each point a 3 x 3-cell dot (as a 1-point marker at the figures'
    resolution), the highest (``z``) point on top where dots overlap; empty cells transparent.
    Returns the image artist."""
    x, y, z = (np.asarray(a, np.float64) for a in (x, y, z))
    if x.size == 0:
        return ax.imshow(np.zeros((1, 1, 4)))
    x0, x1, y0, y1 = float(x.min()), float(x.max()), float(y.min()), float(y.max())
    side = max(x1 - x0, y1 - y0, 1e-12) / cells
    nx = int((x1 - x0) / side) + 1
    ny = int((y1 - y0) / side) + 1
    ix = np.minimum(((x - x0) / side).astype(np.int64), nx - 1)
    iy = np.minimum(((y - y0) / side).astype(np.int64), ny - 1)
    order = np.argsort(z, kind="stable")[::-1]  # highest first: np.unique keeps each cell's first
    cell, first = np.unique((iy * nx + ix)[order], return_index=True)
    # each cell's highest point, two cells of margin round; the image (one cell of margin) shows in
    # each cell the highest point within one cell of it
    top = np.full((ny + 4) * (nx + 4), -np.inf)
    colour = np.zeros(((ny + 4) * (nx + 4), 4))
    at = (iy[order[first]] + 2) * (nx + 4) + ix[order[first]] + 2
    top[at] = z[order[first]]
    colour[at] = rgba[order[first]]
    top = top.reshape(ny + 4, nx + 4)
    colour = colour.reshape(ny + 4, nx + 4, 4)
    best = np.full((ny + 2, nx + 2), -np.inf)
    img = np.zeros((ny + 2, nx + 2, 4))
    for dy in range(3):
        for dx in range(3):
            zs = top[dy:dy + ny + 2, dx:dx + nx + 2]
            hi = zs > best
            best[hi] = zs[hi]
            img[hi] = colour[dy:dy + ny + 2, dx:dx + nx + 2][hi]
    ext = (x0 - side, x0 + (nx + 1) * side, y0 - side, y0 + (ny + 1) * side)
    return ax.imshow(img, origin="lower", extent=ext, interpolation="nearest", aspect="equal")
