"""downlooking: seed 000 design example, a 2.4 m x 2.4 m scene imaged on >= 256 x 256 pixels: raw-data
simulation (factored BLAS path and the numba field kernel against a vectorised NumPy evaluation of
the same fields) and image formation (FFT processor against a direct time-domain along-track matched
filter), with the images compared.

``make bench NAME=downlooking`` (or ``python benchmarks/downlooking.py``) runs it alone.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from common import best_of


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
    from salkit.simulate.downlooking import (
        fast_time,
        make_scatterers,
        simulate_factored,
        simulate_fields,
        track_positions,
    )
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


if __name__ == "__main__":
    import runner
    runner.main(["downlooking"])
