"""peers: salkit against FastSAR (PyPI ``fastsar``, its C++/OpenMP CPU kernels) on the same phase
histories, both judged against salkit's exact former (the float64 matched filter).

Data: the wide-angle arc of ``ffbp_scaling`` (4 degrees of a 7 km radius at 7.3 km height, climbing
0.5 m, ground plane, 0.2 m pixels), unit scatterers with random phases uniformly over the grid,
complex64 phase histories given to both libraries unchanged. Both grids are (i - n/2) x spacing
along the plane's azimuth and range axes (the same pixels); the truth is evaluated on 8 evenly
spread rows. FastSAR's images are sums (salkit's are means): divided by pulses x frequencies.
The simulator's rows: salkit's raw-data simulator (``benchmarks/fast_simulation.py``: a 1.55 um
spotlight, dechirped) on as many scatterers x pulses x samples as the scene, the exact direct sum
(timed on a subset, scaled) against the non-uniform FFT, its error against the direct sum.
No window in either. Each setting is timed warm, runs interleaved between the libraries, best of
``repeat``, each round in its own seeded random order, so that no setting is always timed after the
same one (on the project's VM a setting timed right after FFBP's runs, which take and free some
700 MB, ran up to 25 % slower than the same work elsewhere); threads: numba's (salkit) and
OMP_NUM_THREADS (FastSAR), both set to the cores.

After the rows, issue 33 point 2's criteria judged on them (:func:`point2_verdicts`): for each of
FastSAR's exact-BP settings salkit's fastest direct-BP setting at least as accurate and the ratio
(>= 1.3x asked), the default ``bp`` against -65 dB at 1.2e9 pixel-pulses/s, and the fastest setting
at <= -85 dB against 1.0e9: "met" or "MISSED" with the numbers.

FastSAR is optional (``pip install 'salkit[peers]'``, never needed by ``make test``): without it
this benchmark prints one line saying so and measures nothing.

``make bench NAME=peers`` (or ``python benchmarks/peers.py [SIZE ...] [--ffbp]``, default 1024).
"""
from __future__ import annotations

import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: (label, former, keyword arguments) of salkit
#: (bp: the default, 6x profiles and four fitted taps, 8x at accuracy high; "bp linear 16x" the
#: default until 0.19.0, through the library's linear interpolation; "bp linear 4x" and "8x" the same
#: path at FastSAR's coarsest linear settings' upsampling)
SALKIT = ([("ffbp", "ffbp", {}), ("ffbp high", "ffbp", {"accuracy": "high"}), ("bp", "bp", {}),
           ("bp high (8x)", "bp", {"upsample": 8}), ("bp linear 4x", "linear", {"upsample": 4}),
           ("bp linear 8x", "linear", {"upsample": 8}), ("bp linear 16x", "linear", {"upsample": 16}),
           ("bp linear 32x", "linear", {"upsample": 32}), ("bp_cubic", "bp_cubic", {}),
           ("bp_cubic high (32x)", "bp_cubic", {"upsample": 32}), ("bp_fitted 4x", "bp_fitted", {"upsample": 4}),
           ("bp_fitted", "bp_fitted", {})])
#: (label, form_image keyword arguments) of FastSAR
FASTSAR = ([(f"ffbp target {t} dB", {"algorithm": "ffbp", "target_db": float(t)}) for t in (-40, -50, -60)]
           + [(f"bp {i} {u}x", {"algorithm": "bp", "interp": i, "upsample": u})
              for i in ("linear", "cubic") for u in (4, 8, 16, 32)])


#: Issue 33, point 2: every FastSAR exact-BP setting has a salkit direct-BP setting at least as
#: accurate and this many times as fast ...
DOMINANCE = 1.3
#: ... and salkit's default ``bp`` is at least this accurate (dB) at this rate (pixel-pulses/s) ...
DEFAULT_ERROR_DB, DEFAULT_RATE = -65.0, 1.2e9
#: ... and some salkit direct-BP setting at least this accurate at this rate.
FINE_ERROR_DB, FINE_RATE = -85.0, 1.0e9


def point2_verdicts(rows: dict) -> list:
    """Issue 33 point 2's criteria on one grid's measurements.

    Parameters
    ----------
    rows : dict
        ``(library, label) -> (error dB, pixel-pulses/s)`` for every setting measured; the direct
        backprojection settings are the labels beginning "bp" (salkit's formers ``bp``,
        ``bp_cubic``, ``bp_fitted`` and the library's linear interpolation; FastSAR's exact BP).

    Returns
    -------
    list of (str, bool)
        Each criterion in words, with the numbers it was judged on, and whether it is met.
    """
    ours = {k[1]: v for k, v in rows.items() if k[0] == "salkit" and k[1].startswith("bp")}
    out = []
    for (lib, label), (err, rate) in rows.items():
        if lib != "FastSAR" or not label.startswith("bp"):
            continue
        fit = [(r, lab, e) for lab, (e, r) in ours.items() if e <= err]
        if not fit:
            out.append((f"FastSAR {label} ({err:.1f} dB, {rate:.3g}/s): no salkit setting as accurate", False))
            continue
        r, lab, e = max(fit)
        out.append((f"FastSAR {label} ({err:.1f} dB, {rate:.3g}/s): salkit {lab} ({e:.1f} dB, {r:.3g}/s) "
                    f"{r / rate:.2f}x (>= {DOMINANCE}x)", r >= DOMINANCE * rate))
    if "bp" in ours:
        e, r = ours["bp"]
        out.append((f"default bp {e:.1f} dB at {r:.3g}/s (<= {DEFAULT_ERROR_DB:.0f} dB at >= {DEFAULT_RATE:.2g})",
                    e <= DEFAULT_ERROR_DB and r >= DEFAULT_RATE))
    fine = [(r, lab, e) for lab, (e, r) in ours.items() if e <= FINE_ERROR_DB]
    if fine:
        r, lab, e = max(fine)
        out.append((f"fastest salkit setting at <= {FINE_ERROR_DB:.0f} dB: {lab} {e:.1f} dB at {r:.3g}/s "
                    f"(>= {FINE_RATE:.2g})", r >= FINE_RATE))
    return out


