"""Image-level measures: entropy, contrast, signal-to-noise ratio against a known truth."""
from __future__ import annotations

import numpy as np


def entropy(image: np.ndarray) -> float:
    """Shannon entropy of the normalised intensity, -sum p ln p with p = |I|^2 / sum |I|^2 (nats).

    Parameters
    ----------
    image : complex ndarray

    Returns
    -------
    float
        nats.

    Examples
    --------
    >>> round(entropy(np.ones(4)), 4)  # uniform over 4 pixels: ln 4
    1.3863
    """
    p = np.abs(image).astype(np.float64) ** 2
    s = p.sum()
    if s <= 0:
        return 0.0
    p = p[p > 0] / s
    return float(-(p * np.log(p)).sum())


def contrast(image: np.ndarray) -> float:
    """Intensity contrast std(|I|^2) / mean(|I|^2).

    Parameters
    ----------
    image : complex ndarray

    Returns
    -------
    float
    """
    p = np.abs(image).astype(np.float64) ** 2
    m = p.mean()
    return float(p.std() / m) if m > 0 else 0.0


def snr_against_truth(image: np.ndarray, truth: np.ndarray, mask: np.ndarray | None = None) -> float:
    """Speckle-image SNR: mean signal intensity over the standard deviation of the measured intensity.

    Parameters
    ----------
    image : complex ndarray
        Noisy focused image.
    truth : complex ndarray
        The noise-free focused image of the same scene (same speckle realisation).
    mask : bool ndarray, optional
        Pixels of a uniform region; default where the truth intensity exceeds half its mean.

    Notes
    -----
    For a fully developed speckle cell of mean intensity S plus circular Gaussian noise N the
    measured intensity has standard deviation S + N, so this SNR is S/(S + N) = CNR/(1 + CNR),
    seed 001 eq 14.

    Returns
    -------
    float
    """
    ti = np.abs(truth) ** 2
    if mask is None:
        mask = ti > 0.5 * ti.mean()
    s = ti[mask].mean()
    sd = (np.abs(image[mask]) ** 2).std()
    return float(s / sd) if sd > 0 else float("inf")


def noise_power(image: np.ndarray, truth: np.ndarray) -> float:
    """Mean noise power per pixel, |image - truth|^2.

    Parameters
    ----------
    image, truth : complex ndarray

    Returns
    -------
    float
    """
    return float(np.mean(np.abs(image - truth) ** 2))
