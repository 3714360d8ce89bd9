"""ffbp_leaf_axes: could the wide-angle arc's FFBP leaves be formed by FFT? A study, not a timing.

FFBP's leaves are formed by FFT (``salkit.focus.ffbp.fft_leaves_fit``) where each pulse's range
against its leaf's centre, delta_p = |x - p| - |x - c|, is constant along a polar line: then a line's
values are one inverse transform over the frequencies of the pulses' spectra with their phase ramps.
The lines are of constant u, the cosine of the angle to the image plane's azimuth axis; over the
4-degree arc each leaf's track turns from that axis and climbs, and delta_p moves along a line in the
first order of the pulse's offset. This study takes lines of constant cosine to the leaf's *own*
track direction (first to last pulse, 3-D) instead, points on them by the closed form of a cone
about a tilted axis meeting the plane, and compares with the exact sum over pulses and frequencies:

- zeroth order: delta_p taken at the line's middle (one transform a line);
- first order: what moves, eps_p(r) = delta_p(r) - delta_p(r_mid), taken as its rank-1 part
  a_p b(r) (SVD over the line), exp(j k eps) ~ 1 + j k a_p b(r): a second spectrum sum weighted by
  a_p and k, transformed and scaled by b(r) along the line (two transforms a line).

Printed for the first, middle and last leaf, on the plane's axis and on the leaf's own: the largest
spread of eps over the line's pulses, and the error energy of each order against the exact line
(worst of 5 lines spanning the image, 400 points each).

``python benchmarks/ffbp_leaf_axes.py [N [LEAF ...]]`` (default 4096 16 32; a few minutes).
"""
from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

C = 299792458.0


def _cone_line(c, t, o, ea, er, r, u):
    """Points x in the plane (origin o, axes ea, er) with |x - c| = r and (x - c).t = r u (t a unit
    axis, tilted out of the plane or not), on the image's side of the centre's foot; and which r
    have such a point."""
    nrm = np.cross(ea, er)
    nrm /= np.linalg.norm(nrm)
    tn = t @ nrm
    tp = t - tn * nrm
    tpl = np.linalg.norm(tp)
    ah = tp / tpl
    bh = np.cross(nrm, ah)
    if bh @ er < 0:
        bh = -bh
    h = (c - o) @ nrm
    foot = c - h * nrm
    rho = np.sqrt(np.maximum(r * r - h * h, 0.0))
    cphi = (r * u + h * tn) / (rho * tpl)
    ok = np.abs(cphi) <= 1.0
    cphi = np.clip(cphi, -1.0, 1.0)
    x = foot + rho[:, None] * (cphi[:, None] * ah + np.sqrt(1.0 - cphi ** 2)[:, None] * bh)
    return x, ok


def leaf_line_errors(ph, freq, pos, ref, grid, a: int, b: int, own_axis: bool, lines: int = 5,
                     points: int = 400) -> dict:
    """The eps spread (m) and the zeroth- and first-order errors (dB, worst of ``lines``) of leaf
    pulses a .. b - 1 against the exact sum."""
    kk = 4.0 * np.pi * np.asarray(freq, np.float64) / C
    s = np.asarray(ph[a:b], np.complex128)
    p, rf = pos[a:b], ref[a:b]
    pl = grid.plane
    o, ea, er = pl.origin, pl.azimuth, pl.range
    c = p.mean(axis=0)
    t = (p[-1] - p[0]) if own_axis else np.array(ea, np.float64)
    t = t / np.linalg.norm(t)
    corners = np.array([o + x * ea + y * er for x in (grid.azimuth.min(), grid.azimuth.max())
                        for y in (grid.range.min(), grid.range.max())])
    ec = corners - c
    rc = np.linalg.norm(ec, axis=1)
    uc = ec @ t / rc
    r = np.linspace(rc.min(), rc.max(), points)
    out = {"spread_m": 0.0, "zeroth_db": -np.inf, "first_db": -np.inf}
    for u in np.linspace(uc.min(), uc.max(), lines):
        x, ok = _cone_line(c, t, o, ea, er, r, u)
        R = np.linalg.norm(x[:, None, :] - p[None], axis=-1)  # (points, pulses)
        rx = np.linalg.norm(x - c, axis=1)
        exact = np.einsum("rpm,pm->r", np.exp(1j * kk * (R - rf)[:, :, None]), s)
        d = R - rx[:, None]
        d0 = d[points // 2]
        eps = (d - d0)[ok]
        ramps = s * np.exp(1j * kk[None, :] * (d0 - rf)[:, None])
        base = np.exp(1j * kk[None, :] * rx[ok][:, None])
        zeroth = base @ ramps.sum(axis=0)
        U, S, Vt = np.linalg.svd(eps, full_matrices=False)
        first = zeroth + 1j * (U[:, 0] * S[0]) * (base @ (kk * (Vt[0][:, None] * ramps).sum(axis=0)))
        energy = np.sum(np.abs(exact[ok]) ** 2)
        out["spread_m"] = max(out["spread_m"], float((eps.max(0) - eps.min(0)).max()))
        out["zeroth_db"] = max(out["zeroth_db"], float(10 * np.log10(np.sum(np.abs(zeroth - exact[ok]) ** 2) / energy)))
        out["first_db"] = max(out["first_db"], float(10 * np.log10(np.sum(np.abs(first - exact[ok]) ** 2) / energy)))
    return out


def bench_ffbp_leaf_axes(n: int = 4096, leaves=(16, 32)) -> dict:
    """:func:`leaf_line_errors` on the arc at n^2 for the first, middle and last leaf of each size."""
    from ffbp import _arc
    ph, freq, pos, ref, grid = _arc(n)
    out = {}
    for leaf in leaves:
        count = pos.shape[0] // leaf
        for s in (0, count // 2, count - 1):
            for own in (False, True):
                e = leaf_line_errors(ph, freq, pos, ref, grid, s * leaf, s * leaf + leaf, own)
                key = f"leaf_axes_{leaf}_{s}_{'own' if own else 'plane'}"
                out.update({f"{key}_{k}": v for k, v in e.items()})
                axis = "its own axis" if own else "the plane's axis"
                print(f"leaf of {leaf} pulses #{s:4d} on {axis:16s}: eps spread "
                      f"{e['spread_m'] * 1e6:9.3f} um; zeroth order {e['zeroth_db']:7.1f} dB, first order "
                      f"{e['first_db']:7.1f} dB", flush=True)
    return out


if __name__ == "__main__":
    warnings.simplefilter("ignore")
    args = [int(a) for a in sys.argv[1:]]
    bench_ffbp_leaf_axes(args[0] if args else 4096, tuple(args[1:]) or (16, 32))
