"""salkit benchmarks: throughput figures and ratios against the public alternative, same machine,
same run. Run with ``make bench`` (or ``.venv/bin/python benchmarks/run_all.py``).

- backprojection: salkit (numba) vs a straightforward NumPy backprojection (loop over pulses,
  vectorised over pixels), on the same phase history and grid; images compared.
- PFA: time as a multiple of one complex FFT of the output size (scipy.fft, same workers).
- simulation: scatterer-samples per second of the dechirped-echo simulator.
- spaceborne: GEO sub-images per second in-process and through Dask with 1 and 2 workers
  (64 sub-images, cluster start included).
- chirp: milliseconds per pulse of 1e5 samples for each nonlinear-chirp correction.
- pga: PGA seconds per iteration at 256 x 256 and 2048 x 2048 (LUMV and eigenvector kernels).
- screens: phase screens per second at N = 256, 1024, 4096 against aotools' ft_sh_phase_screen
  (install with ``pip install -e .[bench]``), and both generators' ensemble structure function
  against Kolmogorov theory from 2 pixels to N/4.

- downlooking: seed 000 design example, a 2.4 m x 2.4 m scene imaged on >= 256 x 256 pixels:
  raw-data simulation (factored BLAS path and the numba field kernel against a vectorised NumPy
  evaluation of the same fields) and image formation (FFT processor against a direct
  time-domain along-track matched filter), with the images compared.

- startup: ``import salkit`` and ``salkit --help`` in fresh interpreters against
  ``import numpy, xarray``.
- outside: a 500-pulse collection converted to CPHD (sarkit check included) and the GOTCHA .mat
  layout and back, focused; per-pulse sharpness autofocus per sweep against PGA per iteration at
  1024 x 1024.

- ffbp: fast factorised backprojection against direct backprojection at 512^2, 1024^2 and 4096^2
  pixels (as many pulses), direct BP timed on a block of rows and scaled, both the best of the
  same number of runs; ffbp_knobs: the accuracy-speed curve over the polar-grid oversampling and
  the leaf size at 1024^2.
- accuracy (benchmarks/accuracy.py): every former (bp, bp at 32x, ffbp, ffbp high, pfa) on the
  test geometries against the exact float64 matched filter: error energy, bright-pixel phase
  error, time; the wide-angle arc from 101^2 to 2001^2 pixels.
- propagation: split-step wave-optics propagation per realisation (10 screens) at N = 256, 512,
  1024 against the same propagation written plainly with np.fft; fields compared.
- scaling: time and peak memory of each stage (simulate, phase history, BP, FFBP, PFA, PGA) at
  N = 256, 512, 1024 (N x N pixels, N pulses), and the fitted exponent of time ~ N^a.

``python benchmarks/run_all.py screens`` runs one group.
"""
from __future__ import annotations

import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import scipy.fft as sfft

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import C, best_of, spotlight_problem  # noqa: E402
from accuracy import bench_accuracy  # noqa: E402


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
    from salkit.focus.backprojection import backproject
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


def bench_pfa(n_pix=1024, n_pulses=1024):
    from salkit.focus import focus
    from salkit.simulate import simulate
    sc, _ = spotlight_problem(n_pix, n_pulses)
    raw = simulate(sc)
    from salkit.focus import phase_history
    ph = phase_history(raw)
    from salkit.focus.pfa import pfa
    from salkit.geometry.collection import grid_axes, plane_from
    from salkit.signals.windows import window
    plane = plane_from(ph.track, ph.center_position, "slant")
    az, rg = grid_axes(sc.processing.grid)
    w = lambda n: window("none", n)  # noqa: E731
    run = lambda: pfa(ph.data, ph.freq, ph.positions, ph.reference_range, plane, az, rg, w, w)  # noqa: E731
    run()
    t_pfa, _ = best_of(run, 3)
    x = (np.random.default_rng(0).standard_normal((n_pix, n_pix)) + 0j).astype(np.complex64)
    sfft.fft2(x, workers=-1)
    t_fft, _ = best_of(lambda: sfft.fft2(x, workers=-1), 5)
    del focus
    return {"pfa_output": f"{n_pix}x{n_pix}", "pfa_input": f"{ph.data.shape[0]}x{ph.data.shape[1]}",
            "pfa_s": t_pfa, "fft2_output_s": t_fft, "pfa_over_fft": t_pfa / t_fft}


