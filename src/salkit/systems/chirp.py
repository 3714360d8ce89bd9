"""Seed 002: nonlinear laser chirp, the paper's reference-channel method and established corrections.

Range-only (dechirped beat) experiment: points A, B, C at equivalent distances, a reference delay
line (d_r, d_rlo), a polynomial nonlinearity set by R1 (quadratic = 1/R1 of the linear sweep at the
pulse edge) and R2 (cubic = 1/R2 of the quadratic). Every method runs on the same data:
``none`` (plain deskew + FFT), ``paper`` (seed 002, eq 7 phase shift for each point's delay),
``deskew`` (Meta et al. 2007), ``resample`` (uniform optical frequency), ``ideal`` (linear chirp).
"""
from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np
import xarray as xr

from ..constants import SPEED_OF_LIGHT as C
from ..focus.chirpcorr import (PhaseUnwrapError, correct_deskew, correct_paper, correct_resample,
                               estimate_nonlinear_phase, reference_beat, spectral_width)
from ..focus.rangecomp import deskew
from ..io.datasets import write_dataset, write_json_atomic, write_text_atomic
from ..metrics.pointtarget import ipr_1d
from ..params.models import Scenario
from ..params.scenario import dump_scenario

METHODS = ("none", "paper", "deskew", "resample", "ideal")
UP = 16


def coefficients(k: float, tp: float, r1: float, r2: float) -> tuple[float, float]:
    """Sweep coefficients (c2, c3), Hz/s^2 and Hz/s^3, from the seed's ratios R1 and R2."""
    c2 = 2 * k / (r1 * tp)
    return c2, 2 * c2 / (r2 * tp)


def run_methods(t, fs, f0, k, coeffs, delay, d_r, d_rlo):
    """Range spectra (complex, zero-padded x16) of one point for every method, and figures."""
    dr = (d_r - d_rlo) / C
    raw = reference_beat(t, f0, k, coeffs, delay)[None].astype(np.complex64)
    ref = reference_beat(t, f0, k, coeffs, dr)
    sig = {"ideal": deskew(reference_beat(t, f0, k, (), delay)[None], fs, k)[0],
           "none": deskew(raw, fs, k)[0]}
    try:
        sig["paper"] = correct_paper(raw, ref, t, fs, (delay, 0.0), (d_r / C, d_rlo / C))[0]
    except Exception:  # noqa: BLE001 - the paper's method can break (report it as failed)
        sig["paper"] = None
    try:
        e = estimate_nonlinear_phase(ref, t, f0, k, dr)
        sig["deskew"] = correct_deskew(raw, e, fs, k)[0]
        sig["resample"] = deskew(correct_resample(raw, e, t, k), fs, k)[0]
    except (PhaseUnwrapError, ValueError):
        sig["deskew"] = sig["resample"] = None
    return sig


def analyse(sig, fs, k):
    """Spectral width (Hz), IRW (m), PSLR, ISLR (dB) of a beat signal's range profile."""
    n = sig.size
    spec = np.fft.fftshift(np.fft.fft(sig, n=n * UP))
    df = fs / (n * UP)
    m = ipr_1d(spec, df * C / (2 * k), C / (2 * k) * fs / n)
    return {"width_hz": spectral_width(spec, df), "irw_m": m["irw"], "pslr_db": m["pslr_db"],
            "islr_db": m["islr_db"]}, spec


