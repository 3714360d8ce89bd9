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
import time

import numpy as np
import xarray as xr

from ..constants import SPEED_OF_LIGHT as C
from ..focus.chirpcorr import (PhaseUnwrapError, correct_deskew, correct_paper, correct_resample,
                               estimate_nonlinear_phase, reference_beat, spectral_width)
from ..focus.dechirp import deskew
from ..metrics.pointtarget import ipr_1d
from ..params.models import Scenario
from ..params.scenario import dump_scenario, parse_scenario
from ..studies.engine import execute
from ..studies.plan import check_points, make_plan
from ..studies.spec import Axis
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


#: Quantities of every method at one setting of a table: record name -> grid name.
TABLE_QUANTITIES = {"compression_ratio": "ratio", "irw_m": "irw", "pslr_db": "pslr", "islr_db": "islr"}
#: The seed's sweeps (Tables 2 and 3) as sweep axes: rows, then columns.
TABLES = {"table2": ("experiment.d_rlo", "experiment.d_r"), "table3": ("experiment.r2", "experiment.r1")}


def _fast_time(scenario: Scenario) -> np.ndarray:
    rx, w = scenario.receiver, scenario.waveform
    n = int(w.pulse_width * rx.adc_rate) - 2
    return (np.arange(n) - n // 2) / rx.adc_rate


def table_point(data: dict, metrics=(), keep_images: bool = False) -> dict:
    """One cell of Tables 2 and 3, as a sweep point: the first point (A) through the scenario's
    reference path and nonlinearity, every method; compression ratio, IRW, PSLR and ISLR.

    Parameters
    ----------
    data : dict
        The scenario (``experiment.kind = nonlinear_chirp``) as plain data, with the cell's
        ``d_r``, ``d_rlo``, ``r1`` and ``r2``.
    metrics : sequence of str
        Unused (every quantity is kept).
    keep_images : bool
        Unused.

    Returns
    -------
    dict
        A sweep record (:func:`salkit.studies.engine.execute`): metrics ``<method>_<quantity>``;
        a method that fails has none.
    """
    t0 = time.perf_counter()
    sc = parse_scenario(data)
    exp, w, rx = sc.experiment, sc.waveform, sc.receiver
    fs, k, f0 = rx.adc_rate, w.rate, w.carrier_frequency
    t = _fast_time(sc)
    delay = 2 * list(exp.points.values())[0] / C
    sig = run_methods(t, fs, f0, k, coefficients(k, w.pulse_width, exp.r1, exp.r2), delay, exp.d_r, exp.d_rlo)
    base, _ = analyse(sig["none"], fs, k)
    out = {}
    for meth in METHODS:
        if sig[meth] is not None:
            fig, _ = analyse(sig[meth], fs, k)
            q = {"compression_ratio": base["width_hz"] / fig["width_hz"], "irw_m": fig["irw_m"],
                 "pslr_db": fig["pslr_db"], "islr_db": fig["islr_db"]}
            out.update({f"{meth}_{name}": float(v) for name, v in q.items()})
    return {"status": "ok", "metrics": out, "seconds": time.perf_counter() - t0}


def table(scenario: Scenario, label: str, progress=None) -> tuple[xr.Dataset, dict]:
    """Table 2 (``d_rlo`` x ``d_r``) or 3 (``R2`` x ``R1``) of the seed as a sweep through the
    study engine (:func:`table_point` at every cell; a zero-length reference is an invalid cell).

    Parameters
    ----------
    scenario : Scenario
        With ``experiment.kind = nonlinear_chirp``; the other settings are the scenario's.
    label : {"table2", "table3"}
    progress : callable, optional
        ``progress(done, total)``, in cells.

    Returns
    -------
    (xarray.Dataset, dict)
        The sweep (``<method>_<quantity>`` against the two fields) and the grids: quantity
        (``ratio``, ``irw``, ``pslr``, ``islr``) -> method -> (rows, cols) array, NaN where a method
        fails or the cell is invalid.
    """
    exp = scenario.experiment
    rows_f, cols_f = TABLES[label]
    values = {"experiment.d_rlo": exp.sweep_d_rlo, "experiment.d_r": exp.sweep_d_r,
              "experiment.r2": exp.sweep_r2, "experiment.r1": exp.sweep_r1}
    axes = [Axis(f, tuple(float(v) for v in values[f]), "list", ",".join(f"{v:g}" for v in values[f]))
            for f in (rows_f, cols_f)]
    plan = make_plan(scenario, axes)
    ds = execute(plan, check_points(plan), table_point, progress=progress)
    grids = {q: {m: (ds[f"{m}_{name}"].isel(realisation=0).values if f"{m}_{name}" in ds
                     else np.full(plan.shape, np.nan)) for m in METHODS}
             for name, q in TABLE_QUANTITIES.items()}
    return ds, grids


def run(scenario: Scenario, out_dir=None, progress: Progress = None) -> RunResult:
    """Run the seed 002 experiment: Table 1 (points A, B, C), Tables 2 and 3 (sweeps through the
    study engine, also written as ``table2.nc`` and ``table3.nc``), every method.

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
    t = _fast_time(scenario)
    coeffs = coefficients(k, tp, exp.r1, exp.r2)
    table1, m1, profiles = point_table(exp, t, fs, f0, k, coeffs)
    metrics = {"c2_hz_per_s2": coeffs[0], "c3_hz_per_s3": coeffs[1], **m1}
    tables = {"table1.csv": csv_text(table1)}
    data = {"profiles.nc": profiles}
    sweeps = {}
    for i, label in enumerate(TABLES):
        if progress:
            progress("tables swept", i, 2)
        ds, g = table(scenario, label)
        data[f"{label}.nc"] = ds
        rows_, cols_ = (ds[f].values.tolist() for f in TABLES[label])
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
                     data, tables, figures={"table1": table1, "sweeps": sweeps})


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
