"""Space-borne SAL of a GEO target (seed 001): squinted sub-apertures and incoherent stacking.

Sub-aperture p of the collection is centred at along-track offset u_p = L0 tan(theta_p) on the
straight-line model (or the true relative trajectory), has length L_sa and forms one sub-image
by backprojection onto the common target-frame grid: exact for any squint, so the sub-image is
already geometrically corrected (eq 11 maps the squinted slant frame to this one). Each
sub-aperture has its own photon noise; the scene's scatterers are the same physical target, so
its speckle decorrelates between sub-apertures through the change of aspect alone.
"""
from __future__ import annotations

import math

import numpy as np

from ..focus import focus
from ..params.models import Scenario
from ..simulate import simulate


def squint_of(index: int, count: int, squint_max_deg: float) -> float:
    """Squint (deg) of sub-aperture ``index`` of ``count`` spread evenly over +-squint_max."""
    if count == 1:
        return 0.0
    return -squint_max_deg + 2 * squint_max_deg * (index + 0.5) / count


def subaperture(base: Scenario, squint_deg: float, noise_seed: int) -> Scenario:
    """The scenario of one sub-aperture: same target and grid, its squint, its own noise seed."""
    p = base.platform.model_copy(update={"squint_deg": squint_deg})
    return base.model_copy(update={"platform": p, "seed": noise_seed})


def subimage(base: Scenario, squint_deg: float, noise_seed: int, noise: bool = True) -> np.ndarray:
    """Complex sub-image on the common target grid. The scene (speckle) uses ``base.seed``; the
    photon noise uses ``noise_seed``."""
    sc = subaperture(base, squint_deg, base.seed)
    rng = np.random.default_rng(base.seed)
    from ..simulate.scene import build_scatterers  # noqa: F401  (same scene: same seed first)
    raw = simulate(sc, noise=False, rng=rng)
    if noise and base.receiver.noise.enabled:
        from ..simulate import photon_noise
        sig = raw["signal"].values.copy()
        photon_noise(sig, base.receiver.noise, np.random.default_rng(10_000_019 + noise_seed))
        raw["signal"].values[...] = sig
    return focus(raw, sc.processing)["image"].values


def stack(base: Scenario, count: int, squint_max_deg: float, noise: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Incoherent stack (mean intensity) of ``count`` sub-images, and the first sub-image."""
    acc = None
    first = None
    for i in range(count):
        img = subimage(base, squint_of(i, count, squint_max_deg), i, noise)
        first = img if first is None else first
        acc = np.abs(img) ** 2 if acc is None else acc + np.abs(img) ** 2
    return acc / count, first


def stack_snr(stacked_intensity: np.ndarray, clean_intensity: np.ndarray, mask: np.ndarray) -> float:
    """SNR of a (stacked) intensity image against the truth: mean signal intensity / std."""
    return float(clean_intensity[mask].mean() / stacked_intensity[mask].std())


del math