def _fastsar():
    try:
        import fastsar
    except ImportError:
        return None
    return fastsar


def bench_peers(sizes=(1024,), repeat=3, only: str | None = None):
    """Error against the truth, 99th-percentile bright-pixel phase error and best time of every
    setting of both libraries (``only="ffbp"``: the factorised formers alone, for large grids
    where per-pixel backprojection takes minutes a run)."""
    fastsar = _fastsar()
    if fastsar is None:
        print("peers: FastSAR is not installed (pip install 'salkit[peers]'): skipped, nothing measured")
        return {}
    from numba import get_num_threads
    from ffbp_scaling import measure, problem
    from salkit.focus.bp import backprojection_former
    from salkit.focus.formers import get_former
    from salkit.signals.windows import Window
    out = {"peers_threads_salkit": get_num_threads(), "peers_threads_fastsar": int(os.environ.get("OMP_NUM_THREADS", 0)),
           "peers_fastsar_version": getattr(fastsar, "__version__", "?")}
    for n in sizes:
        ph, ig, sel, truth, t = problem(n)
        P, K = ph.data.shape
        pl = ig.plane
        dx, dy = float(ig.azimuth[1] - ig.azimuth[0]), float(ig.range[1] - ig.range[0])
        assert np.allclose(ig.azimuth, (np.arange(n) - n / 2) * dx) and np.allclose(ig.range, (np.arange(n) - n / 2) * dy)
        runs = {}
        for label, alg, kw in SALKIT:
            if only and not label.startswith(only):
                continue
            former = backprojection_former(alg)[0] if alg == "linear" else get_former(alg)
            runs[("salkit", label)] = (lambda former=former, kw=kw: former(ph, ig, Window("none"), **kw).image)
        fmin, df = float(ph.freq[0]), float(ph.freq[1] - ph.freq[0])
        for label, kw in FASTSAR:
            if only and not label.startswith(only):
                continue
            runs[("FastSAR", label)] = (lambda kw=kw: np.asarray(fastsar.form_image(
                ph.data, ph.positions, fmin, df, n, n, dx, dy, pl.azimuth, pl.range, backend="cpu", window=False,
                ref=ph.reference_range, **kw)) / (P * K))
        best = {k: np.inf for k in runs}
        result = {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for k, run in runs.items():  # warm: compiled, caches filled
                result[k] = run()[sel]
            keys = list(runs)
            for r in range(repeat):  # interleaved, each round in its own (seeded) order
                for i in np.random.default_rng(r).permutation(len(keys)):
                    k = keys[i]
                    run = runs[k]
                    t0 = time.perf_counter()
                    run()
                    best[k] = min(best[k], time.perf_counter() - t0)
        rows = {}  # (library, label) -> (error dB, pixel-pulses/s), for point 2's verdicts
        for (lib, label), img in result.items():
            m = measure(img, truth)
            rate = n * n * P / best[(lib, label)]
            rows[(lib, label)] = (m["error_db"], rate)
            key = f"peers_{n}_{lib}_{label}".replace(" ", "_")
            out.update({f"{key}_error_db": m["error_db"], f"{key}_phase_p99_deg": m["phase_p99_deg"],
                        f"{key}_s": best[(lib, label)], f"{key}_pixel_pulses_per_s": rate})
            out[f"peers_{n}_bright_pixels"] = m["bright"]
            print(f"{n}^2 x {P} pulses x {K} | {lib:7s} | {label:22s} | {m['error_db']:7.1f} dB | "
                  f"{m['phase_p99_deg']:6.3f} deg | {best[(lib, label)]:7.3f} s | {rate:.3g} px-pulses/s", flush=True)
        if not only:  # issue 33 point 2 judged on this run's rows; then the simulator's own rows (as many
            # scatterers x pulses x samples, SAL raw data)
            verdicts = point2_verdicts(rows)
            for text, ok in verdicts:
                print(f"{n}^2 point 2 | {'met   ' if ok else 'MISSED'} | {text}", flush=True)
            out[f"peers_{n}_point2_met"] = all(ok for _, ok in verdicts)
            from fast_simulation import bench_fast_simulation
            sim = bench_fast_simulation(n_scat=int(t["scatterers"]), n_pulses=P, n_samples=K)
            ops = t["scatterers"] * P * K
            out.update({f"peers_{n}_simulation_{k}": v for k, v in sim.items()})
            print(f"{n}^2 x {P} pulses x {K} | salkit  | simulate direct sum    | reference  |            | "
                  f"{sim['direct_sim_s_estimated']:7.3f} s | {ops / sim['direct_sim_s_estimated']:.3g} scatterer-samples/s")
            print(f"{n}^2 x {P} pulses x {K} | salkit  | simulate nufft (-80)   | {sim['fast_sim_error_db']:7.1f} dB |"
                  f"            | {sim['fast_sim_s']:7.3f} s | {ops / sim['fast_sim_s']:.3g} scatterer-samples/s",
                  flush=True)
    return out


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--ffbp"]
    bench_peers(tuple(int(a) for a in args) or (1024,), only="ffbp" if "--ffbp" in sys.argv else None)
