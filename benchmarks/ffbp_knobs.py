"""ffbp_knobs: the accuracy-speed curve of fast factorised backprojection over the polar-grid
oversampling and the leaf size at 1024^2 (the error against direct BP, the time).

``make bench NAME=ffbp_knobs`` (or ``python benchmarks/ffbp_knobs.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
from common import best_of, ffbp_problem


def bench_ffbp_knobs(n=1024):
    """The accuracy knobs: image error against direct BP, and time (best of 3), over the polar
    oversampling (angle x range) and the leaf size (pulses per first-level sub-image)."""
    from salkit.focus.bp_kernel import backproject
    from salkit.focus.ffbp import LEAF_PULSES, OVERSAMPLE_ANGLE, OVERSAMPLE_RANGE, ffbp
    from salkit.focus.formers import ImageGrid
    ph, f, pos, ref, grid = ffbp_problem(n)
    plane, az, rg, M = grid.plane, grid.azimuth, grid.range, ph.shape[1]
    ref_img = backproject(ph, f, pos, ref, plane.points(az, 0 * az), plane.range, rg, np.ones((n, n), np.float32),
                          np.ones(M))
    out = {}
    cases = [(oa, orr, LEAF_PULSES) for oa, orr in ((1.5, 1.5), (1.6, 1.6), (1.75, 1.75), (2.0, 1.75), (2.0, 2.0),
                                                   (2.5, 2.5), (3.0, 3.0))]
    cases += [(OVERSAMPLE_ANGLE, OVERSAMPLE_RANGE, leaf) for leaf in (8, 32, 64)]
    for oa, orr, leaf in cases:
        kw = dict(oversample_angle=oa, oversample_range=orr, leaf=leaf)
        ffbp(ph[:256], f, pos[:256], ref[:256], ImageGrid(plane, az[:32], rg[:32], grid.spec), np.ones(256),
             np.ones(M), **kw)
        dt, (img, _) = best_of(lambda: ffbp(ph, f, pos, ref, grid, np.ones(n), np.ones(M), **kw), 3)
        err = np.sum(np.abs(ref_img - img) ** 2) / np.sum(np.abs(ref_img) ** 2)
        key = f"ffbp_knob_{oa:g}x{orr:g}_leaf{leaf}"
        out[f"{key}_error_db"] = float(10 * np.log10(err))
        out[f"{key}_s"] = dt
    return out


if __name__ == "__main__":
    import runner
    runner.main(["ffbp_knobs"])
