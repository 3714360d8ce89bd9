"""Figures of the turbulence system (seed 004): phase screens and their structure function,
autofocus histories and PGA's steps."""
from __future__ import annotations

from pathlib import Path

import lazy_loader as _lazy
import numpy as np

from .canvas import _db, _log_ticks, _save, _subplots

sfft = _lazy.load("scipy.fft", suppress_warning=True)


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
