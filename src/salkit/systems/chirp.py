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

import numpy as np
import xarray as xr

from ..constants import SPEED_OF_LIGHT as C
from ..focus.chirpcorr import (PhaseUnwrapError, correct_deskew, correct_paper, correct_resample,
                               estimate_nonlinear_phase, reference_beat, spectral_width)
from ..focus.dechirp import deskew
from ..metrics.pointtarget import ipr_1d
from ..params.models import Scenario
from ..params.scenario import dump_scenario
from ..tolerances import CHIRP_IRW_OF_IDEAL
from .result import Progress, RunResult

METHODS = ("none", "paper", "deskew", "resample", "ideal")
UP = 16


def coefficients(k: float, tp: float, r1: float, r2: float) -> tuple[float, float]:
    """Sweep coefficients (c2, c3), Hz/s^2 and Hz/s^3, from the seed's ratios R1 and R2.

    Parameters
    ----------
    k : float
        Chirp rate, Hz/s.
    tp : float
        Pulse width, s.
    r1, r2 : float

    Returns
    -------
    (float, float)
    """
    c2 = 2 * k / (r1 * tp)
    return c2, 2 * c2 / (r2 * tp)


def run_methods(t, fs, f0, k, coeffs, delay, d_r, d_rlo):
    """Range spectra (complex, zero-padded x16) of one point for every method, and figures.

    Parameters
    ----------
    t : float64 (N,)
        s.
    fs, f0, k : float
        Hz, Hz, Hz/s.
    coeffs : tuple of float
    delay : float
        s.
    d_r, d_rlo : float
        m.

    Returns
    -------
    dict
        Method -> complex beat (or None when it failed).
    """
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
    """Spectral width (Hz), IRW (m), PSLR, ISLR (dB) of a beat signal's range profile.

    Parameters
    ----------
    sig : complex (N,)
    fs, k : float
        Hz, Hz/s.

    Returns
    -------
    (dict, complex ndarray)
    """
    n = sig.size
    spec = np.fft.fftshift(np.fft.fft(sig, n=n * UP))
    df = fs / (n * UP)
    m = ipr_1d(spec, df * C / (2 * k), C / (2 * k) * fs / n)
    return {"width_hz": spectral_width(spec, df), "irw_m": m["irw"], "pslr_db": m["pslr_db"],
            "islr_db": m["islr_db"]}, spec


def point_table(exp, t, fs, f0, k, coeffs) -> tuple[list, dict, xr.Dataset]:
    """Table 1 of the seed (every method on points A, B, C) and the range profiles.

    Parameters
    ----------
    exp : ChirpExperiment
    t : float64 (N,)
        s.
    fs, f0, k : float
        Hz, Hz, Hz/s.
    coeffs : (float, float)

    Returns
    -------
    (list of dict, dict, xarray.Dataset)
        Rows of Table 1, their metrics, and the profiles (point, range) of every method.
    """
    n = t.size
    profiles = {m: [] for m in METHODS}
    table1, metrics = [], {}
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
    return table1, metrics, ds


def sweep(rows_, cols_, make, t, fs, f0, k, delay) -> dict:
    """Every method over a grid of (row, column) settings, on one point: compression ratio, IRW,
    PSLR and ISLR grids (NaN where a method fails or the reference has zero length).

    Parameters
    ----------
    rows_, cols_ : sequence of float
    make : callable
        ``make(row, col) -> (coefficients, d_r, d_rlo)``.
    t : ndarray
        Fast time, s.
    fs, f0, k : float
        ADC rate (Hz), carrier (Hz), chirp rate (Hz/s).
    delay : float
        The point's delay, s.

    Returns
    -------
    dict
        ``ratio``, ``irw``, ``pslr``, ``islr``: method -> (rows, cols) array.
    """
    out = {q: {m: np.full((len(rows_), len(cols_)), np.nan) for m in METHODS} for q in ("ratio", "irw", "pslr", "islr")}
    for i, a in enumerate(rows_):
        for j, b in enumerate(cols_):
            co, d_r, d_rlo = make(a, b)
            if d_r == d_rlo:
                continue  # zero-length reference
            sig = run_methods(t, fs, f0, k, co, delay, d_r, d_rlo)
            base, _ = analyse(sig["none"], fs, k)
            for meth in METHODS:
                if sig[meth] is not None:
                    fig, _ = analyse(sig[meth], fs, k)
                    out["ratio"][meth][i, j] = base["width_hz"] / fig["width_hz"]
                    out["irw"][meth][i, j] = fig["irw_m"]
                    out["pslr"][meth][i, j] = fig["pslr_db"]
                    out["islr"][meth][i, j] = fig["islr_db"]
    return out


