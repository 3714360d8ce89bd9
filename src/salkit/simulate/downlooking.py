"""Raw data of the self-interferometric down-looking SAL, computed from the optical fields.

For every scan n (forward when n is even, backward when odd), fast-time sample t and scatterer q:

1. the two orthogonally polarised stop fields (seed 000 eqs 1 and 8) are evaluated at the stop
   point that the transmit telescope projects onto the scatterer, x_in = -f_t d_x/d_z,
   y_in = -f_t (y - Y)/d_z, with d_z the scatterer's own axial distance (M = d_z/f_t):
   e_V = rect rect exp(j pi (x_in - s_V(t))^2/(lambda f_x)) exp(+j pi y_in^2/(lambda f_y)),
   e_P = rect rect exp(j pi (x_in - s_P(t))^2/(lambda f_x)) exp(-j pi y_in^2/(lambda f_y)),
   forward s_V = v t + S_b + S_a, s_P = -v t + S_b - S_a; backward s_V = -v t + S_b + S_a,
   s_P = v t + S_b - S_a;
2. both are multiplied by the reflectivity, the 1/d_z^2 amplitude, the round-trip phase
   exp(-j 2 k (R - Z)) over the exact distance R (Z, the reference range, is a constant phase for
   every field), and the disturbances (common ones on both, the others
   on each beam separately);
3. the receiving half-wave plate (Jones matrix at angle theta) and the polarising beam splitter
   form the two channels c e_V + s e_P and s e_V - c e_P (c = cos 2 theta, s = sin 2 theta);
4. the balanced detector outputs |ch1|^2 - |ch2|^2, summed over scatterers
   (``aperture_averaged``) or formed after the fields of all scatterers add (``point_detector``).

:func:`simulate_fields` does exactly this in a numba kernel. :func:`simulate_factored` is the fast
path for the common case (aperture-averaged detection, no transmitter-pupil turbulence, no motion
during a scan): the same fields factor into a cross-track matrix (fast time x scatterer) and an
along-track matrix (scan x scatterer), so the current is a complex matrix product (BLAS). A test
holds the two to 1e-5.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

import xarray as xr

from ..errors import ScenarioError
from ..geometry.downlooking import DLDesign, beam_coordinates, design, jones
from ..io.datasets import FORMAT_VERSION, clean_attrs, salkit_version
from ..params.scenario import dump_scenario


@dataclass(frozen=True)
class DLScatterers:
    """Scatterers in beam coordinates (float64): cross-track offset d_x, along-track ground
    position y, axial distance d_z (all m), amplitude |rho| and phase (rad); plus ground positions."""

    d_x: np.ndarray
    y: np.ndarray
    d_z: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    ground: np.ndarray

    @property
    def count(self) -> int:
        """Number of scatterers."""
        return int(self.d_x.size)


def make_scatterers(ground: np.ndarray, amplitude: np.ndarray, phase: np.ndarray, range_m: float,
                    look_angle_deg: float) -> DLScatterers:
    """Scatterers from ground coordinates (x along, y across, z up; m) for a given look geometry.

    Parameters
    ----------
    ground : float64 (N, 3)
        m.
    amplitude, phase : float64 (N,)
        |rho| and rad.
    range_m : float
        Reference range, m.
    look_angle_deg : float
        deg.

    Returns
    -------
    DLScatterers
    """
    g = np.asarray(ground, np.float64).reshape(-1, 3)
    dx, y, dz = beam_coordinates(g, range_m, look_angle_deg)
    return DLScatterers(dx, y, dz, np.asarray(amplitude, np.float64).ravel(),
                        np.asarray(phase, np.float64).ravel(), g)


@dataclass(frozen=True)
class Disturbances:
    """Sampled disturbances (rad) handed to the kernel. Empty arrays mean none."""

    vibration: np.ndarray          # (n_scans,) common
    jitter: np.ndarray             # (n_scans, n_t) common, or (0, 0)
    path_screen: np.ndarray        # (N, N) common screen halfway along the path, or (0, 0)
    path_dx: float
    tx_screen: np.ndarray          # (N, N) screen at the transmit pupil, or (0, 0)
    tx_dx: float
    tx_shift: float                # m per scan
    differential: np.ndarray       # (n_scans,) on the P beam only


def no_disturbance(n_scans: int) -> Disturbances:
    """Disturbances that are all absent.

    Parameters
    ----------
    n_scans : int

    Returns
    -------
    Disturbances
    """
    z2 = np.zeros((0, 0))
    return Disturbances(np.zeros(n_scans), z2, z2, 1.0, z2, 1.0, 0.0, np.zeros(n_scans))


@nb.njit(cache=True, inline="always")
def _bilinear(screen, dx, u, v):
    n = screen.shape[0]
    fx = u / dx + n / 2
    fy = v / dx + n / 2
    fx = fx % (n - 1)
    fy = fy % (n - 1)
    i = int(fx)
    j = int(fy)
    a = fx - i
    b = fy - j
    return ((1 - a) * (1 - b) * screen[i, j] + a * (1 - b) * screen[i + 1, j]
            + (1 - a) * b * screen[i, j + 1] + a * b * screen[i + 1, j + 1])


@nb.njit(parallel=True, cache=True, fastmath=True)
def _fields_kernel(d_x, y, d_z, amp, rho_phase, Y, t, scan_speed, lam, fx, fy, ft, wx, wy, sb, sa, vx,
                   z0, c, s, point_detector, vib, jitter, path_screen, path_dx, tx_screen, tx_dx,
                   tx_shift, diff):
    n_scan = Y.size
    n_t = t.size
    n_q = d_x.size
    out = np.zeros((n_scan, n_t))
    k2 = 4.0 * math.pi / lam
    has_jit = jitter.shape[0] > 0
    has_path = path_screen.shape[0] > 0
    has_tx = tx_screen.shape[0] > 0
    moving = scan_speed != 0.0
    ax = math.pi / (lam * fx)
    ay = math.pi / (lam * fy)
    for n in nb.prange(n_scan):
        sg = 1.0 if (n % 2) == 0 else -1.0  # forward scans on even n
        acc = np.zeros(n_t)
        c1 = np.zeros(n_t, np.complex128)
        c2 = np.zeros(n_t, np.complex128)
        for q in range(n_q):
            x_in = -ft * d_x[q] / d_z[q]
            if abs(x_in) > 0.5 * wx:
                continue
            zq = z0 / d_z[q]
            a = amp[q] * zq * zq
            # per-scatterer quantities for a platform that stands still during the scan
            dy = y[q] - Y[n]
            y_in = -ft * dy / d_z[q]
            lit = abs(y_in) <= 0.5 * wy
            if not moving and not lit:
                continue
            r = math.sqrt(d_x[q] * d_x[q] + dy * dy + d_z[q] * d_z[q])
            ph_c0 = rho_phase[q] - k2 * (r - z0) + vib[n]  # exp(-j 2 k R), R relative to z0 (a constant)
            if has_path:
                ph_c0 += _bilinear(path_screen, path_dx, 0.5 * d_x[q], 0.5 * (y[q] + Y[n]))
            for it in range(n_t):
                tt = t[it]
                if moving:
                    yplat = Y[n] + scan_speed * tt
                    dy = y[q] - yplat
                    y_in = -ft * dy / d_z[q]
                    if abs(y_in) > 0.5 * wy:
                        continue
                    r = math.sqrt(d_x[q] * d_x[q] + dy * dy + d_z[q] * d_z[q])
                    ph_c = rho_phase[q] - k2 * (r - z0) + vib[n]
                    if has_path:
                        ph_c += _bilinear(path_screen, path_dx, 0.5 * d_x[q], 0.5 * (y[q] + yplat))
                else:
                    ph_c = ph_c0
                if has_jit:
                    ph_c += jitter[n, it]
                s_v = sg * vx * tt + sb + sa
                s_p = -sg * vx * tt + sb - sa
                ph_v = ph_c + ax * (x_in - s_v) ** 2 + ay * y_in * y_in
                ph_p = ph_c + ax * (x_in - s_p) ** 2 - ay * y_in * y_in + diff[n]
                if has_tx:
                    # geometric optics: the ray reaching this target point left the stop point x_in
                    # at the local angle of each beam's wavefront and crossed the pupil here
                    uxv = x_in + ft * (x_in - s_v) / fx
                    uxp = x_in + ft * (x_in - s_p) / fx
                    uyv = y_in + ft * y_in / fy + tx_shift * n
                    uyp = y_in - ft * y_in / fy + tx_shift * n
                    ph_v += _bilinear(tx_screen, tx_dx, uxv, uyv)
                    ph_p += _bilinear(tx_screen, tx_dx, uxp, uyp)
                ev = a * complex(math.cos(ph_v), math.sin(ph_v))
                ep = a * complex(math.cos(ph_p), math.sin(ph_p))
                h1 = c * ev + s * ep
                h2 = s * ev - c * ep
                if point_detector:
                    c1[it] += h1
                    c2[it] += h2
                else:
                    acc[it] += (h1.real * h1.real + h1.imag * h1.imag) - (h2.real * h2.real + h2.imag * h2.imag)
        if point_detector:
            for it in range(n_t):
                out[n, it] = (c1[it].real ** 2 + c1[it].imag ** 2) - (c2[it].real ** 2 + c2[it].imag ** 2)
        else:
            for it in range(n_t):
                out[n, it] = acc[it]
    return out


def fast_time(design: DLDesign, duration: float) -> np.ndarray:
    """Fast-time sample instants over one scan, s: -T_f/2 + k / f_s.

    Parameters
    ----------
    design : DLDesign
    duration : float
        Scan duration T_f, s.

    Returns
    -------
    float64 (samples,)
        s.
    """
    return -0.5 * duration + np.arange(design.samples) / design.sample_rate


def track_positions(exp, design: DLDesign, y_min: float, y_max: float) -> np.ndarray:
    """Along-track platform positions Y_n (m) for scenes spanning [y_min, y_max] along track.

    The scans start on an even index (a forward scan) and come in forward/backward pairs.

    Parameters
    ----------
    exp : DownlookingExperiment
    design : DLDesign
    y_min, y_max : float
        m.

    Returns
    -------
    float64
        m.
    """
    tr = exp.track
    half = 0.5 * design.spot_y
    if tr.length is not None:
        a, b = -0.5 * tr.length, 0.5 * tr.length
    else:
        a, b = y_min - half, y_max + half
    n = int(math.ceil((b - a) / tr.spacing)) + 1
    n += n % 2
    return a + tr.spacing * np.arange(n, dtype=np.float64)


def simulate_fields(scat: DLScatterers, exp, design: DLDesign, Y: np.ndarray,
                    dist: Disturbances | None = None) -> np.ndarray:
    """Balanced-detector current (n_scans, n_t) from the optical fields, scatterer by scatterer.

    Parameters
    ----------
    scat : DLScatterers
    exp : DownlookingExperiment
    design : DLDesign
    Y : ndarray
        Along-track platform position of each scan at its mid-point, m.
    dist : Disturbances, optional

    Returns
    -------
    ndarray float64 (n_scans, n_t)
        Detector output, in units of the balanced beat of a unit scatterer at the reference range.
    """
    o, s = exp.optics, exp.scan
    t = fast_time(design, s.duration)
    dist = dist or no_disturbance(Y.size)
    c, sn = jones(o.hwp_angle_deg)
    scan_speed = exp.track.speed or 0.0
    return _fields_kernel(scat.d_x, scat.y, scat.d_z, scat.amplitude, scat.phase, np.asarray(Y, np.float64),
                          t, float(scan_speed), design.wavelength, o.focal_x, o.focal_y, o.focal_transmit,
                          o.stop_x, o.stop_y, o.bias_common, o.bias_opposite, s.speed, design.range, c, sn,
                          exp.detection == "point_detector", dist.vibration, dist.jitter, dist.path_screen,
                          dist.path_dx, dist.tx_screen, dist.tx_dx, dist.tx_shift, dist.differential)


def simulate_factored(scat: DLScatterers, exp, design: DLDesign, Y: np.ndarray,
                      differential: np.ndarray | None = None, chunk: int = 16384) -> np.ndarray:
    """The same current as :func:`simulate_fields` for aperture-averaged detection, as a matrix product.

    For one scatterer the balanced output is (c^2 - s^2)(|e_V|^2 - |e_P|^2) + 4 c s Re(e_V e_P*),
    the first term is zero (equal amplitudes), the round-trip phase and every common-mode
    disturbance cancel in e_V e_P*, and e_V e_P* = X(t, q) Y(n, q) with
    X = exp(j pi [(x_in - s_V)^2 - (x_in - s_P)^2] / (lambda f_x)) and
    Y = exp(j 2 pi y_in^2 / (lambda f_y)) (times amplitudes and rects). Valid without motion
    during the scan and without transmitter-pupil turbulence (use :func:`simulate_fields` then).

    Parameters
    ----------
    scat : DLScatterers
    exp : DownlookingExperiment
    design : DLDesign
    Y : float64 (n_scans,)
        m.
    differential : float64 (n_scans,), optional
        Differential phase between the beams, rad.
    chunk : int
        Scatterers per block.

    Returns
    -------
    float64 (n_scans, samples)
    """
    if exp.detection != "aperture_averaged":
        raise ValueError("the factored simulation needs aperture-averaged detection")
    o, s = exp.optics, exp.scan
    lam = design.wavelength
    t = fast_time(design, s.duration)
    c, sn = jones(o.hwp_angle_deg)
    Y = np.asarray(Y, np.float64)
    out = np.zeros((Y.size, t.size))
    x_in = -o.focal_transmit * scat.d_x / scat.d_z
    keep = np.abs(x_in) <= 0.5 * o.stop_x
    if not keep.any():
        return out
    x_in, yq, dz = x_in[keep], scat.y[keep], scat.d_z[keep]
    w = (scat.amplitude[keep] * (design.range / dz) ** 2) ** 2
    kx, ky = np.pi / (lam * o.focal_x), 2 * np.pi / (lam * o.focal_y)
    t_step = _uniform(t)
    for q0 in range(0, x_in.size, chunk):
        sl = slice(q0, q0 + chunk)
        for parity in (0, 1):
            sgn = 1.0 if parity == 0 else -1.0
            # (x - s_V)^2 - (x - s_P)^2 = (s_P - s_V)(2x - s_V - s_P), s_V + s_P = 2 bias_common
            xargs = (x_in[sl], kx, -2.0 * (sgn * s.speed), -2.0 * o.bias_opposite, o.bias_common)
            Xc, Xs = _along_factor(t, t_step[1], *xargs) if t_step is not None else _along_factor_direct(t, *xargs)
            rows = np.arange(parity, Y.size, 2)
            diff = differential[rows] if differential is not None else np.zeros(rows.size)
            args = (diff, yq[sl], dz[sl], w[sl], ky, -o.focal_transmit, 0.5 * o.stop_y)
            uniform = _uniform(Y[rows])
            Yc, Ys = (_scan_factor(*uniform, rows.size, *args) if uniform is not None
                      else _scan_factor_direct(Y[rows], *args))
            # Re(Y X^T) = Yc Xc^T - Ys Xs^T: two real products where the complex one takes four
            out[rows] += (4 * c * sn) * (Yc @ Xc.T - Ys @ Xs.T)
    return out


def _uniform(Y: np.ndarray):
    """(Y0, dY) where Y_n = Y0 + n dY to 1e-12 of the span (scan positions as
    :func:`track_positions` makes them), else None."""
    if Y.size < 2:
        return (float(Y[0]), 0.0) if Y.size else None
    n = np.arange(Y.size)
    dY = float(Y[-1] - Y[0]) / (Y.size - 1)
    dev = float(np.max(np.abs(Y - (Y[0] + n * dY))))
    return (float(Y[0]), dY) if dev <= 1e-12 * max(float(np.max(np.abs(Y))), abs(dY) * Y.size) else None


@nb.njit(parallel=True, cache=True)
def _along_factor_direct(t, x, k, rate, offset, centre):
    """X(t, q) = exp(j k (rate t + offset) 2 (x_q - centre)) as its real and imaginary parts,
    float32 each, the phase in float64."""
    re = np.empty((t.size, x.size), np.float32)
    im = np.empty((t.size, x.size), np.float32)
    for i in nb.prange(t.size):
        a = k * (rate * t[i] + offset)
        for q in range(x.size):
            ph = a * 2.0 * (x[q] - centre)
            re[i, q] = math.cos(ph)
            im[i, q] = math.sin(ph)
    return re, im


@nb.njit(parallel=True, cache=True)
def _scan_factor_direct(Yr, diff, y, dz, w, k, scale, half_stop):
    """Y(n, q) = w_q exp(j (k y_in^2 - diff_n)) inside the field stop (|y_in| <= half_stop), else 0,
    with y_in = scale (y_q - Y_n) / dz_q, as its real and imaginary parts, float32 each, the phase
    in float64."""
    re = np.zeros((Yr.size, y.size), np.float32)
    im = np.zeros((Yr.size, y.size), np.float32)
    for n in nb.prange(Yr.size):
        for q in range(y.size):
            yi = scale * (y[q] - Yr[n]) / dz[q]
            if abs(yi) <= half_stop:
                ph = k * yi * yi - diff[n]
                re[n, q] = w[q] * math.cos(ph)
                im[n, q] = w[q] * math.sin(ph)
    return re, im


#: Rows between the exact (sin, cos) anchors of the factors' recurrences: a complex128 product a
#: row drifts by about 1e-16 rad each, far below the float32 the factors are stored in.
ANCHOR_ROWS = 32


@nb.njit(cache=True, inline="always")
def _anchor_block(blk, rows, Q):
    """Rows first .. last (exclusive) of anchor block ``blk``, and its phasor and step buffers
    (real and imaginary parts, ``Q`` each)."""
    first = blk * ANCHOR_ROWS
    return first, min(first + ANCHOR_ROWS, rows), np.empty(Q), np.empty(Q), np.empty(Q), np.empty(Q)


@nb.njit(parallel=True, cache=True, fastmath=False)
def _along_factor(t, dt, x, k, rate, offset, centre):
    """X(t, q) = exp(j k (rate t + offset) 2 (x_q - centre)) at uniform t_i (step dt) as its real
    and imaginary parts, float32 each. The phase is linear in t: exact (float64 sin, cos) every
    :data:`ANCHOR_ROWS` rows, a complex128 rotation by exp(j k rate dt 2 (x_q - centre)) between."""
    Q = x.size
    nt = t.size
    re = np.empty((nt, Q), np.float32)
    im = np.empty((nt, Q), np.float32)
    for blk in nb.prange((nt + ANCHOR_ROWS - 1) // ANCHOR_ROWS):
        i0, i1, zr, zi, wr, wi = _anchor_block(blk, nt, Q)
        a = k * (rate * t[i0] + offset)
        da = k * rate * dt
        for q in range(Q):
            b = 2.0 * (x[q] - centre)
            zr[q] = math.cos(a * b)
            zi[q] = math.sin(a * b)
            wr[q] = math.cos(da * b)
            wi[q] = math.sin(da * b)
        for i in range(i0, i1):
            for q in range(Q):
                re[i, q] = zr[q]
                im[i, q] = zi[q]
                r = zr[q] * wr[q] - zi[q] * wi[q]
                zi[q] = zr[q] * wi[q] + zi[q] * wr[q]
                zr[q] = r
    return re, im


@nb.njit(parallel=True, cache=True, fastmath=False)
def _scan_factor(Y0, dY, ny, diff, y, dz, w, k, scale, half_stop):
    """Y(n, q) = w_q exp(j (k y_in^2 - diff_n)) inside the field stop (|y_in| <= half_stop), else 0,
    with y_in = scale (y_q - Y_n) / dz_q at Y_n = Y0 + n dY (n < ny), as its real and imaginary
    parts, float32 each. k y_in^2 is quadratic in n: exact (float64 sin, cos) every
    :data:`ANCHOR_ROWS` rows, a second-order complex128 recurrence between."""
    Q = y.size
    re = np.empty((ny, Q), np.float32)
    im = np.empty((ny, Q), np.float32)
    sq = np.empty(Q)
    vr = np.empty(Q)
    vi = np.empty(Q)
    for q in nb.prange(Q):
        sq[q] = scale / dz[q]
        B = sq[q] * dY
        vr[q] = math.cos(2.0 * k * B * B)
        vi[q] = math.sin(2.0 * k * B * B)
    for blk in nb.prange((ny + ANCHOR_ROWS - 1) // ANCHOR_ROWS):
        n0, n1, zr, zi, wr, wi = _anchor_block(blk, ny, Q)
        for q in range(Q):
            A = sq[q] * (y[q] - (Y0 + n0 * dY))  # y_in at row n0; y_in(n0 + m) = A - m B
            B = sq[q] * dY
            ph = k * A * A
            zr[q] = math.cos(ph)
            zi[q] = math.sin(ph)
            d = k * B * (B - 2.0 * A)  # phase step n0 -> n0 + 1; each next step adds 2 k B^2
            wr[q] = math.cos(d)
            wi[q] = math.sin(d)
        for n in range(n0, n1):
            cd = math.cos(diff[n])
            sd = -math.sin(diff[n])
            Yn = Y0 + n * dY
            for q in range(Q):
                g = w[q] if abs(sq[q] * (y[q] - Yn)) <= half_stop else 0.0  # branch-free: vectorises
                re[n, q] = g * (zr[q] * cd - zi[q] * sd)
                im[n, q] = g * (zr[q] * sd + zi[q] * cd)
                r = zr[q] * wr[q] - zi[q] * wi[q]
                zi[q] = zr[q] * wi[q] + zi[q] * wr[q]
                zr[q] = r
                r = wr[q] * vr[q] - wi[q] * vi[q]
                wi[q] = wr[q] * vi[q] + wi[q] * vr[q]
                wr[q] = r
    return re, im


def add_receiver_noise(current: np.ndarray, snr_db: float | None, hwp_angle_deg: float,
                       rng: np.random.Generator) -> np.ndarray:
    """White Gaussian receiver noise; SNR per sample against the beat amplitude of a unit scatterer.

    Parameters
    ----------
    current : float (n_scans, samples)
    snr_db : float or None
        dB; None adds nothing.
    hwp_angle_deg : float
        deg.
    rng : numpy.random.Generator

    Returns
    -------
    float ndarray
    """
    if snr_db is None:
        return current
    c, s = jones(hwp_angle_deg)
    sigma = abs(4 * c * s) / 10 ** (snr_db / 20)
    return current + sigma * rng.standard_normal(current.shape)


def simulate_current(scat: DLScatterers, exp, d: DLDesign, Y: np.ndarray, dist: Disturbances | None = None,
                     rng: np.random.Generator | None = None, force_fields: bool = False) -> np.ndarray:
    """Balanced current of a scene: the field kernel, or its factored form where that is exact.

    Parameters
    ----------
    scat : DLScatterers
    exp : DownlookingExperiment
    d : DLDesign
    Y : float64 (n_scans,)
        m.
    dist : Disturbances, optional
    rng : numpy.random.Generator, optional
        Adds receiver noise when given.
    force_fields : bool
        Always use the field kernel.

    Returns
    -------
    float64 (n_scans, samples)
    """
    fields = (force_fields or exp.detection == "point_detector" or exp.track.speed is not None
              or (dist is not None and (dist.tx_screen.size > 0)) or scat.count <= 64)
    if fields:
        cur = simulate_fields(scat, exp, d, Y, dist)
    else:
        diff = None if dist is None or not np.any(dist.differential) else dist.differential
        cur = simulate_factored(scat, exp, d, Y, diff)
    if rng is not None:
        cur = add_receiver_noise(cur, exp.noise_snr_db, exp.optics.hwp_angle_deg, rng)
    return cur


def raw_dataset(current: np.ndarray, Y: np.ndarray, t: np.ndarray, d: DLDesign, scenario_text: str) -> xr.Dataset:
    """The balanced-detector current as a labelled dataset (data-format.md, DL-SAL raw data).

    Parameters
    ----------
    current : float (n_scans, samples)
    Y : float64 (n_scans,)
        m.
    t : float64 (samples,)
        s.
    d : DLDesign
    scenario_text : str

    Returns
    -------
    xarray.Dataset
    """
    at = {"salkit_kind": "raw_downlooking", "salkit_format": FORMAT_VERSION, "salkit_version": salkit_version(),
          "scenario": scenario_text}
    at.update({f"design_{k}": v for k, v in d.as_dict().items()})
    return xr.Dataset(
        {"current": (("scan", "fast_time"), current.astype(np.float32),
                     {"long_name": "balanced detector output", "units": "unit-scatterer beat"}),
         "forward": (("scan",), (np.arange(Y.size) % 2 == 0).astype(np.int8),
                     {"long_name": "1 for a forward scan, 0 for a backward scan"})},
        coords={"along_track": ("scan", np.asarray(Y, np.float64), {"units": "m"}),
                "fast_time": ("fast_time", np.asarray(t, np.float64), {"units": "s"})},
        attrs=clean_attrs(at))


def simulate_downlooking(scenario, progress=None, noise: bool | None = None,
                         rng: np.random.Generator | None = None) -> xr.Dataset:
    """Raw data (balanced current) of a down-looking scenario's point targets, by the field kernel.

    Parameters
    ----------
    scenario : DownlookingScenario
    progress : callable, optional
        ``progress(done, total)``, called at the end.
    noise : bool, optional
        Add the receiver noise of ``experiment.noise_snr_db`` (default True).
    rng : numpy.random.Generator, optional
        Default: seeded from ``scenario.seed``.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind = raw_downlooking`` (docs/data-format.md): ``current`` (scan, fast_time).

    Raises
    ------
    ScenarioError
        Without point targets.
    """
    exp = scenario.experiment
    d = design(exp)
    if not scenario.scene.points:
        raise ScenarioError("scene.points", [], "the down-looking raw data needs at least one point target")
    pts = scenario.scene.points
    ground = np.array([[p.x, p.y, p.z] for p in pts], np.float64)
    scat = make_scatterers(ground, np.array([p.amplitude for p in pts]), np.array([p.phase for p in pts]),
                           exp.track.range, exp.track.look_angle_deg)
    Y = track_positions(exp, d, float(ground[:, 0].min()), float(ground[:, 0].max()))
    rng = rng if rng is not None else np.random.default_rng(scenario.seed)
    cur = simulate_current(scat, exp, d, Y, None, rng if noise is not False else None, force_fields=True)
    if progress:
        progress(Y.size, Y.size)
    return raw_dataset(cur, Y, fast_time(d, exp.scan.duration), d, dump_scenario(scenario))
