"""Image-level measures: entropy, contrast, signal-to-noise ratio against a known truth."""
from __future__ import annotations

import numpy as np

from ..io.reading import blocks


ROWS_A_BLOCK_BYTES = 4 << 20  # an image is visited a block of about this many bytes of pixels at a time
_SUB_BYTES = 1 << 20  # a block is measured this many bytes of pixels at a time (bounded temporaries)


def _pieces(image, rows: int | None = None):
    """(row, column, piece) of ``image`` (:func:`salkit.io.datasets.blocks`: about
    ``ROWS_A_BLOCK_BYTES`` a block, whole chunks of a file), each block cut into pieces of about 1 MiB
    of pixels, so that a measure over the whole image holds bounded temporaries."""
    target = rows * 8 * int(image.shape[1]) if rows else ROWS_A_BLOCK_BYTES
    for a, b, blk in blocks(image, target_bytes=target):
        sub = max(1, _SUB_BYTES // max(1, 8 * blk.shape[1]))
        for c in range(0, blk.shape[0], sub):
            yield a + c, b, blk[c:c + sub]


def scan(image, rows: int | None = None) -> tuple[tuple[int, int], dict]:
    """One pass over an image, a block at a time (bounded memory; an image opened lazily is read
    once, a chunk at a time): the brightest pixel and the intensity moments of p = |I|^2 (``n``
    pixels, ``s1`` sum p, ``s2`` sum p^2, ``slog`` sum p ln p over p > 0), from which
    :func:`entropy_from_moments` and :func:`contrast_from_moments` follow.

    Parameters
    ----------
    image : complex array-like (nx, ny)
        In memory, or lazily read (an ``xarray.DataArray`` of an open file).
    rows : int, optional
        Rows a block; default about 4 MiB of pixels.

    Returns
    -------
    ((int, int), dict)
        Indices of the brightest pixel, and the moments.

    Examples
    --------
    >>> scan(np.array([[1, 2], [5j, 0]]))[0]
    (1, 0)
    """
    best, at = -1.0, (0, 0)
    n, s1, s2, slog = 0, 0.0, 0.0, 0.0
    for a, b, blk in _pieces(image, rows):
        p = np.abs(blk).astype(np.float64) ** 2
        k = int(np.argmax(p))
        if p.flat[k] > best:
            best, at = float(p.flat[k]), (a + k // blk.shape[1], b + k % blk.shape[1])
        n += p.size
        s1 += float(p.sum())
        s2 += float(np.square(p).sum())
        q = p[p > 0]
        slog += float((q * np.log(q)).sum())
    return at, {"n": n, "s1": s1, "s2": s2, "slog": slog}


def brightest_pixel(image, rows: int | None = None) -> tuple[int, int]:
    """Indices of the brightest pixel (:func:`scan`).

    Parameters
    ----------
    image : complex array-like (nx, ny)
    rows : int, optional

    Returns
    -------
    (int, int)
    """
    return scan(image, rows)[0]


def intensity_moments(image, rows: int | None = None) -> dict:
    """Sums over the image's intensity p = |I|^2 (:func:`scan`): an image written tile by tile is
    measured in one pass, equal to the in-memory figures to rounding.

    Parameters
    ----------
    image : complex array-like (nx, ny)
    rows : int, optional

    Returns
    -------
    dict
    """
    return scan(image, rows)[1]


def entropy_from_moments(mom: dict) -> float:
    """Entropy (nats) from :func:`intensity_moments`: ln S - (sum p ln p) / S, S = sum p.

    Parameters
    ----------
    mom : dict
        :func:`intensity_moments`.

    Returns
    -------
    float
        nats.
    """
    s = mom["s1"]
    return float(np.log(s) - mom["slog"] / s) if s > 0 else 0.0


def contrast_from_moments(mom: dict) -> float:
    """Contrast std(p) / mean(p) from :func:`intensity_moments`.

    Parameters
    ----------
    mom : dict
        :func:`intensity_moments`.

    Returns
    -------
    float
        Dimensionless.
    """
    if mom["n"] == 0 or mom["s1"] <= 0:
        return 0.0
    m = mom["s1"] / mom["n"]
    return float(np.sqrt(max(mom["s2"] / mom["n"] - m * m, 0.0)) / m)


def entropy(image: np.ndarray) -> float:
    """Shannon entropy of the normalised intensity, -sum p ln p with p = |I|^2 / sum |I|^2 (nats).

    Parameters
    ----------
    image : complex ndarray

    Returns
    -------
    float
        nats. Computed a block of rows at a time (:func:`intensity_moments`).

    Examples
    --------
    >>> round(entropy(np.ones(4)), 4)  # uniform over 4 pixels: ln 4
    1.3863
    """
    return entropy_from_moments(intensity_moments(np.atleast_2d(image)))


def contrast(image: np.ndarray) -> float:
    """Intensity contrast std(|I|^2) / mean(|I|^2).

    Parameters
    ----------
    image : complex ndarray

    Returns
    -------
    float
    """
    return contrast_from_moments(intensity_moments(np.atleast_2d(image)))


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