def bench_simulation(n_scat=2000, n_pulses=256):
    from salkit.geometry import build_collection
    from salkit.simulate import echo_signal, fast_time_axis
    sc, _ = spotlight_problem(256, n_pulses)
    col = build_collection(sc)
    rng = np.random.default_rng(1)
    pos = np.c_[rng.uniform(-1, 1, (n_scat, 2)), np.zeros(n_scat)]
    amp = (rng.standard_normal(n_scat) + 1j * rng.standard_normal(n_scat)).astype(np.complex128)
    t = fast_time_axis(1024, sc.receiver.adc_rate)
    run = lambda: echo_signal(col, pos, amp, sc, t)  # noqa: E731
    echo_signal(col, pos[:10], amp[:10], sc, t)
    ts, _ = best_of(run, 3)
    n = n_scat * n_pulses * t.size
    return {"sim_scatterer_samples": n, "sim_s": ts, "sim_scatterer_samples_per_s": n / ts}


def bench_screens(sizes=(256, 1024, 4096)):
    """Phase screens per second against aotools' ft_sh_phase_screen, and accuracy at N/4."""
    from salkit.atmosphere import phase_screens, structure_function, structure_function_estimate
    try:
        from aotools.turbulence.phasescreen import ft_sh_phase_screen
    except ImportError:
        ft_sh_phase_screen = None
    out = {}
    r0, dx = 0.1, 0.01
    for n in sizes:
        k = {256: 32, 1024: 8, 4096: 2}.get(n, 4)
        phase_screens(n, dx, r0, count=2, seed=0)
        t, _ = best_of(lambda: phase_screens(n, dx, r0, count=k, seed=1), 2)
        out[f"screens_salkit_per_s_N{n}"] = k / t
        t32, _ = best_of(lambda: phase_screens(n, dx, r0, count=k, seed=1, dtype=np.float32), 2)
        out[f"screens_salkit_f32_per_s_N{n}"] = k / t32
        if ft_sh_phase_screen is not None:
            ka = max(1, min(k, 8 if n <= 1024 else 1))
            t0 = time.perf_counter()
            for i in range(ka):
                ft_sh_phase_screen(r0, n, dx, 1e8, 1e-9, seed=i)
            ta = (time.perf_counter() - t0) / ka
            out[f"screens_aotools_per_s_N{n}"] = 1 / ta
            out[f"screens_speedup_vs_aotools_N{n}"] = ta / (t / k)
            out[f"screens_f32_speedup_vs_aotools_N{n}"] = ta / (t32 / k)
    # accuracy: ensemble structure function at N/4 against Kolmogorov, same ensemble size
    n, K = 64, 1000
    s = phase_screens(n, dx, r0, count=K, seed=7)
    r, d, e = structure_function_estimate(s, dx)
    th = structure_function(r, r0)
    out["screens_salkit_sf_ratio_at_N4"] = float(d[-1] / th[-1])
    out["screens_salkit_sf_worst_2px_to_N4"] = float(np.max(np.abs(d[1:] / th[1:] - 1)))
    if ft_sh_phase_screen is not None:
        sa = np.stack([ft_sh_phase_screen(r0, n, dx, 1e8, 1e-9, seed=1000 + i) for i in range(K)])
        r, d, e = structure_function_estimate(sa, dx)
        out["screens_aotools_sf_ratio_at_N4"] = float(d[-1] / th[-1])
        out["screens_aotools_sf_worst_2px_to_N4"] = float(np.max(np.abs(d[1:] / th[1:] - 1)))
    out["screens_sf_stderr_at_N4"] = float(e[-1] / th[-1])
    return out


