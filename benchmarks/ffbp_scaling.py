"""ffbp_scaling: FFBP's error against the exact former as the collection grows, on the wide-angle arc
(4 degrees of a 7 km radius at 7.3 km height, climbing 0.5 m; 0.2 m pixels): 1024^2 (the pulses the
grid needs), 4096^2 from 4096 pulses and 8192^2 from 8192 pulses, ground and slant planes.

The scene: unit scatterers with random phases, uniformly over the grid (0.005 a pixel), their phase
history one non-uniform FFT a pulse (salkit.simulate.analytic, about -240 dB against the direct sum). The truth
(salkit.focus.exact, the float64 matched filter of those data) is evaluated on ``rows`` image rows
evenly spread (an unbiased sample of the error energy), holding thousands of pixels within 30 dB
of the peak (counted and printed). (Targets placed on the sampled rows flatter every former by
4 to 5 dB: their main lobes dominate the rows' energy, while the errors spread.) Figures: the error energy over the rows,
the 99th percentile of the phase error of the pixels within 30 dB of the peak, FFBP's time.

``python benchmarks/ffbp_scaling.py [SIZE ...]`` runs it (default 1024 4096).
"""
from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def problem(n: int, plane: str = "ground", rows: int = 8, density: float = 0.005, seed: int = 1,
            bright: float = 0.0, truth: bool = True):
    """The phase history of ``density`` unit scatterers a pixel (random phases, uniformly over the
    grid), the image grid, ``rows`` sampled rows (every n / rows-th, offset) and their truth (None
    without ``truth``)."""
    from salkit.focus import phase_history
    from salkit.focus.exact import exact_image
    from salkit.focus.formers import ImageGrid
    from salkit.simulate import testbeds
    from salkit.simulate.analytic import phase_history_dataset
    tb = testbeds.wide_angle(4.0, 0.5, plane, n=n, pulses=None if n <= 1024 else n)
    rng = np.random.default_rng(seed)
    pl = tb.image_plane()
    K = int(density * n * n)
    a = rng.uniform(-0.5, 0.5, K) * n * tb.dx
    g = rng.uniform(-0.5, 0.5, K) * n * tb.dy
    amp = np.exp(2j * np.pi * rng.random(K))
    amp[rng.random(K) < bright] *= 30.0  # the accuracy benchmark's speckle: a fraction 30 times brighter
    pts = pl.points(a, g)
    t0 = time.perf_counter()
    ds = phase_history_dataset(tb.positions, tb.frequency, pts, amp, attrs={"testbed": tb.name})  # by the NUFFT
    ph = phase_history(ds)
    t_data = time.perf_counter() - t0
    ig = ImageGrid.of(ph, tb.grid(n))
    sel = (np.arange(rows) * n) // rows + n // (2 * rows)
    ro = ig.plane.points(ig.azimuth[sel], np.zeros(sel.size))
    t0 = time.perf_counter()
    truth = exact_image(ph.data, ph.freq, ph.positions, ph.reference_range, ro, ig.plane.range, ig.range) if truth else None
    return ph, ig, sel, truth, {"data_s": t_data, "truth_s": time.perf_counter() - t0, "scatterers": K}


def measure(img_rows: np.ndarray, truth: np.ndarray) -> dict:
    """Error energy (dB), 99th-percentile phase error of the bright pixels (deg) and their count."""
    a = np.abs(truth)
    bright = a >= a.max() * 10 ** (-30 / 20)
    err = np.sum(np.abs(img_rows - truth) ** 2) / np.sum(a ** 2)
    dphi = np.degrees(np.abs(np.angle(img_rows[bright] * np.conj(truth[bright]))))
    return {"error_db": float(10 * np.log10(err)), "phase_p99_deg": float(np.percentile(dphi, 99)),
            "bright": int(bright.sum())}


def bench_ffbp_scaling(sizes=(1024, 4096), planes=("ground",), settings=None, density: float = 0.005,
                       rows: int = 8, bright: float = 0.0):
    """FFBP (default and high) against the truth at each size."""
    from salkit.focus.formers import get_former
    from salkit.signals.windows import Window
    settings = settings or {"default": {}, "high": {"accuracy": "high"}}
    out = {}
    for plane in planes:
        for n in sizes:
            ph, ig, sel, truth, t = problem(n, plane, rows=rows, density=density, bright=bright)
            key = f"ffbp_scaling_{plane}_{n}" + ("_bright" if bright else "")
            out[f"{key}_pulses"], out[f"{key}_frequencies"] = ph.data.shape
            out.update({f"{key}_{k}": v for k, v in t.items()})
            for label, kw in settings.items():
                former = get_former("ffbp")
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    t0 = time.perf_counter()
                    res = former(ph, ig, Window("none"), **kw)
                    dt = time.perf_counter() - t0
                m = measure(res.image[sel], truth)
                out.update({f"{key}_{label}_{k}": v for k, v in m.items()})
                out[f"{key}_{label}_s"] = dt
                print(f"{plane} {n}^2 x {ph.data.shape[0]} pulses, {label}: {m['error_db']:.1f} dB, "
                      f"p99 {m['phase_p99_deg']:.3f} deg over {m['bright']} bright pixels, {dt:.2f} s", flush=True)
    return out


if __name__ == "__main__":
    sizes = tuple(int(a) for a in sys.argv[1:]) or (1024, 4096)
    bench_ffbp_scaling(sizes)
