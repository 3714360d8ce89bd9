"""ffbp_arcs: fast factorised backprojection over wide arcs and a full circle, against the exact
float64 matched filter: the error, the bright pixels' phase, and the time, formed in parts (each
part on the quarter turn of the grid that looks at the scene from it: ``salkit.focus.ffbp.plan_parts``)
and, up to 170 degrees, as one tree (refused past 180 degrees); direct backprojection's time beside.

The X-band testbed arc (``salkit.simulate.testbeds.wide_angle``: 7 km radius, 7.3 km height,
climbing 0.5 m, ground plane), 2048 pulses, 424 frequencies, 101^2 pixels at 0.8 of the azimuth
resolution over a speckled scene.

``make bench NAME=ffbp_arcs`` (or ``python benchmarks/ffbp_arcs.py``) runs it alone.
"""
from __future__ import annotations

import numpy as np
from common import best_of


def bench_ffbp_arcs(n=101, pulses=2048, arcs=(60.0, 120.0, 170.0, 200.0, 270.0, 360.0)):
    """Per arc and accuracy: error (dB) and p99 phase (deg) against the exact former, time (best of
    2) in parts and as one tree, and direct backprojection's time."""
    from salkit.focus import phase_history
    from salkit.focus.exact import exact_image
    from salkit.focus.ffbp import plan_parts
    from salkit.focus.formers import ImageGrid, get_former
    from salkit.signals.windows import Window
    from salkit.simulate.testbeds import wide_angle
    import salkit.focus.ffbp as ffbp_module
    out = {}
    for arc in arcs:
        tb = wide_angle(arc, 0.5, "ground", pulses=pulses)
        pts, amp = tb.speckle(n, extent=1.0, density=0.15, seed=1)
        ph = phase_history(tb.dataset(pts, amp))
        ig = ImageGrid.of(ph, tb.grid(n))
        ro = ig.plane.points(ig.azimuth, np.zeros_like(ig.azimuth))
        truth = exact_image(ph.data, ph.freq, ph.positions, ph.reference_range, ro, ig.plane.range, ig.range)
        bright = np.abs(truth) >= np.abs(truth).max() * 10 ** (-1.5)
        key = f"arc{arc:g}"
        out[f"{key}_parts"] = len(plan_parts(ph.positions, ph.freq, ig))
        out[f"{key}_bright_pixels"] = int(bright.sum())
        dt, r = best_of(lambda: get_former("bp")(ph, ig, Window("none"), upsample=6), 2)
        out[f"{key}_bp_s"] = dt
        for level in ("standard", "high"):
            for split in (True, False):
                if not split and arc > 170.0:
                    continue
                former = get_former("ffbp")
                inner = ffbp_module.ffbp

                def one_tree(*a, **k):
                    return inner(*a, **{**k, "split": False})
                if not split:
                    ffbp_module.ffbp = one_tree
                try:
                    dt, r = best_of(lambda: former(ph, ig, Window("none"), accuracy=level), 2)
                finally:
                    ffbp_module.ffbp = inner
                err = 10 * np.log10(np.sum(np.abs(r.image - truth) ** 2) / np.sum(np.abs(truth) ** 2))
                p99 = float(np.percentile(np.degrees(np.abs(np.angle(r.image[bright] * np.conj(truth[bright])))), 99))
                how = "parts" if split else "one_tree"
                out[f"{key}_{level}_{how}_error_db"] = float(err)
                out[f"{key}_{level}_{how}_p99_deg"] = p99
                out[f"{key}_{level}_{how}_s"] = dt
    return out


if __name__ == "__main__":
    import runner
    runner.main(["ffbp_arcs"])
