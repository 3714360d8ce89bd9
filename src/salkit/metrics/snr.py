"""Signal-to-noise estimators of intensity images and their stacks (seed 001, eqs 14-16)."""
from __future__ import annotations

import math

import numpy as np


def split_snr(intensities: np.ndarray, mask: np.ndarray, noise_power: float) -> float:
    """SNR of the mean of independent intensity images: (mean - noise power) over the standard
    deviation of the random part, estimated from two independent half-stacks (odd and even):
    std((A - B)/2). The target's deterministic intensity pattern (edges, structure, sidelobes)
    cancels in A - B, so only speckle and noise are counted, as in eqs 14-16.

    Parameters
    ----------
    intensities : float (K, ny, nx)
        Independent intensity images.
    mask : bool (ny, nx)
        Pixels of a uniform region.
    noise_power : float
        Mean noise intensity per pixel.

    Returns
    -------
    float
    """
    A = intensities[0::2].mean(axis=0)
    B = intensities[1::2].mean(axis=0)
    full = intensities.mean(axis=0)
    rand = float(np.std((A - B)[mask])) / 2 * math.sqrt(
        4 * len(intensities[0::2]) * len(intensities[1::2]) / len(intensities) ** 2)
    return float((full[mask].mean() - noise_power) / rand)


def stack_snr(stacked_intensity: np.ndarray, clean_intensity: np.ndarray, mask: np.ndarray) -> float:
    """SNR of a (stacked) intensity image against the truth: mean signal intensity / std.

    Parameters
    ----------
    stacked_intensity : float (ny, nx)
    clean_intensity : float (ny, nx)
        Noise-free intensity of the same scene.
    mask : bool (ny, nx)

    Returns
    -------
    float
    """
    return float(clean_intensity[mask].mean() / stacked_intensity[mask].std())
