"""Figures of the down-looking SAL experiment (seed 000)."""
from __future__ import annotations

import numpy as np

from .canvas import _db, _save, _subplots
import textwrap


def _ext(imgs):
    return [imgs.y[0], imgs.y[-1], imgs.x[0], imgs.x[-1]]


def raw_current(current, Y, t, path):
    """The balanced-detector current of the first scans: a forward/backward pair and the history.

    Parameters
    ----------
    current : float (n_scans, samples)
    Y : float64 (n_scans,)
        m.
    t : float64 (samples,)
        s.
    path : path

    Returns
    -------
    Path
    """
    fig, ax = _subplots(1, 2, figsize=(11, 3.6))
    mid = current.shape[0] // 2 & ~1
    ax[0].plot(t * 1e3, current[mid], lw=0.6, label=f"forward scan {mid}")
    ax[0].plot(t * 1e3, current[mid + 1], lw=0.6, label=f"backward scan {mid + 1}")
    ax[0].set_xlabel("fast time (ms)")
    ax[0].set_ylabel("balanced current (arb. units)")
    ax[0].set_xlim(t[0] * 1e3, t[0] * 1e3 + (t[-1] - t[0]) * 1e3 * 0.1)
    ax[0].legend(fontsize=8)
    im = ax[1].imshow(current.T, aspect="auto", origin="lower", cmap="gray",
                      extent=[Y[0], Y[-1], t[0] * 1e3, t[-1] * 1e3], interpolation="nearest")
    fig.colorbar(im, ax=ax[1], label="balanced current (arb. units)")
    ax[1].set_xlabel("along-track position (m)")
    ax[1].set_ylabel("fast time (ms)")
    ax[1].set_title("raw current (scan x fast time)")
    return _save(fig, path)


def scene_figure(imgs, paper, design, path):
    """Extended scene: plain image, eq-19 fringes, interferogram phase, the paper-order image.

    Parameters
    ----------
    imgs, paper : DLImages
        Focus-then-add and paper-order images.
    design : DLDesign
    path : path

    Returns
    -------
    Path
    """
    fig, ax = _subplots(1, 4, figsize=(18, 5.0))
    ext = _ext(imgs)
    ref = np.abs(imgs.forward).max()
    im = ax[0].imshow(_db(imgs.forward, ref).T, origin="lower", extent=ext, cmap="gray", vmin=-30, vmax=0)
    ax[0].set_title("plain DL-SAL image\n(forward scans), dB", fontsize=10)
    fig.colorbar(im, ax=ax[0], label="dB", shrink=0.8)
    lim = np.abs(imgs.combined.real).max()
    im = ax[1].imshow(imgs.combined.real.T, origin="lower", extent=ext, cmap="RdBu_r", vmin=-lim, vmax=lim)
    ax[1].set_title(f"eq 19: forward + backward (real part)\nfringe period {design.fringe_period_x * 1e3:.0f} mm",
                    fontsize=10)
    fig.colorbar(im, ax=ax[1], label="amplitude", shrink=0.8)
    ifg = imgs.forward * np.conj(imgs.backward)
    im = ax[2].imshow(np.angle(ifg).T, origin="lower", extent=ext, cmap="twilight", vmin=-np.pi, vmax=np.pi)
    ax[2].set_title("interferogram phase\nforward x conj(backward)", fontsize=10)
    fig.colorbar(im, ax=ax[2], label="rad", shrink=0.8)
    im = ax[3].imshow(_db(paper.combined, ref * 2).T, origin="lower", extent=ext, cmap="gray", vmin=-30, vmax=0)
    ax[3].set_title("paper order (eq 16 then eq 17), dB:\nbackward scans not focused", fontsize=10)
    fig.colorbar(im, ax=ax[3], label="dB", shrink=0.8)
    for a in ax:
        a.set_xlabel("along track (m)")
        a.set_ylabel("cross track (m)")
    return _save(fig, path)


