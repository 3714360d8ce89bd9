"""Figures a person can look at. Only the interface layers (cli, report, systems) call these."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402
from ..io.datasets import atomic_path
import lazy_loader as _lazy
sfft = _lazy.load("scipy.fft", suppress_warning=True)


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


def image_db(image_ds, path, title: str = "", dynamic_range: float = 40.0, truth=None) -> Path:
    """The image magnitude in dB (peak 0 dB), axes in metres, expected target positions marked.

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
    img = np.abs(image_ds["image"].values)
    az = image_ds["azimuth"].values
    rg = image_ds["range"].values
    db = 20 * np.log10(np.maximum(img / max(img.max(), 1e-30), 1e-12))
    fig, ax = _subplots(figsize=(6.4, 5.2))
    ext = [az[0], az[-1], rg[0], rg[-1]]
    im = ax.imshow(db.T, origin="lower", extent=ext, cmap="gray", vmin=-dynamic_range, vmax=0,
                   aspect="equal", interpolation="nearest")
    if truth is not None and len(truth):
        ax.plot(truth[:, 0], truth[:, 1], "o", mfc="none", mec="tab:red", ms=10, mew=1.0,
                label="expected position")
        ax.legend(loc="upper right", fontsize=8)
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

    Parameters
    ----------
    raw_ds : xarray.Dataset
    path : path

    Returns
    -------
    Path
    """
    s = np.abs(raw_ds["signal"].values)
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


def screen_image(phi: np.ndarray, dx: float, path, title: str = "") -> Path:
    """A phase screen (rad) with axes in metres.

    Parameters
    ----------
    phi : float (n, n)
        rad.
    dx : float
        m.
    path : path
    title : str

    Returns
    -------
    Path
    """
    n = phi.shape[0]
    fig, ax = _subplots(figsize=(5.6, 4.8))
    im = ax.imshow(phi, origin="lower", extent=[0, phi.shape[1] * dx, 0, n * dx], cmap="viridis")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title)
    fig.colorbar(im, ax=ax, label="phase (rad)")
    return _save(fig, path)


def autofocus_history(res, path, title: str = "") -> Path:
    """Per-iteration entropy and correction RMS, and the total phase correction (rad).

    Parameters
    ----------
    res : AutofocusResult
    path : path
    title : str

    Returns
    -------
    Path
    """
    it = [h["iteration"] for h in res.history]
    fig, axes = _subplots(1, 2, figsize=(11, 3.6))
    ax = axes[0]
    ax.plot(it, [h["entropy"] for h in res.history], "o-", label="entropy (nats)")
    ax.axvline(res.best_iteration, color="gray", ls=":", label="returned")
    ax.set_xlabel("iteration")
    ax.set_ylabel("entropy (nats)")
    ax2 = ax.twinx()
    ax2.plot(it, [h["phase_rms"] for h in res.history], "s--", color="tab:red", label="correction RMS")
    ax2.set_ylabel("correction RMS (rad)", color="tab:red")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title)
    axes[1].plot(sfft.fftshift(res.phase))
    axes[1].set_xlabel("phase-history bin (centred)")
    axes[1].set_ylabel("estimated phase error (rad)")
    axes[1].grid(alpha=0.3)
    return _save(fig, path)


def screens_figure(path, out) -> Path:
    """Seed 004 figs 1-2: one layer's screen and the sum of all layers (rad), axes in metres.

    Parameters
    ----------
    path : TurbulentPath
    out : path
        PNG to write.

    Returns
    -------
    Path
    """
    n = path.screens.shape[1]
    ext = [0, n * path.dx, 0, n * path.dx]
    fig, axes = _subplots(1, 2, figsize=(11, 4.4))
    for ax, data, t in ((axes[0], path.screens[0], f"one layer (z = {path.z[0]:.0f} m, r0 = {path.r0[0]:.3g} m)"),
                        (axes[1], path.screens.sum(axis=0), f"sum of {path.screens.shape[0]} layers")):
        im = ax.imshow(data.T, origin="lower", extent=ext, cmap="viridis")
        ax.set_title(t, fontsize=9)
        ax.set_xlabel("along track (m)")
        ax.set_ylabel("across (m)")
        fig.colorbar(im, ax=ax, label="rad")
    return _save(fig, out)


def structure_function_figure(r, d, err, theory, out, title="") -> Path:
    """Seed 004 fig 3: ensemble structure function against theory, and their ratio.

    Parameters
    ----------
    r : float array
        Separations, m.
    d, err : float arrays
        Ensemble estimate and its standard error, rad^2.
    theory : float array
        rad^2.
    out : path
    title : str

    Returns
    -------
    Path
    """
    fig, axes = _subplots(1, 2, figsize=(11, 3.8))
    axes[0].loglog(r, theory, "k-", label="theory 6.88 (r/r0)^(5/3)")
    _log_ticks(axes[0])
    axes[0].errorbar(r, d, yerr=err, fmt="o", ms=3, label="ensemble")
    axes[0].set_xlabel("separation (m)")
    axes[0].set_ylabel("D(r) (rad^2)")
    axes[0].legend(fontsize=8)
    axes[0].set_title(title, fontsize=9)
    axes[1].errorbar(r / r[0], d / theory, yerr=err / theory, fmt="o-", ms=3)
    axes[1].axhspan(0.97, 1.03, color="g", alpha=0.15, label="+-3 %")
    axes[1].axhline(1, color="k", lw=0.8)
    axes[1].set_xlabel("separation (pixels)")
    axes[1].set_ylabel("measured / theory")
    axes[1].legend(fontsize=8)
    return _save(fig, out)


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


def _db(img, ref):
    a = np.abs(img) / max(ref, 1e-30)
    return 20 * np.log10(np.maximum(a, 1e-4))


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


def pga_steps_figure(before, steps, out, title="", notes=None) -> Path:
    """Seed 004 figs 6-8: the I target after PGA capped at 5, 10 and 20 iterations.

    Parameters
    ----------
    before : xarray.Dataset
    steps : dict
        Label -> image.
    out : path
    title : str
        The turbulence class.
    notes : dict, optional
        Label -> a second title line (the image entropy, which tells panels apart that look alike).

    Returns
    -------
    Path
    """
    items = [("focused, no PGA", before)] + list(steps.items())
    fig, axes = _subplots(1, len(items), figsize=(3.0 * len(items) + 1.0, 3.6))
    im = None
    for ax, (t, ds) in zip(axes, items):
        img = ds["image"].values
        az, rg = ds["azimuth"].values, ds["range"].values
        ka, kr = np.abs(az) <= 0.5, np.abs(rg) <= 0.5
        sub = img[np.ix_(ka, kr)]
        im = ax.imshow(_db(sub, np.abs(sub).max()).T, origin="lower", cmap="gray", vmin=-30, vmax=0,
                       extent=[az[ka][0], az[ka][-1], rg[kr][0], rg[kr][-1]])
        note = (notes or {}).get(t, "")
        ax.set_title(f"{t}" + (f"\n{note}" if note else ""), fontsize=8)
        ax.set_xlabel("azimuth (m)", fontsize=8)
        ax.set_ylabel("range (m)", fontsize=8)
        ax.tick_params(labelsize=7)
    fig.colorbar(im, ax=axes, shrink=0.85, label="dB (peak = 0)")
    if title:
        fig.suptitle(f"{title} class: PGA stopped after at most 5, 10 and 20 iterations (it stops by itself once "
                     "the phase estimate converges)", fontsize=9)
    return _save(fig, out)


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


def spaceborne_figures(truth, fig7, single, stack, counts, curve, snr1_theory, az, rg, out) -> None:
    """Seed 001 figs 7 and 8 and the stack SNR against sqrt(P).

    Parameters
    ----------
    truth : float (nx, ny)
    fig7 : dict
        Squint (deg) -> (uncorrected, corrected) magnitude.
    single, stack : float (nx, ny)
        Magnitudes.
    counts : list of int
    curve : list of float
        Stack SNR for each count.
    snr1_theory : float
        Single sub-image SNR of eq 15.
    az, rg : float64
        m.
    out : path
        Folder.
    """
    out = Path(out)
    ext = [az[0], az[-1], rg[0], rg[-1]]
    qs = list(fig7)
    fig, axes = _subplots(2, len(qs) + 1, figsize=(3.2 * (len(qs) + 1) + 1.0, 6.8))
    axes[0, 0].imshow(truth.T, origin="lower", extent=ext, cmap="gray")
    axes[0, 0].set_title("target (truth)", fontsize=9)
    axes[1, 0].axis("off")
    im = None
    for j, q in enumerate(qs):
        for i, (img, t) in enumerate(zip(fig7[q], ("before geometric correction", "after (common frame)"))):
            a = img / max(img.max(), 1e-30)
            im = axes[i, j + 1].imshow(20 * np.log10(np.maximum(a, 1e-3)).T, origin="lower", extent=ext, cmap="gray",
                                       vmin=-30, vmax=0)
            axes[i, j + 1].set_title(f"squint {q:+.1f} deg\n{t}", fontsize=8)
    for ax in axes.ravel():
        if ax.axison:
            ax.tick_params(labelsize=7)
            ax.set_xlabel("along track (m)", fontsize=8)
            ax.set_ylabel("range (m)", fontsize=8)
    fig.colorbar(im, ax=axes[:, 1:], shrink=0.8, label="dB (each panel's peak = 0)")
    _save(fig, out / "subimages.png")
    fig, axes = _subplots(1, 2, figsize=(9.6, 4.2))
    im = None
    for ax, img, t in ((axes[0], single, "one photon-limited sub-image"), (axes[1], stack, f"stack of {counts[-1]}")):
        a = img / max(np.percentile(img, 99.5), 1e-30)
        im = ax.imshow(np.minimum(a, 1).T, origin="lower", extent=ext, cmap="gray", vmin=0, vmax=1)
        ax.set_title(t, fontsize=9)
        ax.set_xlabel("along track (m)")
        ax.set_ylabel("range (m)")
    fig.colorbar(im, ax=axes, shrink=0.85, label="intensity / its 99.5th percentile")
    _save(fig, out / "stack.png")
    fig, ax = _subplots(figsize=(5.8, 4))
    c = np.asarray(counts, float)
    ax.loglog(c, curve, "o-", label="measured")
    ax.loglog(c, snr1_theory * np.sqrt(c), "k--", label="sqrt(P) x eq 15")
    ax.set_xlabel("sub-images stacked, P")
    ax.set_ylabel("image SNR")
    _log_ticks(ax)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    _save(fig, out / "snr_vs_p.png")


def coherent_stack_figure(image, stack_incoherent, az, rg, res, path) -> Path:
    """The coherent stack against the incoherent one, and the coherent stack's along-track
    resolution against the number of sub-apertures (point target) with the combined aperture's
    theory.

    Parameters
    ----------
    image : complex (nx, ny)
        Coherent stack.
    stack_incoherent : float (nx, ny)
        Incoherent stack (amplitude).
    az, rg : float64
        m.
    res : dict
        :func:`salkit.stack.coherent_resolution`.
    path : path

    Returns
    -------
    Path
    """
    fig, axes = _subplots(1, 3, figsize=(14, 4.0))
    ext = [az[0], az[-1], rg[0], rg[-1]]
    for ax, a, t in ((axes[0], stack_incoherent, "incoherent stack (mean intensity)"),
                     (axes[1], np.abs(image), "coherent stack (phase-aligned sum)")):
        a = a ** 2 / max(np.percentile(a ** 2, 99.5), 1e-30)
        im = ax.imshow(np.minimum(a, 1).T, origin="lower", extent=ext, cmap="gray", vmin=0, vmax=1)
        ax.set_title(t, fontsize=9)
        ax.set_xlabel("along track (m)")
        ax.set_ylabel("range (m)")
    fig.colorbar(im, ax=axes[:2], shrink=0.85, label="intensity / its 99.5th percentile")
    ax = axes[2]
    P = np.asarray(res["counts"], float)
    ax.loglog(P, 100 * np.asarray(res["irw_theory_m"]), "k--", label="0.886 lambda L0 / (2 P L_sa)")
    ax.loglog(P, 100 * np.asarray(res["irw_m"]), "o", label="coherent stack, point target")
    ax.loglog(P, 100 * np.full(P.size, res["irw_m"][0]), ":", color="tab:gray", label="incoherent stack (unchanged)")
    _log_ticks(ax)
    ax.set_xlabel("sub-apertures summed, P")
    ax.set_ylabel("along-track IRW (cm)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return _save(fig, path)


def trajectory_figure(fig_data, path) -> Path:
    """The point target on the true relative orbit, focused with the true positions, the tangent
    line and the seed's straight line: peak (over the true processing's) and PSLR against squint.

    Parameters
    ----------
    fig_data : dict
        :func:`salkit.systems.spaceborne.trajectory_study`'s figure data.
    path : path

    Returns
    -------
    Path
    """
    q = fig_data["squints"]
    labels = {"true": "true positions (BP)", "tangent": "tangent line at the sub-aperture centre",
              "line": "the seed's straight line at V"}
    fig, axes = _subplots(1, 2, figsize=(11, 3.8))
    for k, lab in labels.items():
        axes[0].plot(q, fig_data[k]["peak"], "o-", label=lab)
        axes[1].plot(q, fig_data[k]["pslr"], "o-", label=lab)
    axes[0].set_yscale("log")
    axes[0].set_ylim(1e-3, 2)
    axes[0].set_ylabel("peak / true processing's peak")
    axes[1].axhline(-13.26, color="k", ls=":", lw=1, label="sinc -13.26 dB")
    axes[1].set_ylabel("azimuth PSLR (dB)")
    for ax in axes:
        ax.set_xlabel("squint (deg)")
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=8)
    return _save(fig, path)


def resolution_squint_figure(squints, measured, q, theory, qm, path) -> Path:
    """Seed 001 fig 5: along-track resolution against squint, eq 12 (``theory`` at squints ``q``,
    deg, m) and measured points; ``qm`` the squint within which it stays within 1.1x.

    Parameters
    ----------
    squints, measured : sequence of float
        deg, m.
    q, theory : float arrays
        deg, m.
    qm : float
        deg.
    path : path

    Returns
    -------
    Path
    """
    fig, ax = _subplots(figsize=(5.8, 3.8))
    ax.plot(q, 100 * np.asarray(theory), "k-", label="eq 12")
    ax.plot(squints, 100 * np.asarray(measured), "o", label="measured (IRW / 0.886)")
    ax.axvspan(-qm, qm, color="g", alpha=0.1, label=f"within 1.1x (|squint| < {qm:.1f} deg)")
    ax.set_xlabel("squint (deg)")
    ax.set_ylabel("along-track resolution (cm)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return _save(fig, path)
