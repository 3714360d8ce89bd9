"""Figures of the space-borne GEO system (seed 001): the stack and its SNR curve, the coherent
stack, resolution against squint, the trajectory study."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .canvas import _log_ticks, _save, _subplots


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