def run(scenario: Scenario, out_dir=None, progress: Progress = None) -> RunResult:
    """Run the seed 002 experiment: Table 1 (points A, B, C), Tables 2 and 3 (sweeps), every method.

    Parameters
    ----------
    scenario : Scenario
        With ``experiment.kind = nonlinear_chirp``.
    out_dir : path, optional
        Unused.
    progress : callable, optional
        ``progress(stage, done, total)``, in tables.

    Returns
    -------
    RunResult
    """
    exp, w, rx = scenario.experiment, scenario.waveform, scenario.receiver
    fs, k, f0, tp = rx.adc_rate, w.rate, w.carrier_frequency, w.pulse_width
    n = int(tp * fs) - 2
    t = (np.arange(n) - n // 2) / fs
    coeffs = coefficients(k, tp, exp.r1, exp.r2)
    table1, m1, profiles = point_table(exp, t, fs, f0, k, coeffs)
    metrics = {"c2_hz_per_s2": coeffs[0], "c3_hz_per_s3": coeffs[1], **m1}
    tables = {"table1.csv": csv_text(table1)}
    a_delay = 2 * list(exp.points.values())[0] / C
    sweeps = {}
    for i, (label, rows_, cols_, make) in enumerate((
            ("table2", exp.sweep_d_rlo, exp.sweep_d_r, lambda a, b: (coeffs, b, a)),
            ("table3", exp.sweep_r2, exp.sweep_r1, lambda a, b: (coefficients(k, tp, b, a), exp.d_r, exp.d_rlo)))):
        if progress:
            progress("tables swept", i, 2)
        g = sweep(rows_, cols_, make, t, fs, f0, k, a_delay)
        sweeps[label] = (rows_, cols_, g["ratio"], g["irw"])
        for meth in METHODS:
            for suffix, q in (("", "ratio"), ("_irw_m", "irw"), ("_pslr_db", "pslr"), ("_islr_db", "islr")):
                tables[f"{label}_{meth}{suffix}.csv"] = grid_csv(rows_, cols_, g[q][meth])
    if progress:
        progress("tables swept", 2, 2)
    irws = sweeps["table3"][3]  # success on Table 3: range IRW within 5 % of the ideal chirp's
    for meth in ("paper", "deskew", "resample"):
        metrics[f"table3_{meth}_cells_within_5pct_of_ideal"] = int(np.nansum(np.abs(irws[meth] / irws["ideal"] - 1) <= CHIRP_IRW_OF_IDEAL))
    metrics["table3_cells"] = int(np.isfinite(irws["ideal"]).sum())
    return RunResult("nonlinear_chirp", scenario.name, scenario.description, dump_scenario(scenario), metrics,
                     {"profiles.nc": profiles}, tables, figures={"table1": table1, "sweeps": sweeps})


def csv_text(rows: list[dict]) -> str:
    """CSV text of a list of dicts (the first row's keys as the header).

    Parameters
    ----------
    rows : list of dict

    Returns
    -------
    str
    """
    buf = io.StringIO()
    wr = csv.DictWriter(buf, fieldnames=list(rows[0]))
    wr.writeheader()
    wr.writerows(rows)
    return buf.getvalue()


def grid_csv(rows_, cols_, grid) -> str:
    """CSV text of a (rows, cols) grid with its row and column labels (empty cells for NaN).

    Parameters
    ----------
    rows_, cols_ : sequence of float
    grid : float (rows, cols)

    Returns
    -------
    str
    """
    buf = io.StringIO()
    wr = csv.writer(buf)
    wr.writerow(["row\\col"] + [f"{c:g}" for c in cols_])
    for r, line in zip(rows_, grid):
        wr.writerow([f"{r:g}"] + ["" if not math.isfinite(v) else f"{v:.4g}" for v in line])
    return buf.getvalue()