def bench_pga(sizes=(256, 2048)):
    """PGA time per iteration (LUMV kernel) on n x n images with a random smooth phase error."""
    from salkit.autofocus.pga import pga
    out = {}
    rng = np.random.default_rng(0)
    for n in sizes:
        refl = (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))) * 0.1
        idx = rng.integers(0, n, (n // 4, 2))
        refl[idx[:, 0], idx[:, 1]] += 8
        k = np.fft.fftfreq(n) * n
        phi = 4.0 * (k / (n / 2)) ** 2
        img = np.fft.ifft(np.fft.fft(refl, axis=0) * np.exp(1j * phi)[:, None], axis=0)
        for kernel in ("lumv", "ev"):
            pga(img[:, :8], kernel=kernel, max_iter=1)
            t0 = time.perf_counter()
            res = pga(img, kernel=kernel, max_iter=10, tol=0.0)
            dt = time.perf_counter() - t0
            out[f"pga_{kernel}_s_per_iteration_N{n}"] = dt / (len(res.history) - 1)
    return out


def bench_outside(n_pulses=500, n_pix=256):
    """Outside data: a 500-pulse collection converted NetCDF -> CPHD (with sarkit's consistency
    check) -> GOTCHA .mat -> read back, and focused from each; per-pulse sharpness autofocus time
    per sweep on 1024 x 1024 pixels (the contribution matrix built once) against PGA per iteration
    on the same 1024 x 1024 image."""
    import tempfile
    from salkit.autofocus.pga import pga
    from salkit.autofocus.sharpness import pulse_sharpness
    from salkit.focus import focus
    from salkit.focus.backprojection import pulse_contributions
    from salkit.geometry.collection import grid_axes, plane_from
    from salkit.io import check_cphd, read_cphd, read_gotcha, write_cphd, write_dataset, write_gotcha
    from salkit.autofocus.pulses import as_dataset
    out = {}
    sc, ph = spotlight_problem(n_pix, n_pulses)
    ds = as_dataset(ph, ph.data)
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        write_dataset(ds, d / "ph.nc")
        t0 = time.perf_counter()
        write_cphd(ds, d / "c.cphd")
        out["outside_write_cphd_s_P500"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        res = check_cphd(d / "c.cphd")
        out["outside_cphd_check_s_P500"] = time.perf_counter() - t0
        out["outside_cphd_check_errors"] = len(res["errors"])
        t0 = time.perf_counter()
        back = read_cphd(d / "c.cphd")
        out["outside_read_cphd_s_P500"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        write_gotcha(back, d / "g.mat")
        g = read_gotcha(d / "g.mat")
        out["outside_mat_write_read_s_P500"] = time.perf_counter() - t0
        focus(back, sc.processing)
        t0 = time.perf_counter()
        focus(g, sc.processing)
        out[f"outside_focus_bp_s_P500_N{n_pix}"] = time.perf_counter() - t0
    # autofocus at 1024 x 1024
    sc, ph = spotlight_problem(1024, 1024)
    plane = plane_from(ph.track, ph.center_position, "slant")
    az, rg = grid_axes(sc.processing.grid)
    rows = az[::16]  # 64 rows x 1024 columns x 1024 pulses = 2**26 entries (512 MiB)
    A, R = np.meshgrid(rows, rg, indexing="ij")
    t0 = time.perf_counter()
    B = pulse_contributions(ph.data, ph.freq, ph.positions, ph.reference_range, plane.points(A.ravel(), R.ravel()))
    out["pulse_af_contributions_s_P1024_K65536"] = time.perf_counter() - t0
    pulse_sharpness(B[:, :64], max_sweeps=1)
    t0 = time.perf_counter()
    r = pulse_sharpness(B, max_sweeps=3, tol=0.0)
    out["pulse_af_s_per_sweep_P1024_K65536"] = (time.perf_counter() - t0) / (len(r.history) - 1)
    del B
    image = focus(as_dataset(ph, ph.data), sc.processing)["image"].values
    pga(image[:, :8], max_iter=1)
    t0 = time.perf_counter()
    res = pga(image, max_iter=5, tol=0.0)
    out["pga_s_per_iteration_1024x1024"] = (time.perf_counter() - t0) / (len(res.history) - 1)
    out["pulse_af_sweep_over_pga_iteration"] = out["pulse_af_s_per_sweep_P1024_K65536"] / out["pga_s_per_iteration_1024x1024"]
    return out


def bench_startup(repeat=5):
    """Start-up: ``import salkit`` and ``salkit --help`` against ``import numpy, xarray``, each in a
    fresh interpreter, best of ``repeat`` (issue 12 target: within 1.5x)."""
    import subprocess

    def best(cmd):
        t = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            subprocess.run(cmd, check=True, capture_output=True)
            t.append(time.perf_counter() - t0)
        return min(t)
    py = sys.executable
    base = best([py, "-c", "import numpy, xarray"])
    imp = best([py, "-c", "import salkit"])
    hlp = best([py, "-m", "salkit.cli.main", "--help"])
    return {"startup_import_numpy_xarray_s": base, "startup_import_salkit_s": imp, "startup_help_s": hlp,
            "startup_import_ratio": imp / base, "startup_help_ratio": hlp / base}


def bench_chirp(n=100_000):
    """Cost of each nonlinear-chirp correction per pulse of n samples (seed 002 chirp)."""
    from salkit.focus.chirpcorr import (correct_deskew, correct_paper, correct_resample,
                                        estimate_nonlinear_phase, reference_beat)
    from salkit.focus.dechirp import deskew
    from salkit.systems.chirp import coefficients
    k, tp = 5.44e14, 7.8e-6
    fs = n / tp
    f0 = C / 1.55e-6
    t = (np.arange(n) - n // 2) / fs
    co = coefficients(k, tp, 50, 50)
    raw = reference_beat(t, f0, k, co, 2 * 26.9355 / C)[None].astype(np.complex64)
    ref = reference_beat(t, f0, k, co, 0.3 / C)
    out = {"chirp_samples_per_pulse": n}
    runs = {
        "none (deskew only)": lambda: deskew(raw, fs, k),
        "estimate e(t) from reference": lambda: estimate_nonlinear_phase(ref, t, f0, k, 0.3 / C),
        "resample": lambda: deskew(correct_resample(raw, e, t, k), fs, k),
        "deskew (Meta)": lambda: correct_deskew(raw, e, fs, k),
        "paper (eq 7)": lambda: correct_paper(raw, ref, t, fs, (2 * 26.9355 / C, 0.0), (0.8 / C, 0.5 / C)),
    }
    e = estimate_nonlinear_phase(ref, t, f0, k, 0.3 / C)
    for name, fn in runs.items():
        fn()
        dt, _ = best_of(fn, 3)
        out[f"chirp_ms_per_pulse_{name}"] = dt * 1e3
    return out


def bench_spaceborne(n=64):
    """Space-borne sub-images per second: in-process, and through Dask with 1 and 2 workers."""
    import shutil
    import tempfile
    from salkit.params import load_scenario
    from salkit.stack import geo_base, nearest_squints, run_stack, subimage
    ex = Path(__file__).resolve().parents[1] / "examples" / "spaceborne_geo.yaml"
    base = geo_base(load_scenario(ex))
    sq = nearest_squints(n, 3.1, 2e5)
    subimage(base, 0.0, 0)
    t0 = time.perf_counter()
    for i, q in enumerate(sq[:16]):
        subimage(base, q, i)
    out = {"geo_subimages_per_s_in_process": 16 / (time.perf_counter() - t0)}
    for w in (1, 2):
        d = tempfile.mkdtemp()
        try:
            t0 = time.perf_counter()
            run_stack(base, sq, Path(d) / "s.zarr", workers=w)
            out[f"geo_subimages_per_s_dask_{w}_workers"] = n / (time.perf_counter() - t0)
        finally:
            shutil.rmtree(d, ignore_errors=True)
    out["geo_dask_speedup_2_over_1"] = out["geo_subimages_per_s_dask_2_workers"] / out["geo_subimages_per_s_dask_1_workers"]
    out["geo_full_collection_minutes_at_2_workers"] = 11288 / out["geo_subimages_per_s_dask_2_workers"] / 60
    return out


def numpy_fields(scat, exp, d, Y, t):
    """The straightforward NumPy way: for every scan, both fields on a (fast time x scatterer) array."""
    o, lam = exp.optics, d.wavelength
    x_in = -o.focal_transmit * scat.d_x / scat.d_z
    out = np.zeros((Y.size, t.size))
    for n in range(Y.size):
        sg = 1.0 if n % 2 == 0 else -1.0
        y_in = -o.focal_transmit * (scat.y - Y[n]) / scat.d_z
        lit = (np.abs(y_in) <= o.stop_y / 2) & (np.abs(x_in) <= o.stop_x / 2)
        a = scat.amplitude * (d.range / scat.d_z) ** 2 * lit
        s_v = sg * exp.scan.speed * t[:, None] + o.bias_common + o.bias_opposite
        s_p = -sg * exp.scan.speed * t[:, None] + o.bias_common - o.bias_opposite
        ev = a * np.exp(1j * (np.pi * (x_in - s_v) ** 2 / (lam * o.focal_x) + np.pi * y_in ** 2 / (lam * o.focal_y)))
        ep = a * np.exp(1j * (np.pi * (x_in - s_p) ** 2 / (lam * o.focal_x) - np.pi * y_in ** 2 / (lam * o.focal_y)))
        h1, h2 = (ev + ep) / np.sqrt(2), (ev - ep) / np.sqrt(2)
        out[n] = (np.abs(h1) ** 2 - np.abs(h2) ** 2).sum(axis=1)
    return out


def direct_along_track(rows, Y_rows, y_out, d, sign):
    """Time-domain matched filter: out[j] = sum_k rows[k] h(y_j - Y_k), reference matrix times data."""
    u = y_out[:, None] - Y_rows[None, :]
    H = np.where(np.abs(u) <= d.spot_y / 2, np.exp(-sign * 1j * d.along_chirp * u ** 2), 0)
    return (H @ rows) / np.abs(H[H.shape[0] // 2]).sum()


def bench_downlooking(extent=2.4):
    from salkit.focus.downlooking import cross_track_focus, focus_downlooking
    from salkit.geometry.downlooking import design
    from salkit.params import load_scenario
    from salkit.simulate.downlooking import (fast_time, make_scatterers, simulate_factored, simulate_fields,
                                             track_positions)
    from salkit.simulate.scene import extended_scatterers
    root = Path(__file__).resolve().parents[1]
    sc = load_scenario(root / "examples" / "downlooking_3d.yaml",
                       [f"scene.extended.extent=[{extent},{extent}]", "scene.extended.pattern=uniform",
                        "scene.extended.spacing=0.018", "scene.extended.speckle=true"])
    exp, d = sc.experiment, design(sc.experiment)
    pos, amp = extended_scatterers(sc.scene.extended, d.resolution_x * d.resolution_y, np.random.default_rng(0))
    scat = make_scatterers(pos, np.abs(amp), np.angle(amp), exp.track.range, 0.0)
    Y = track_positions(exp, d, -extent / 2, extent / 2)
    t = fast_time(d, exp.scan.duration)
    # scatterer-samples actually lit: each scatterer is in the beam for M W_y / Delta-Y scans
    lit_scans = d.spot_y / exp.track.spacing
    work = scat.count * lit_scans * t.size
    t_fac, cur = best_of(lambda: simulate_factored(scat, exp, d, Y), repeat=1)
    sub = make_scatterers(pos[:300], np.abs(amp[:300]), np.angle(amp[:300]), exp.track.range, 0.0)
    Ys = Y[::8]
    simulate_fields(sub, exp, d, Ys[:4])  # compile
    t_fld, a = best_of(lambda: simulate_fields(sub, exp, d, Ys), repeat=1)
    Yn = Ys[Ys.size // 2 - 20: Ys.size // 2 + 20]
    t_np, b = best_of(lambda: numpy_fields(sub, exp, d, Yn, t), repeat=1)
    sub_work_fields = sub.count * Ys.size * t.size
    sub_work_np = sub.count * Yn.size * t.size
    ref = simulate_fields(sub, exp, d, Yn)
    half = extent / 2
    t_img, imgs = best_of(lambda: focus_downlooking(cur, Y, d, exp, y_range=(-half, half), x_range=(-half, half)),
                          repeat=2)
    # along-track stage alone: FFT fast convolution against the direct time-domain matched filter,
    # at this size and for the whole 7.5 m swath
    from salkit.focus.downlooking import along_track_focus
    along = {}
    for tag, hw in (("256", half), ("swath", 0.5 * d.spot_x - 0.05)):
        Yh = track_positions(exp, d, -hw, hw)
        noise = np.random.default_rng(1).standard_normal((Yh.size, t.size))
        spec, x = cross_track_focus(noise, d, exp, (-hw, hw))
        F, YF = spec[0::2], Yh[0::2]
        y_out = YF[(YF >= -hw) & (YF <= hw)]
        t_fft, a1 = best_of(lambda: along_track_focus(F, YF, y_out, d, 1.0), repeat=3)
        t_dir, a2 = best_of(lambda: direct_along_track(F, YF, y_out, d, 1.0), repeat=3)
        along[tag] = (t_fft, t_dir, float(np.abs(a1 - a2).max() / np.abs(a2).max()), f"{y_out.size} x {x.size}")
    return {
        "dl_image_pixels": f"{imgs.forward.shape[0]} x {imgs.forward.shape[1]}",
        "dl_scatterers": scat.count, "dl_scans": int(Y.size), "dl_fast_time_samples": int(t.size),
        "dl_sim_factored_s": t_fac, "dl_sim_factored_scat_samples_per_s": work / t_fac,
        "dl_sim_fields_kernel_scat_samples_per_s": sub_work_fields / t_fld,
        "dl_sim_numpy_fields_scat_samples_per_s": sub_work_np / t_np,
        "dl_sim_kernel_over_numpy": (sub_work_fields / t_fld) / (sub_work_np / t_np),
        "dl_sim_factored_over_numpy": (work / t_fac) / (sub_work_np / t_np),
        "dl_sim_numpy_vs_kernel_max_diff": float(np.abs(b - ref).max() / np.abs(ref).max()),
        "dl_image_s": t_img, "dl_image_pixels_per_s": imgs.forward.size * 2 / t_img,
        "dl_image_scan_samples_per_s": cur.size / t_img,
        "dl_along_fft_s_256": along["256"][0], "dl_along_direct_s_256": along["256"][1],
        "dl_along_fft_speedup_256": along["256"][1] / along["256"][0],
        "dl_along_swath_pixels": along["swath"][3],
        "dl_along_fft_s_swath": along["swath"][0], "dl_along_direct_s_swath": along["swath"][1],
        "dl_along_fft_speedup_swath": along["swath"][1] / along["swath"][0],
        "dl_along_fft_vs_direct_max_diff": max(along["256"][2], along["swath"][2]),
    }


def _synthetic_collection(P, M, R=5000.0, lam=1.55e-6, res=0.02):
    """A spotlight phase history of three points at range R (float64 geometry), P pulses x M
    frequencies, for the given resolution in both dimensions."""
    fc = C / lam
    B = C / (2 * res)
    f = fc + (np.arange(M) - M // 2) * B / M
    L = lam * R / (2 * res)
    y = np.linspace(-L / 2, L / 2, P)
    pos = np.stack([y, np.full(P, -R * 0.8), np.full(P, R * 0.6)], axis=1)
    ref = np.linalg.norm(pos, axis=1)
    ph = np.zeros((P, M), np.complex64)
    for t in np.array([[0, 0, 0], [0.3, 0.2, 0], [-0.5, -0.4, 0]]):
        dR = np.linalg.norm(pos - t, axis=1) - ref
        ph += np.exp(-4j * np.pi * f[None, :] * dR[:, None] / C).astype(np.complex64)
    return ph, f, pos, ref, res


def _ffbp_problem(n):
    """The synthetic collection of N pulses and its N x N grid at 0.8 of the resolution, with the
    FFBP kernels compiled on a small part of it."""
    from salkit.focus.ffbp import ffbp
    from salkit.focus.formers import ImageGrid
    from salkit.geometry.collection import grid_axes, plane_from
    from salkit.params import Grid
    ph, f, pos, ref, res = _synthetic_collection(n, n)
    g = Grid(nx=n, ny=n, dx=0.8 * res, dy=0.8 * res)
    plane = plane_from(np.array([1.0, 0, 0]), pos[n // 2], "slant")
    az, rg = grid_axes(g)
    M = ph.shape[1]
    ffbp(ph[:256], f, pos[:256], ref[:256], ImageGrid(plane, az[:32], rg[:32], g), np.ones(256), np.ones(M))  # every level compiled
    return ph, f, pos, ref, ImageGrid(plane, az, rg, g)


def bench_ffbp(sizes=((512, None, 3), (1024, 256, 3), (4096, 128, 2))):
    """Fast factorised backprojection against direct backprojection on the same data (N x N pixels,
    N pulses): direct BP timed on blocks of R and 2 rows around the centre, its per-row cost
    extrapolated to the image (the range profiles, a fixed cost, counted once), FFBP on the whole
    image; both the best of the same number of runs (the VM's spread is +-15 %); the image error
    energy on the block."""
    from salkit.focus.backprojection import backproject
    from salkit.focus.ffbp import ffbp
    out = {}
    for n, rows, repeat in sizes:
        ph, f, pos, ref, grid = _ffbp_problem(n)
        plane, az, rg, M = grid.plane, grid.azimuth, grid.range, ph.shape[1]
        t_f, (img, info) = best_of(lambda: ffbp(ph, f, pos, ref, grid, np.ones(n), np.ones(M)), repeat)
        rows = rows or n

        def direct(k):
            sub = slice(n // 2 - k // 2, n // 2 + k // 2)
            a = az[sub]
            t, im = best_of(lambda: backproject(ph, f, pos, ref, plane.points(a, 0 * a), plane.range, rg,
                                                np.ones((a.size, n), np.float32), np.ones(M)), repeat)
            return t, im, sub

        backproject(ph[:8], f, pos[:8], ref[:8], plane.points(az[:2], 0 * az[:2]), plane.range, rg[:8],
                    np.ones((2, 8), np.float32), np.ones(M))
        t_full, ref_img, sub = direct(rows)
        if rows < n:  # the range profiles cost the same for any number of rows: extrapolate the rest
            t_two, _, _ = direct(2)  # the fixed cost (range profiles) and two rows: the widest lever arm
            per_row = (t_full - t_two) / (rows - 2)
            t_d = t_full + per_row * (n - rows)
        else:
            t_d = t_full
        err = np.sum(np.abs(ref_img - img[sub]) ** 2) / np.sum(np.abs(ref_img) ** 2)
        out.update({f"ffbp_{n}_s": t_f, f"ffbp_{n}_direct_bp_s": t_d, f"ffbp_{n}_speedup": t_d / t_f,
                    f"ffbp_{n}_error_db": float(10 * np.log10(err)), f"ffbp_{n}_levels": info["ffbp_levels"],
                    f"ffbp_{n}_polar_samples_per_level": info["ffbp_polar_samples"], f"ffbp_{n}_runs": repeat})
    return out


def bench_ffbp_knobs(n=1024):
    """The accuracy knobs: image error against direct BP, and time (best of 3), over the polar
    oversampling (angle x range) and the leaf size (pulses per first-level sub-image)."""
    from salkit.focus.backprojection import backproject
    from salkit.focus.ffbp import LEAF_PULSES, OVERSAMPLE_ANGLE, OVERSAMPLE_RANGE, ffbp
    from salkit.focus.formers import ImageGrid
    ph, f, pos, ref, grid = _ffbp_problem(n)
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


def _traced(fn):
    """Wall time (s), peak memory the call allocated through NumPy/Python (bytes, tracemalloc:
    numba's own scratch arrays inside kernels are not seen) and the result."""
    import tracemalloc
    tracemalloc.start()
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    t0 = time.perf_counter()
    out = fn()
    dt = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    return dt, peak, out


def bench_scaling(sizes=(256, 512, 1024)):
    """Growth of each stage's cost with size: simulation, phase history, direct BP, FFBP, PFA and
    PGA on N x N pixels from N pulses (the shared spotlight problem), wall time and peak memory at
    each N, and the exponent a of time ~ N^a fitted over the sizes (least squares in log-log)."""
    from salkit.autofocus.pga import pga
    from salkit.focus import phase_history
    from salkit.focus.formers import ImageGrid, get_former
    from salkit.signals.windows import Window
    from salkit.simulate import simulate
    times: dict = {}
    out = {}
    win = Window("none")
    for n in sizes:
        sc, _ = spotlight_problem(n, n)
        if n == sizes[0]:  # compile every kernel once, untimed
            raw = simulate(sc)
            ph = phase_history(raw)
            grid = ImageGrid.of(ph, sc.processing.grid)
            for name in ("bp", "ffbp", "pfa"):
                img = get_former(name)(ph, grid, win).image
            pga(img, max_iter=2)
        stages = {}
        stages["simulate"] = _traced(lambda: simulate(sc))
        raw = stages["simulate"][2]
        stages["phase_history"] = _traced(lambda: phase_history(raw))
        ph = stages["phase_history"][2]
        grid = ImageGrid.of(ph, sc.processing.grid)
        for name in ("bp", "ffbp", "pfa"):
            stages[name] = _traced(lambda: get_former(name)(ph, grid, win))
        img = stages["bp"][2].image
        stages["pga_10_iterations"] = _traced(lambda: pga(img, max_iter=10, tol=0.0))
        for k, (dt, peak, _) in stages.items():
            times.setdefault(k, []).append(dt)
            out[f"scaling_{k}_N{n}_s"] = dt
            out[f"scaling_{k}_N{n}_peak_MiB"] = peak / 2**20
    x = np.log(np.asarray(sizes, float))
    for k, ts in times.items():
        out[f"scaling_{k}_exponent"] = float(np.polyfit(x, np.log(ts), 1)[0])
    return out


def numpy_propagation(field, wavelength, dx, distance, screens):
    """The same split-step propagation written plainly: np.fft, the transfer function made for
    every step, the screen phasor and the field in complex128."""
    n = field.shape[0]
    f = np.fft.fftfreq(n, dx)
    fx, fy = np.meshgrid(f, f, indexing="ij")
    dz = distance / len(screens)
    u = field.astype(np.complex128)
    steps = [dz / 2] + [dz] * (len(screens) - 1) + [dz / 2]
    for i, step in enumerate(steps):
        u = np.fft.ifft2(np.fft.fft2(u) * np.exp(-1j * np.pi * wavelength * step * (fx ** 2 + fy ** 2)))
        if i < len(screens):
            u = u * np.exp(1j * screens[i])
    return u


def bench_propagation(sizes=(256, 512, 1024), layers=10):
    """Wave-optics propagation per realisation (10 screens) against the plain NumPy version, same
    screens, same machine; the fields compared."""
    from salkit.atmosphere.waveoptics import periodic_screens, propagate
    out = {}
    lam, L = 1.55e-6, 1000.0
    for n in sizes:
        dx = 0.004
        scr = periodic_screens(n, dx, 0.2, layers, np.random.default_rng(0))
        u0 = np.ones((n, n), np.complex128)
        propagate(u0, lam, dx, L, scr)
        t_s, a = best_of(lambda: propagate(u0, lam, dx, L, scr), 3)
        t_n, b = best_of(lambda: numpy_propagation(u0, lam, dx, L, scr), 2)
        out[f"propagation_{n}_salkit_s"] = t_s
        out[f"propagation_{n}_numpy_s"] = t_n
        out[f"propagation_{n}_speedup"] = t_n / t_s
        out[f"propagation_{n}_max_difference"] = float(np.abs(a - b).max())
    return out


def bench_turbulence_wave_optics(classes=("weak", "medium", "strong")):
    """Cost of the seed 004 point-target simulation per turbulence class (51 pulses, 50 layers):
    phase-only screens against wave optics through the same screens (one beam propagation per
    pulse on the planned grid); the grid side and the time per pulse."""
    import salkit
    from salkit.geometry.collection import build_collection
    from salkit.params import load_scenario
    from salkit.simulate import screen_size, simulate, wave_optics_plan
    base = load_scenario(salkit.example_path("turbulence_pga"), ["experiment=null", "receiver.noise.enabled=false"])
    cn2s = {"weak": 1e-15, "medium": 1e-14, "strong": 1e-13}
    out = {}
    simulate(load_scenario(salkit.example_path("turbulence_pga"), ["experiment=null", "atmosphere.cn2=1e-15",
                                                                   "atmosphere.model=wave_optics"]))  # compile
    for name in classes:
        wo = base.model_copy(update={"atmosphere": base.atmosphere.model_copy(
            update={"cn2": cn2s[name], "model": "wave_optics"})})
        col = build_collection(wo)
        n_screen = screen_size(wo, col)
        plan, _ = wave_optics_plan(wo, col)
        wo = wo.model_copy(update={"atmosphere": wo.atmosphere.model_copy(update={"screen_n": n_screen})})
        ps = wo.model_copy(update={"atmosphere": wo.atmosphere.model_copy(update={"model": "phase_screen"})})
        t_ps, _ = best_of(lambda: simulate(ps), 1)
        t_wo, _ = best_of(lambda: simulate(wo), 1)
        out[f"wave_optics_{name}_grid_n"] = plan.n
        out[f"wave_optics_{name}_screen_n"] = n_screen
        out[f"wave_optics_{name}_phase_screen_s"] = t_ps
        out[f"wave_optics_{name}_wave_optics_s"] = t_wo
        out[f"wave_optics_{name}_per_pulse_s"] = (t_wo - t_ps) / col.n_pulses
    return out


def bench_wave_structure_function(count=256):
    """The spherical wave's structure function against 6.88 (rho/r0_sph)^(5/3) on a large ensemble
    (1 um over 1 km, spherical sigma_R^2 = 0.2, receiver disc 16 cm): ratio and standard error
    (16 batches) at 4 mm, 2 cm and 4 cm, and the time per realisation."""
    import math as _m
    from salkit.atmosphere import r0_from_cn2
    from salkit.atmosphere.waveoptics import plan_spherical, spherical_wave_ensemble, wave_structure_function
    lam, L = 1e-6, 1000.0
    cn2 = 0.2 / (0.5 * (2 * _m.pi / lam) ** (7 / 6) * L ** (11 / 6))
    s = plan_spherical(lam, L, cn2, receiver=0.16)
    t0 = time.perf_counter()
    f, s = spherical_wave_ensemble(lam, L, cn2, count, seed=11, sampling=s)
    t = time.perf_counter() - t0
    r, d, se = wave_structure_function(f, s.deltan, max_lag=10, batches=16)
    th = 6.88 * (r / r0_from_cn2(cn2, L, lam, "spherical")) ** (5 / 3)
    out = {"wsf_realisations": count, "wsf_grid_n": s.n, "wsf_s_per_realisation": t / count}
    for i in (0, 4, 9):
        mm = round(r[i] * 1e3)
        out[f"wsf_ratio_{mm}mm"] = float(d[i] / th[i])
        out[f"wsf_standard_error_{mm}mm"] = float(se[i] / th[i])
    return out


def main():
    info = {"machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
            "python": platform.python_version(), "numpy": np.__version__}
    res = {}
    only = sys.argv[1:]
    for name, fn in (("backprojection", bench_backprojection), ("pfa", bench_pfa), ("simulation", bench_simulation),
                     ("screens", bench_screens), ("pga", bench_pga), ("chirp", bench_chirp),
                     ("spaceborne", bench_spaceborne), ("downlooking", bench_downlooking), ("outside", bench_outside),
                     ("startup", bench_startup), ("ffbp", bench_ffbp), ("ffbp_knobs", bench_ffbp_knobs), ("accuracy", bench_accuracy),
                     ("scaling", bench_scaling), ("propagation", bench_propagation),
                     ("turbulence_wave_optics", bench_turbulence_wave_optics),
                     ("wave_structure_function", bench_wave_structure_function)):
        if only and name not in only:
            continue
        t0 = time.perf_counter()
        r = fn()
        res.update(r)
        print(f"== {name} ({time.perf_counter() - t0:.1f} s)")
        for k, v in r.items():
            print(f"   {k:<34} {v:.4g}" if isinstance(v, float) else f"   {k:<34} {v}")
    out = Path(__file__).resolve().parent / "last_run.json"
    out.write_text(json.dumps({"info": info, "results": res}, indent=2) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
