"""Phase utilities."""
from __future__ import annotations

import numpy as np


def wrap(phase):
    """Wrap phase (rad) into [-pi, pi).

    Parameters
    ----------
    phase : float or array
        rad.

    Returns
    -------
    ndarray
        rad.

    Examples
    --------
    >>> wrap([3 * np.pi / 2, -np.pi]).round(4).tolist()
    [-1.5708, -3.1416]
    """
    return (np.asarray(phase) + np.pi) % (2 * np.pi) - np.pi
