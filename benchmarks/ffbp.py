"""ffbp: fast factorised backprojection against direct backprojection at 512^2, 1024^2 and 4096^2
pixels (as many pulses), direct BP timed on a block of rows and scaled, both the best of the same
number of runs. Direct BP at the default former's settings (``bp``: 6x profiles, four fitted taps),
and at 0.19.0's (16x profiles, linear interpolation: ``_linear16``).

``make bench NAME=ffbp`` (or ``python benchmarks/ffbp.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
from common import best_of, ffbp_problem


def bench_ffbp(sizes=((512, None, 3), (1024, 256, 3), (4096, 128, 2))):
    """Fast factorised backprojection against direct backprojection on the same data (N x N pixels,
    N pulses): direct BP timed on blocks of R and 2 rows around the centre, its per-row cost
    extrapolated to the image (the range profiles, a fixed cost, counted once), FFBP on the whole
    image; both the best of the same number of runs (the VM's spread is +-15 %); the image error
    energy on the block."""
    from salkit.focus.bp_kernel import backproject
    from salkit.focus.ffbp import ffbp
    from salkit.registry import FORMERS
    default = {"interpolation": "fitted", "upsample": FORMERS["bp"].upsample["standard"]}
    out = {}
    for n, rows, repeat in sizes:
        ph, f, pos, ref, grid = ffbp_problem(n)
        plane, az, rg, M = grid.plane, grid.azimuth, grid.range, ph.shape[1]
        t_f, (img, info) = best_of(lambda: ffbp(ph, f, pos, ref, grid, np.ones(n), np.ones(M)), repeat)
        rows = rows or n

        def direct(k, kw):
            sub = slice(n // 2 - k // 2, n // 2 + k // 2)
            a = az[sub]
            t, im = best_of(lambda: backproject(ph, f, pos, ref, plane.points(a, 0 * a), plane.range, rg,
                                                np.ones((a.size, n), np.float32), np.ones(M), **kw), repeat)
            return t, im, sub

        out.update({f"ffbp_{n}_s": t_f, f"ffbp_{n}_levels": info["ffbp_levels"],
                    f"ffbp_{n}_polar_samples_per_level": info["ffbp_polar_samples"], f"ffbp_{n}_runs": repeat})
        for tag, kw in (("", default), ("_linear16", {"interpolation": "linear", "upsample": 16})):
            backproject(ph[:8], f, pos[:8], ref[:8], plane.points(az[:2], 0 * az[:2]), plane.range, rg[:8],
                        np.ones((2, 8), np.float32), np.ones(M), **kw)
            t_full, ref_img, sub = direct(rows, kw)
            if rows < n:  # the range profiles cost the same for any number of rows: extrapolate the rest
                t_two, _, _ = direct(2, kw)  # the fixed cost (range profiles) and two rows: the widest lever arm
                per_row = (t_full - t_two) / (rows - 2)
                t_d = t_full + per_row * (n - rows)
            else:
                t_d = t_full
            err = np.sum(np.abs(ref_img - img[sub]) ** 2) / np.sum(np.abs(ref_img) ** 2)
            out.update({f"ffbp_{n}_direct_bp{tag}_s": t_d, f"ffbp_{n}_speedup{tag}": t_d / t_f,
                        f"ffbp_{n}_error{tag}_db": float(10 * np.log10(err))})
    return out


if __name__ == "__main__":
    import runner
    runner.main(["ffbp"])
