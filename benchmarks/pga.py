"""pga: PGA seconds per iteration at 256 x 256 and 2048 x 2048 (LUMV and eigenvector kernels).

``make bench NAME=pga`` (or ``python benchmarks/pga.py``) runs it alone.
"""
from __future__ import annotations

import time

import numpy as np


def bench_pga(sizes=(256, 2048)):
    """PGA time per iteration (LUMV kernel) on n x n images with a random smooth phase error."""
    from salkit.autofocus.pga import pga
    out = {}
    rng = np.random.default_rng(0)
    for n in sizes:
        refl = (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))) * 0.1
        idx = rng.integers(0, n, (n // 4, 2))
        refl[idx[:, 0], idx[:, 1]] += 8
        k = np.fft.fftfreq(n) * n
        phi = 4.0 * (k / (n / 2)) ** 2
        img = np.fft.ifft(np.fft.fft(refl, axis=0) * np.exp(1j * phi)[:, None], axis=0)
        for kernel in ("lumv", "ev"):
            pga(img[:, :8], kernel=kernel, max_iter=1)
            t0 = time.perf_counter()
            res = pga(img, kernel=kernel, max_iter=10, tol=0.0)
            dt = time.perf_counter() - t0
            out[f"pga_{kernel}_s_per_iteration_N{n}"] = dt / (len(res.history) - 1)
    return out


if __name__ == "__main__":
    import runner
    runner.main(["pga"])