def terrain_figures(ter, design, exp, out):
    """Terrain height, its image, interferogram, unwrapped residual, contour map, ground fringe.

    Parameters
    ----------
    ter : dict
        :func:`salkit.systems.downlooking.terrain_run`.
    design : DLDesign
    exp : DownlookingExperiment
    out : path
        Folder.

    Returns
    -------
    Path
    """
    imgs = ter["images"]
    ext = _ext(imgs)
    gext = [ter["ground_x"][0], ter["ground_x"][-1], ter["ground_y"][0], ter["ground_y"][-1]]
    fig, ax = _subplots(2, 3, figsize=(17, 10))
    a = ax[0, 0]
    im = a.imshow(ter["ground_z"].T, origin="lower", extent=gext, cmap="terrain")
    a.set_title("true terrain height\n(ground coordinates)")
    fig.colorbar(im, ax=a, label="m")
    a.set_xlabel("along track (m)")
    a.set_ylabel("across track, ground (m)")
    a = ax[0, 1]
    im = a.imshow(_db(imgs.forward, np.percentile(np.abs(imgs.forward), 99.5)).T, origin="lower", extent=ext,
                  cmap="gray", vmin=-25, vmax=0)
    a.set_title(f"DL-SAL image at {exp.terrain_look_angle_deg:g} deg look")
    fig.colorbar(im, ax=a, label="dB")
    a = ax[0, 2]
    im = a.imshow(ter["wrapped"].T, origin="lower", extent=ext, cmap="twilight", vmin=-np.pi, vmax=np.pi)
    a.set_title("interferogram: wrapped phase\n(straight fringes)")
    fig.colorbar(im, ax=a, label="rad")
    a = ax[1, 0]
    im = a.imshow(ter["ground_fringe"].T, origin="lower", extent=gext, cmap="RdBu_r")
    a.set_title("what Fig. 2 pictures: fringe phase on the\nterrain, ground coordinates, minus flat ground")
    fig.colorbar(im, ax=a, label="rad")
    a.set_xlabel("along track (m)")
    a.set_ylabel("across track, ground (m)")
    a = ax[1, 1]
    v = ter["valid"]
    h, r = ter["h_true"][v], ter["residual"][v]
    pick = np.random.default_rng(0).choice(h.size, size=min(h.size, 4000), replace=False)
    a.plot(h[pick], r[pick], ".", ms=2, alpha=0.4, label="SAL interferogram minus flat carrier")
    hh = np.linspace(0, h.max(), 10)
    model = ter["metrics"]["terrain_phase_per_height_model_rad_per_m"]
    a.plot(hh, model * hh, "r-", label=f"fringe-projection model ({model:.1f} rad/m)")
    a.plot(hh, ter["metrics"]["terrain_phase_per_height_rad_per_m"] * hh, "k--",
           label=f"fit ({ter['metrics']['terrain_phase_per_height_rad_per_m']:.2f} rad/m)")
    a.set_xlabel("true height of the pixel's surface (m)")
    a.set_ylabel("phase (rad)")
    a.set_title(f"phase against height ({exp.unwrap} unwrap)")
    a.legend(fontsize=8)
    a = ax[1, 2]
    ht, hr = ter["h_true_map"], ter["h_rec_map"]
    top = max(float(np.nanmax(ht)), 1e-3)
    levels = np.linspace(0.1 * top, top, 8)
    cs1 = a.contour(imgs.y, imgs.x, ht.T, levels=levels, colors="tab:green", linewidths=0.9)
    a.clabel(cs1, fontsize=7, fmt="%.2f")
    rms = float(np.sqrt(np.nanmean(hr ** 2)))
    if np.nanmax(hr) >= levels[0]:
        a.contour(imgs.y, imgs.x, hr.T, levels=levels, colors="tab:red", linewidths=1.0)
        a.set_title(f"contour map: true height (green, m)\nrecovered from the fringes (red): RMS {rms:.3f} m")
    else:  # nothing to draw: say so rather than promise red lines
        a.set_title(f"contour map: true height (green, m); the height\nrecovered from the fringes is flat "
                    f"(RMS {rms:.3f} m, below\nthe lowest contour): no red contour to draw", fontsize=10)
    a.set_xlim(ext[0], ext[1])
    a.set_ylim(ext[2], ext[3])
    for aa in (ax[0, 1], ax[0, 2], ax[1, 2]):
        aa.set_xlabel("along track (m)")
        aa.set_ylabel("cross track, image (m)")
    return _save(fig, out / "terrain.png")


def disturbance_figure(images, path):
    """Point-target images (dB) under each disturbance, DL-SAL and side-looking SAL.

    Parameters
    ----------
    images : dict
    path : path

    Returns
    -------
    Path
    """
    n = len(images)
    fig, ax = _subplots(1, n, figsize=(3.4 * n + 1.0, 4.4))
    ax = np.atleast_1d(ax)
    im = None
    for a, (title, (obj, arr)) in zip(ax, images.items()):
        if arr is not None:
            img, y, x = arr, obj.y, obj.x
        else:
            img, y, x = obj["image"].values, obj["azimuth"].values, obj["range"].values
        im = a.imshow(_db(img, np.abs(img).max()).T, origin="lower", extent=[y[0], y[-1], x[0], x[-1]], cmap="gray",
                      vmin=-35, vmax=0)
        a.set_title(textwrap.fill(title, 30), fontsize=8)
        a.set_xlabel("along track (m)")
        a.set_ylabel("cross track (m)")
    fig.colorbar(im, ax=ax, shrink=0.8, label="dB (each panel's peak = 0)")
    return _save(fig, path)
