"""Numba kernels of the dechirped-echo simulator.

Both kernels compute, for each pulse p, fast-time sample n (time t relative to the dechirp
reference delay) and scatterer s with two-way delay offset dtau = 2 (R - R_ref)/c,

    s[p, n] += a_s * g_ps * exp(j [Phi(t - dtau) - Phi(t)]),   |t - dtau| <= T_p/2,

where Phi is the transmitted phase and g the two-way beam gain. For a linear chirp the phase is
-2 pi (f0 + k t) dtau + pi k dtau^2 (the last term is the residual video phase). Ranges and
phases are float64; only the per-sample rotation table and the accumulator are float32.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..atmosphere.path import path_phase
from ..constants import SPEED_OF_LIGHT
from ..signals.vectors import LANES, caxpy16

_TWO_PI = 2.0 * math.pi
_BLOCK = LANES  # samples a block of the linear chirp's phase recurrence


@njit(cache=True, inline="always")
def _beam(dx, dy, dz, R, bx, by, bz, table, dsin):
    cosb = (dx * bx + dy * by + dz * bz) / R
    if cosb <= 0.0:
        return 0.0
    s2 = 1.0 - cosb * cosb
    sinb = math.sqrt(s2) if s2 > 0.0 else 0.0
    fi = sinb / dsin
    if fi >= table.shape[0] - 1:
        return 0.0
    i0 = int(fi)
    fr = fi - i0
    return table[i0] * (1.0 - fr) + table[i0 + 1] * fr


@njit(parallel=True, cache=True, fastmath=False)
def simulate_linear(pos, ref, bore, scat, amp_re, amp_im, t0, dt, f0, k, tp, table, dsin,
                    out_re, out_im, scr, scr_z, scr_org, scr_dx, u0, ax_a, ax_b, gain):
    """Stop-and-go, linear chirp: phase recurrence over fast time in blocks of 16 samples, each
    block's sixteen samples accumulated as one vector (:func:`salkit.signals.vectors.caxpy16`).

    ``scr`` (L, n, n) are turbulence screens (L = 0: none); each echo then carries the two-way
    path phase, twice the one-way phase along the antenna-scatterer ray (see atmosphere.path).
    ``gain`` (P, S) complex, when not empty, replaces the beam pattern: each echo is weighted by
    its two-way complex gain (wave optics, :mod:`salkit.atmosphere.beam`).

    Parameters
    ----------
    pos, ref, bore, scat, amp_re, amp_im, t0, dt, f0, k, tp, table, dsin, out_re, out_im, scr, scr_z, scr_org, scr_dx, u0, ax_a, ax_b, gain
        Geometry (float64, m), reflectivities, fast time (s), chirp (Hz, Hz/s, s), beam table,
        output planes (float32, filled in place), screens and gains; see
        :func:`salkit.simulate.echo_signal`.
    """
    P = pos.shape[0]
    S = scat.shape[0]
    N = out_re.shape[1]
    B = _BLOCK
    c = SPEED_OF_LIGHT
    for p in prange(P):
        acc_re = np.zeros(N + B, np.float32)  # a block's width of padding: the last block's masked lanes
        acc_im = np.zeros(N + B, np.float32)
        pw_re = np.empty(B, np.float32)
        pw_im = np.empty(B, np.float32)
        px, py, pz = pos[p, 0], pos[p, 1], pos[p, 2]
        bx, by, bz = bore[p, 0], bore[p, 1], bore[p, 2]
        rp = ref[p]
        for s in range(S):
            dx = scat[s, 0] - px
            dy = scat[s, 1] - py
            dz = scat[s, 2] - pz
            R = math.sqrt(dx * dx + dy * dy + dz * dz)
            if gain.shape[0] > 0:
                gr, gi = gain[p, s].real, gain[p, s].imag
            else:
                gr, gi = _beam(dx, dy, dz, R, bx, by, bz, table, dsin), 0.0
                if gr < 1e-7:
                    continue
            dtau = 2.0 * (R - rp) / c
            nlo = int(math.ceil((dtau - 0.5 * tp - t0) / dt))
            nhi = int(math.floor((dtau + 0.5 * tp - t0) / dt))
            if nlo < 0:
                nlo = 0
            if nhi > N - 1:
                nhi = N - 1
            if nlo > nhi:
                continue
            # phase in cycles at n = nlo, reduced in float64
            cyc = -(f0 + k * (t0 + nlo * dt)) * dtau + 0.5 * k * dtau * dtau
            cyc -= np.floor(cyc)
            step = -_TWO_PI * k * dt * dtau
            ph = _TWO_PI * cyc
            if scr.shape[0] > 0:
                ph += 2.0 * path_phase(px, py, pz, scat[s, 0], scat[s, 1], scat[s, 2], scr, scr_z, scr_org,
                                       scr_dx, u0, ax_a, ax_b)
            ar = amp_re[s] * gr - amp_im[s] * gi
            ai = amp_re[s] * gi + amp_im[s] * gr
            cph, sph = math.cos(ph), math.sin(ph)
            cur_re = ar * cph - ai * sph
            cur_im = ar * sph + ai * cph
            # rotation table by recurrence from one sin/cos pair (float64, then float32)
            r1_re = math.cos(step)
            r1_im = math.sin(step)
            q_re = 1.0
            q_im = 0.0
            for j in range(B):
                pw_re[j] = q_re
                pw_im[j] = q_im
                tq = q_re * r1_re - q_im * r1_im
                q_im = q_re * r1_im + q_im * r1_re
                q_re = tq
            rb_re = q_re
            rb_im = q_im
            n = nlo
            while n <= nhi:  # sixteen samples a block, the last block's lanes past nhi masked
                caxpy16(acc_re, acc_im, pw_re, pw_im, n, np.float32(cur_re), np.float32(cur_im), min(B, nhi + 1 - n))
                tr = cur_re * rb_re - cur_im * rb_im
                cur_im = cur_re * rb_im + cur_im * rb_re
                cur_re = tr
                n += B
        for n in range(N):
            out_re[p, n] = acc_re[n]
            out_im[p, n] = acc_im[n]


@njit(cache=True, inline="always")
def _poly_diff(t, d, m):
    """(t - d)**m - t**m, factorised to avoid cancellation: -d * sum_i (t-d)**i t**(m-1-i)."""
    a = t - d
    acc = 0.0
    ai = 1.0
    for i in range(m):
        acc += ai * t ** (m - 1 - i)
        ai *= a
    return -d * acc


@njit(cache=True, inline="always")
def _etab(x, e_t0, e_dt, e_tab):
    """Linear interpolation of the tabulated chirp phase error (rad) at time x (s)."""
    if e_tab.shape[0] == 0:
        return 0.0
    u = (x - e_t0) / e_dt
    if u <= 0.0:
        return e_tab[0]
    m = e_tab.shape[0] - 1
    if u >= m:
        return e_tab[m]
    i = int(u)
    f = u - i
    return e_tab[i] * (1.0 - f) + e_tab[i + 1] * f


@njit(parallel=True, cache=True, fastmath=False)
def simulate_exact(pos, vel, ref, bore, scat, amp_re, amp_im, t0, dt, f0, k, tp, coeffs, intra,
                   table, dsin, out_re, out_im, scr, scr_z, scr_org, scr_dx, u0, ax_a, ax_b,
                   gain, e_t0, e_dt, e_tab, n_dt, n_echo_t0, n_echo, n_lo_t0, n_lo, n_lo_shift):
    """Per-sample evaluation: polynomial chirp nonlinearity, laser phase noise and optional
    intra-pulse motion.

    ``coeffs[m]`` multiplies t**(m+2) in the frequency sweep (Hz/s**(m+2)); ``e_tab`` (spacing
    ``e_dt`` from ``e_t0``) tabulates an arbitrary chirp phase error e(t), rad (empty: none); with
    intra-pulse motion the antenna is at pos + vel * t during sample t. The laser's phase noise
    (empty ``n_echo``: none) is tabulated per pulse at spacing ``n_dt``: the echo of delay offset d
    carries ``n_echo[p]`` at t - d (from ``n_echo_t0``), the local oscillator ``n_lo[p]`` at
    t + ``n_lo_shift[p]`` (from ``n_lo_t0[p]``), two windows of one Wiener path.

    Parameters
    ----------
    pos, vel, ref, bore, scat, amp_re, amp_im, t0, dt, f0, k, tp, coeffs, intra, table, dsin, out_re, out_im, scr, scr_z, scr_org, scr_dx, u0, ax_a, ax_b, gain, e_t0, e_dt, e_tab, n_dt, n_echo_t0, n_echo, n_lo_t0, n_lo, n_lo_shift
        As :func:`simulate_linear`, with the antenna velocity (m/s), the chirp polynomial, the
        tabulated chirp phase error and the tabulated phase noise (rad, s).
    """
    P = pos.shape[0]
    S = scat.shape[0]
    N = out_re.shape[1]
    c = SPEED_OF_LIGHT
    M = coeffs.shape[0]
    noisy = n_echo.shape[0] > 0
    for p in prange(P):
        for s in range(S):
            dx0 = scat[s, 0] - pos[p, 0]
            dy0 = scat[s, 1] - pos[p, 1]
            dz0 = scat[s, 2] - pos[p, 2]
            R0 = math.sqrt(dx0 * dx0 + dy0 * dy0 + dz0 * dz0)
            if gain.shape[0] > 0:
                gr, gi = gain[p, s].real, gain[p, s].imag
            else:
                gr, gi = _beam(dx0, dy0, dz0, R0, bore[p, 0], bore[p, 1], bore[p, 2], table, dsin), 0.0
                if gr < 1e-7:
                    continue
            ar = amp_re[s] * gr - amp_im[s] * gi
            ai = amp_re[s] * gi + amp_im[s] * gr
            if scr.shape[0] > 0:  # frozen screens: the path phase of the pulse
                tph = 2.0 * path_phase(pos[p, 0], pos[p, 1], pos[p, 2], scat[s, 0], scat[s, 1], scat[s, 2],
                                       scr, scr_z, scr_org, scr_dx, u0, ax_a, ax_b)
                ctp, stp = math.cos(tph), math.sin(tph)
                ar, ai = ar * ctp - ai * stp, ar * stp + ai * ctp
            for n in range(N):
                t = t0 + n * dt
                if intra:
                    dx = dx0 - vel[p, 0] * t
                    dy = dy0 - vel[p, 1] * t
                    dz = dz0 - vel[p, 2] * t
                    R = math.sqrt(dx * dx + dy * dy + dz * dz)
                else:
                    R = R0
                d = 2.0 * (R - ref[p]) / c
                if abs(t - d) > 0.5 * tp:
                    continue
                cyc = -f0 * d + 0.5 * k * _poly_diff(t, d, 2)
                for m in range(M):
                    cyc += coeffs[m] / (m + 3) * _poly_diff(t, d, m + 3)
                cyc -= np.floor(cyc)
                ph = _TWO_PI * cyc + _etab(t - d, e_t0, e_dt, e_tab) - _etab(t, e_t0, e_dt, e_tab)
                if noisy:  # the laser's phase when the echo left, less the local oscillator's now
                    ph += (_etab(t - d, n_echo_t0, n_dt, n_echo[p])
                           - _etab(t + n_lo_shift[p], n_lo_t0[p], n_dt, n_lo[p]))
                cph, sph = math.cos(ph), math.sin(ph)
                out_re[p, n] += np.float32(ar * cph - ai * sph)
                out_im[p, n] += np.float32(ar * sph + ai * cph)