def run(scenario: Scenario, out_dir, progress=None) -> dict:
    """Run the seed 002 experiment; returns the metrics written to metrics.json."""
    from .. import plot
    exp = scenario.experiment
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out / "scenario.yaml", dump_scenario(scenario))
    w, rx = scenario.waveform, scenario.receiver
    fs, k, f0, tp = rx.adc_rate, w.rate, w.carrier_frequency, w.pulse_width
    n = int(tp * fs) - 2
    t = (np.arange(n) - n // 2) / fs
    coeffs = coefficients(k, tp, exp.r1, exp.r2)
    metrics: dict = {"c2_hz_per_s2": coeffs[0], "c3_hz_per_s3": coeffs[1]}
    # Table 1 and profiles
    profiles = {m: [] for m in METHODS}
    rng_axis = None
    table1 = []
    first_delay = 2 * list(exp.points.values())[0] / C
    first = list(exp.points)[0]
    for name, dist in exp.points.items():
        delay = 2 * dist / C
        sig = run_methods(t, fs, f0, k, coeffs, delay, exp.d_r, exp.d_rlo)
        base, _ = analyse(sig["none"], fs, k)
        if delay != first_delay:  # the paper's method is matched to one delay: apply A's to this point
            raw = reference_beat(t, f0, k, coeffs, delay)[None]
            ref = reference_beat(t, f0, k, coeffs, (exp.d_r - exp.d_rlo) / C)
            mis = correct_paper(raw, ref, t, fs, (first_delay, 0.0), (exp.d_r / C, exp.d_rlo / C))[0]
            fig, _ = analyse(mis, fs, k)
            table1.append({"point": name, "method": f"paper matched to {first}",
                           "width_before_mhz": base["width_hz"] / 1e6, "width_after_mhz": fig["width_hz"] / 1e6,
                           "compression_ratio": base["width_hz"] / fig["width_hz"], "irw_m": fig["irw_m"],
                           "pslr_db": fig["pslr_db"], "islr_db": fig["islr_db"]})
            metrics[f"{name}_paper_matched_{first}_irw_m"] = float(fig["irw_m"])
        for meth in METHODS:
            if sig[meth] is None:
                profiles[meth].append(np.full(n * UP, np.nan + 0j))
                continue
            fig, spec = analyse(sig[meth], fs, k)
            profiles[meth].append(spec.astype(np.complex64))
            ratio = base["width_hz"] / fig["width_hz"]
            table1.append({"point": name, "method": meth, "width_before_mhz": base["width_hz"] / 1e6,
                           "width_after_mhz": fig["width_hz"] / 1e6, "compression_ratio": ratio,
                           "irw_m": fig["irw_m"], "pslr_db": fig["pslr_db"], "islr_db": fig["islr_db"]})
            for key, v in (("compression_ratio", ratio), ("irw_m", fig["irw_m"]), ("pslr_db", fig["pslr_db"]),
                           ("islr_db", fig["islr_db"]), ("width_after_hz", fig["width_hz"])):
                metrics[f"{name}_{meth}_{key}"] = float(v)
        rng_axis = (np.arange(n * UP) - n * UP // 2) * fs / (n * UP) * C / (2 * k)
    ds = xr.Dataset({m: (("point", "range"), np.stack(profiles[m])) for m in METHODS},
                    coords={"point": list(exp.points), "range": ("range", -rng_axis, {"units": "m",
                            "long_name": "range from the LO delay (beat frequency -k tau)"})},
                    attrs={"salkit_kind": "range_profiles", "r1": exp.r1, "r2": exp.r2, "d_r": exp.d_r,
                           "d_rlo": exp.d_rlo})
    write_dataset(ds, out / "profiles.nc")
    _write_csv(out / "table1.csv", table1)
    # Table 2 (d_r x d_rlo) and Table 3 (R1 x R2), point A, every method
    a_delay = 2 * list(exp.points.values())[0] / C
    sweeps = {}
    for label, rows_, cols_, make in (
            ("table2", exp.sweep_d_rlo, exp.sweep_d_r,
             lambda a, b: (coeffs, b, a)),
            ("table3", exp.sweep_r2, exp.sweep_r1,
             lambda a, b: (coefficients(k, tp, b, a), exp.d_r, exp.d_rlo))):
        grids = {m: np.full((len(rows_), len(cols_)), np.nan) for m in METHODS}
        irws = {m: np.full((len(rows_), len(cols_)), np.nan) for m in METHODS}
        pslrs = {m: np.full((len(rows_), len(cols_)), np.nan) for m in METHODS}
        islrs = {m: np.full((len(rows_), len(cols_)), np.nan) for m in METHODS}
        for i, a in enumerate(rows_):
            for j, b in enumerate(cols_):
                co, d_r, d_rlo = make(a, b)
                if d_r == d_rlo:
                    continue  # zero-length reference
                sig = run_methods(t, fs, f0, k, co, a_delay, d_r, d_rlo)
                base, _ = analyse(sig["none"], fs, k)
                for meth in METHODS:
                    if sig[meth] is not None:
                        fig, _ = analyse(sig[meth], fs, k)
                        grids[meth][i, j] = base["width_hz"] / fig["width_hz"]
                        irws[meth][i, j] = fig["irw_m"]
                        pslrs[meth][i, j] = fig["pslr_db"]
                        islrs[meth][i, j] = fig["islr_db"]
        sweeps[label] = (rows_, cols_, grids, irws)
        for meth in METHODS:
            _write_grid(out / f"{label}_{meth}.csv", rows_, cols_, grids[meth])
            _write_grid(out / f"{label}_{meth}_irw_m.csv", rows_, cols_, irws[meth])
            _write_grid(out / f"{label}_{meth}_pslr_db.csv", rows_, cols_, pslrs[meth])
            _write_grid(out / f"{label}_{meth}_islr_db.csv", rows_, cols_, islrs[meth])
        plot.sweep_heatmaps(rows_, cols_, grids, irws, out / f"{label}.png",
                            ("d_rlo (m)", "d_r (m)") if label == "table2" else ("R2", "R1"))
    # success statistics: the paper's method and salkit's, on Table 3
    rows_, cols_, grids, irws = sweeps["table3"]
    ideal = irws["ideal"]
    for meth in ("paper", "deskew", "resample"):
        ok = np.abs(irws[meth] / ideal - 1) <= 0.05
        metrics[f"table3_{meth}_cells_within_5pct_of_ideal"] = int(np.nansum(ok))
    metrics["table3_cells"] = int(np.isfinite(ideal).sum())
    plot.range_profiles_figure(ds, out / "profiles.png")
    write_json_atomic(out / "metrics.json", metrics)
    from ..report import write_chirp_report
    write_chirp_report(out, scenario, table1, sweeps, metrics)
    return metrics


def _write_csv(path, rows):
    buf = io.StringIO()
    wr = csv.DictWriter(buf, fieldnames=list(rows[0]))
    wr.writeheader()
    wr.writerows(rows)
    write_text_atomic(path, buf.getvalue())


def _write_grid(path, rows_, cols_, grid):
    buf = io.StringIO()
    wr = csv.writer(buf)
    wr.writerow(["row\\col"] + [f"{c:g}" for c in cols_])
    for r, line in zip(rows_, grid):
        wr.writerow([f"{r:g}"] + ["" if not math.isfinite(v) else f"{v:.4g}" for v in line])
    write_text_atomic(path, buf.getvalue())
