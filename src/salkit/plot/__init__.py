"""Figures a person can look at. Only the interface layers (cli, report, systems) call these."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..signals.windows import window  # noqa: E402


def _save(fig, path: str | Path) -> Path:
    from ..io.datasets import atomic_path
    try:
        with atomic_path(path, suffix=".png") as tmp:
            fig.savefig(tmp, dpi=110, bbox_inches="tight")
    finally:
        plt.close(fig)
    return Path(path)


def image_db(image_ds, path, title: str = "", dynamic_range: float = 40.0, truth=None) -> Path:
    """The image magnitude in dB (peak 0 dB), axes in metres, expected target positions marked."""
    img = np.abs(image_ds["image"].values)
    az = image_ds["azimuth"].values
    rg = image_ds["range"].values
    db = 20 * np.log10(np.maximum(img / max(img.max(), 1e-30), 1e-12))
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
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


def theory_ipr(window_name: str, x: np.ndarray, resolution: float, nbar: int = 4,
               sll: float = 35.0) -> np.ndarray:
    """Theoretical |IPR|^2 (peak 1) of a window at offsets x (m) for a given resolution (m)."""
    n = 256
    w = window(window_name, n, nbar, sll)
    t = (np.arange(n) - (n - 1) / 2) / n  # normalised aperture coordinate
    h = np.abs(np.exp(2j * np.pi * np.outer(x / resolution, t)) @ w)
    return (h / h.max()) ** 2


def cuts(details: dict, metrics: dict, attrs: dict, path) -> Path:
    """Range and azimuth cuts through the brightest target against the theoretical response."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for ax, name, d0, key in ((axes[0], "range", details["_cut_dy"], "_cut_range"),
                              (axes[1], "azimuth", details["_cut_dx"], "_cut_azimuth")):
        y = details[key] ** 2
        y = y / y.max()
        i = int(np.argmax(y))
        x = (np.arange(y.size) - i) * d0
        res = float(attrs.get(f"resolution_{name}", np.nan))
        keep = np.abs(x) <= 8 * res
        ax.plot(x[keep] * 100, 10 * np.log10(np.maximum(y[keep], 1e-8)), label="measured")
        th = theory_ipr(attrs.get("window", "none"), x[keep], res)
        ax.plot(x[keep] * 100, 10 * np.log10(np.maximum(th, 1e-8)), "--", label="theory")
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
    """Magnitude of the raw dechirped samples (slow time vs fast time)."""
    s = np.abs(raw_ds["signal"].values)
    t = raw_ds["fast_time"].values * 1e6
    st = raw_ds["slow_time"].values
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    im = ax.imshow(s.T, origin="lower", aspect="auto", cmap="viridis",
                   extent=[st[0], st[-1], t[0], t[-1]])
    ax.set_xlabel("slow time (s)")
    ax.set_ylabel("fast time (us)")
    ax.set_title("raw dechirped signal magnitude")
    fig.colorbar(im, ax=ax)
    return _save(fig, path)


def screen_image(phi: np.ndarray, dx: float, path, title: str = "") -> Path:
    """A phase screen (rad) with axes in metres."""
    n = phi.shape[0]
    fig, ax = plt.subplots(figsize=(5.6, 4.8))
    im = ax.imshow(phi, origin="lower", extent=[0, phi.shape[1] * dx, 0, n * dx], cmap="viridis")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title)
    fig.colorbar(im, ax=ax, label="phase (rad)")
    return _save(fig, path)


def autofocus_history(res, path, title: str = "") -> Path:
    """Per-iteration entropy and correction RMS, and the total phase correction (rad)."""
    import scipy.fft as sfft
    it = [h["iteration"] for h in res.history]
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.6))
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
    fig.subplots_adjust(wspace=0.45)
    return _save(fig, path)
