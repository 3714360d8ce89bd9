"""Accuracy against the exact truth: every image former on the test geometries users bring
(salkit.simulate.testbeds), error energy against the exact float64 matched filter
(salkit.focus.exact), the 99th percentile of the phase error over the pixels within 30 dB of the
peak, and the time, in one run.

Scenes: speckle (1 % of the scatterers 30 times brighter) over the grid; on large grids the truth
is evaluated on every k-th azimuth row (an unbiased sample of the error energy). The wide-angle
arc is also run from 101^2 to 2001^2 pixels (the error must not grow with the scene), with pulses
and frequencies sampling each grid without ambiguity and, ``_p469``, with the issue's 469 pulses
(aliased in azimuth beyond 108 m, consistently for every former and the truth).

``python benchmarks/run_all.py accuracy`` runs it; ``python benchmarks/accuracy.py`` prints the
markdown table of docs/performance.md.
"""
from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: (name, geometry factory, grid size, truth on every k-th row)
CASES = [
    ("wide4_level_ground_101", lambda t: t.wide_angle(4.0, 0.0, "ground"), 101, 1),
    ("wide4_climb_ground_101", lambda t: t.wide_angle(4.0, 0.5, "ground"), 101, 1),
    ("wide4_climb_ground_501", lambda t: t.wide_angle(4.0, 0.5, "ground", n=501), 501, 4),
    ("wide4_climb_ground_1001", lambda t: t.wide_angle(4.0, 0.5, "ground", n=1001), 1001, 8),
    ("wide4_climb_ground_2001", lambda t: t.wide_angle(4.0, 0.5, "ground", n=2001), 2001, 32),
    ("wide4_climb_ground_1001_p469", lambda t: t.wide_angle(4.0, 0.5, "ground", n=1001, pulses=469), 1001, 8),
    ("wide4_climb_ground_2001_p469", lambda t: t.wide_angle(4.0, 0.5, "ground", n=2001, pulses=469), 2001, 32),
    ("wide4_level_ground_501", lambda t: t.wide_angle(4.0, 0.0, "ground", n=501), 501, 4),
    ("wide4_climb_slant_501", lambda t: t.wide_angle(4.0, 0.5, "slant", n=501), 501, 4),
    ("wide10_climb_ground_501", lambda t: t.wide_angle(10.0, 0.5, "ground", n=501), 501, 4),
    ("wide30_climb_ground_501", lambda t: t.wide_angle(30.0, 0.5, "ground", n=501), 501, 8),
    ("wide60_climb_slant_501", lambda t: t.wide_angle(60.0, 0.5, "slant", n=501), 501, 8),
    ("seed_5km_256", lambda t: t.seed("5km", 256), 256, 2),
    ("seed_200km_256", lambda t: t.seed("200km", 256), 256, 2),
    ("seed_560km_256", lambda t: t.seed("560km", 256), 256, 2),
    ("curved_ground_501", lambda t: t.curved(0.5, "ground"), 501, 4),
]
#: (label, former, keyword arguments): bp at its settings (6x profiles and fitted taps, 8x at high),
#: and 0.19.0's bp (16x profiles read linearly; 32x at high) through the library's linear interpolation
FORMERS = [("bp", "bp", {}), ("bp_high", "bp", {"upsample": 8}), ("ffbp", "ffbp", {}),
           ("ffbp_high", "ffbp", {"accuracy": "high"}), ("pfa", "pfa", {}),
           ("linear_16x", "linear", {"upsample": 16}), ("linear_32x", "linear", {"upsample": 32})]


def _case(tb, n, every):
    from salkit.focus import phase_history
    from salkit.focus.exact import exact_image
    from salkit.focus.formers import ImageGrid
    density = 0.15 if n <= 501 else (0.03 if n <= 1001 else 0.01)
    pts, amp = tb.speckle(n, extent=1.0, density=density, seed=1)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(n))
    rows = np.arange(every // 2, n, every)
    ro = ig.plane.points(ig.azimuth[rows], np.zeros(rows.size))
    t0 = time.perf_counter()
    truth = exact_image(ph.data, ph.freq, ph.positions, ph.reference_range, ro, ig.plane.range, ig.range)
    return ph, ig, rows, truth, time.perf_counter() - t0


def bench_accuracy(cases=None):
    """Error (dB) against the truth, 99th-percentile bright-pixel phase error (deg) and time (s)
    of each former on each geometry."""
    from salkit.errors import ScenarioError
    from salkit.focus.bp import backprojection_former
    from salkit.focus.formers import get_former
    from salkit.signals.windows import Window
    from salkit.simulate import testbeds
    out = {}
    for name, make, n, every in cases or CASES:
        ph, ig, rows, truth, t_truth = _case(make(testbeds), n, every)
        out[f"acc_{name}_truth_s_per_row"] = t_truth / rows.size
        a = np.abs(truth)
        sel = a >= a.max() * 10 ** (-30 / 20)
        for label, alg, kw in FORMERS:
            former = backprojection_former(alg)[0] if alg == "linear" else get_former(alg)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    former(ph, ig, Window("none"), **kw)  # compiled, warm
                except ScenarioError as e:  # a former that refuses the geometry (PFA over a wide arc)
                    out[f"acc_{name}_{label}_refused"] = str(e)
                    continue
                t0 = time.perf_counter()
                img = former(ph, ig, Window("none"), **kw).image[rows]
                dt = time.perf_counter() - t0
            err = np.sum(np.abs(img - truth) ** 2) / np.sum(np.abs(truth) ** 2)
            ph_err = np.degrees(np.abs(np.angle(img[sel] * np.conj(truth[sel]))))
            out[f"acc_{name}_{label}_error_db"] = float(10 * np.log10(err))
            out[f"acc_{name}_{label}_phase_p99_deg"] = float(np.percentile(ph_err, 99))
            out[f"acc_{name}_{label}_s"] = dt
    return out


def table(res: dict) -> str:
    """Markdown table: geometry rows, former columns, 'error dB / p99 phase deg / s'."""
    names = [c[0] for c in CASES if f"acc_{c[0]}_bp_error_db" in res]
    head = "| geometry | " + " | ".join(f[0] for f in FORMERS) + " |"
    lines = [head, "|---" * (len(FORMERS) + 1) + "|"]
    for nm in names:
        cells = []
        for label, _, _ in FORMERS:
            if f"acc_{nm}_{label}_refused" in res:
                cells.append("refused")
                continue
            e, p, s = (res[f"acc_{nm}_{label}_{k}"] for k in ("error_db", "phase_p99_deg", "s"))
            cells.append(f"{e:.1f} dB / {p:.2f} deg / {s:.2f} s")
        lines.append(f"| {nm} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    r = bench_accuracy()
    print(table(r))
