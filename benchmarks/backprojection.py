"""backprojection: salkit (numba) vs a straightforward NumPy backprojection (loop over pulses,
vectorised over pixels), on the same phase history and grid; images compared.

``make bench NAME=backprojection`` (or ``python benchmarks/backprojection.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
from common import C, best_of, spotlight_problem


def numpy_backprojection(ph, plane, az, rg, upsample=8):
    """The common Python SAR way: loop over pulses, vectorise over pixels, np.interp the profile."""
    P, M = ph.data.shape
    df = ph.freq[1] - ph.freq[0]
    nfft = M * upsample
    prof = np.fft.fftshift(np.fft.ifft(ph.data, n=nfft, axis=1) * nfft, axes=1)
    # the ifft above puts sample m at index m; shift so the centre frequency is the reference
    prof *= np.exp(-2j * np.pi * (M // 2) * np.arange(nfft) / nfft)[None, :] * (-1) ** (M // 2)
    dr = C / (2 * df * nfft)
    r_axis = (np.arange(nfft) - nfft // 2) * dr
    X = plane.points(az[:, None], rg[None, :]).reshape(-1, 3)
    x, y, z = (np.ascontiguousarray(X[:, i]) for i in range(3))
    k = 4 * np.pi * ph.freq[M // 2] / C
    img = np.zeros(X.shape[0], np.complex128)
    for p in range(P):
        px, py, pz = ph.positions[p]
        dR = np.sqrt((x - px) ** 2 + (y - py) ** 2 + (z - pz) ** 2) - ph.reference_range[p]
        img += np.interp(dR, r_axis, prof[p]) * np.exp(1j * k * dR)
    return img.reshape(az.size, rg.size) / (P * M)


def bench_backprojection(n_pix=512, n_pulses=512):
    from salkit.focus.bp_kernel import backproject
    from salkit.geometry.collection import grid_axes, plane_from
    sc, ph = spotlight_problem(n_pix, n_pulses)
    g = sc.processing.grid
    plane = plane_from(ph.track, ph.center_position, "slant")
    az, rg = grid_axes(g)
    W = np.ones((az.size, ph.data.shape[0]), np.float32)
    ro = plane.points(az, np.zeros_like(az))
    wr = np.ones(ph.data.shape[1])
    run = lambda: backproject(ph.data, ph.freq, ph.positions, ph.reference_range, ro, plane.range, rg, W, wr)  # noqa: E731
    run()  # compile
    t_s, img_s = best_of(run, 3)
    t_n, img_n = best_of(lambda: numpy_backprojection(ph, plane, az, rg), 1)
    img_s = img_s / (ph.data.shape[0] * ph.data.shape[1])
    corr = abs(np.vdot(img_s, img_n)) / (np.linalg.norm(img_s) * np.linalg.norm(img_n))
    pp = az.size * rg.size * ph.data.shape[0]
    return {"bp_pixels": az.size * rg.size, "bp_pulses": ph.data.shape[0], "bp_salkit_s": t_s, "bp_numpy_s": t_n,
            "bp_salkit_pixel_pulses_per_s": pp / t_s, "bp_numpy_pixel_pulses_per_s": pp / t_n,
            "bp_speedup_vs_numpy": t_n / t_s, "bp_image_correlation": float(corr)}


if __name__ == "__main__":
    import runner
    runner.main(["backprojection"])
