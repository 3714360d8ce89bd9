"""Autofocus of a formed image: ``autofocus(image, method)`` removes the image's deterministic
phase (see docs/data-format.md) so that the azimuth transform is the aperture domain, estimates
and removes the azimuth phase error (PGA or minimum entropy), puts the deterministic phase back
and returns the image with its history; :func:`history_metrics` flattens that history."""
from __future__ import annotations

import numpy as np
import xarray as xr

from ..choices import AUTOFOCUS_METHODS, IMAGE_AUTOFOCUS_METHODS
from ..errors import ScenarioError
from ..metrics.measure import image_phase_model
from .pga import KERNELS, AutofocusResult, min_entropy, pga

#: Autofocus methods (``processing.autofocus``) and those that work on a formed image.
METHODS = AUTOFOCUS_METHODS
IMAGE_METHODS = IMAGE_AUTOFOCUS_METHODS


def autofocus(image: xr.Dataset, method: str = "pga", kernel: str = "lumv", max_iter: int = 30,
              tol: float = 0.01) -> tuple[xr.Dataset, AutofocusResult]:
    """Autofocus a salkit image dataset.

    Parameters
    ----------
    image : xarray.Dataset
        Focused image (``image`` variable, azimuth first).
    method : {"pga", "min-entropy", "none"}
    kernel : {"pd", "lumv", "ev"}
        PGA phase-gradient kernel.
    max_iter : int
        PGA iterations at most (stops earlier when converged).
    tol : float
        PGA convergence: RMS of an iteration's correction, rad.

    Returns
    -------
    (xarray.Dataset, AutofocusResult)
        The corrected image (attributes ``autofocus``, ``autofocus_kernel``) and the result with
        the per-iteration history (phase RMS in rad, entropy in nats).
    """

    if method == "pulse":
        raise ScenarioError("processing.autofocus", method, "pulse autofocus works on the phase history, "
                            "not an image: use salkit.autofocus.pulse_autofocus(raw)")
    if method not in METHODS:
        raise ScenarioError("processing.autofocus", method, f"must be one of {METHODS}")
    if kernel not in KERNELS:
        raise ScenarioError("processing.autofocus_kernel", kernel, f"must be one of {KERNELS}")
    img = np.asarray(image["image"].values, dtype=np.complex128)
    if method == "none":
        return image, AutofocusResult(image=img, phase=np.zeros(img.shape[0]))
    fn = image_phase_model(image)
    az = image["azimuth"].values
    rg = image["range"].values
    psi = fn(az[:, None], rg[None, :]) if fn is not None else np.zeros(img.shape)
    flat = img * np.exp(-1j * psi)
    if method == "pga":
        res = pga(flat, kernel=kernel, max_iter=max_iter, tol=tol)
    else:
        res = min_entropy(flat)
    out = image.copy()
    out["image"] = (("azimuth", "range"), (res.image * np.exp(1j * psi)).astype(np.complex64),
                    image["image"].attrs)
    out.attrs["autofocus"] = method
    out.attrs["autofocus_kernel"] = kernel if method == "pga" else ""
    out.attrs["autofocus_iterations"] = len(res.history) - 1
    return out, res


def history_metrics(res: AutofocusResult, prefix: str = "autofocus") -> dict:
    """Flat numbers for metrics.json: per-iteration phase RMS and entropy, and the summary.

    Parameters
    ----------
    res : AutofocusResult
    prefix : str
        Key prefix.

    Returns
    -------
    dict
        Phase RMS (rad), entropy (nats), iterations.
    """
    out = {f"{prefix}_iterations": len(res.history) - 1, f"{prefix}_converged": int(res.converged),
           f"{prefix}_best_iteration": res.best_iteration}
    for h in res.history:
        out[f"{prefix}_entropy_{h['iteration']}"] = h["entropy"]
        out[f"{prefix}_phase_rms_{h['iteration']}"] = h["phase_rms"]
    return out
