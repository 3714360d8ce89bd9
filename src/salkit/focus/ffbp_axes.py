"""FFBP's leaves on their own axes: polar lines of constant direction cosine to each leaf's own track.

The FFT leaves (:func:`salkit.focus.ffbp._fft_leaves`) need each pulse's range against its leaf's
centre, delta_p = |x - p| - |x - c|, constant along a polar line. On lines of constant cosine to the
image plane's azimuth axis e_a that holds for a straight track along e_a; over a curved or climbing
track (an arc), the leaf's pulses leave that axis and delta_p moves along a line in the first order
of the offset (1.3 mm over 16 pulses of the 4-degree X-band arc at 4096^2). On lines of constant
cosine u = (x - c).t / |x - c| to the leaf's *own* direction t (3-D, its first pulse to its last)
only the pulses' offsets across t (the arc's sagitta) and the second order remain: 2 um over 16
pulses, 9 um over 32. What is left, eps_p(r) = delta_p(r) - delta_p(r_mid) along the line, is
close to a product a_p b(r) (:func:`rank_one`): the leaf then takes exp(j k eps) ~ 1 + j k a_p b(r),
a second sum of the pulses' spectra weighted by a_p and k, transformed and scaled by b(r) along the
line: to -106 dB against the exact sum at 32 pulses (``benchmarks/ffbp_leaf_axes.py``).

Such a line is where the cone of half-angle acos(u) about t through the leaf's centre c meets the
image plane. With n the plane's unit normal, h = (o - c).n (o the plane's origin), t_n = t.n and
t_p = t - t_n n (its part in the plane, |t_p| = sqrt(1 - t_n^2)), a = t_p / |t_p| and b = n x a
(turned towards the image's range axis e_r), the point at range r is

    x - c = h n + alpha a + beta b,   alpha = (u r - h t_n) / |t_p|,   beta = sqrt(r^2 - h^2 - alpha^2),

on the image's side of the line through the centre's foot along a; it exists from the range r+ at
which beta^2 = 0 on (the positive root of (1 - t_n^2 - u^2) r^2 + 2 u h t_n r - h^2). With t = e_a
(t_n = 0) these are the plane axis' lines (:func:`salkit.focus.ffbp_leaves._polar_line`).

Each leaf's frame is a row of 14 float64: h n (3), a (3), b (3), h t_n, t_n, t (3)
(:func:`leaf_frames`).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

#: Columns of a leaf's frame (:func:`leaf_frames`).
FRAME_COLUMNS = 14
#: Smallest part of a leaf's direction in the image plane, |t_p| (a track steeper than 60 degrees
#: to the plane keeps the plane's axis).
MIN_IN_PLANE = 0.5
#: Smallest distance, as a part of the range, from the scene's points to where the own-axis lines
#: turn (beta = 0, the line through the centre's foot along a): the scene must lie well on one side.
MIN_BETA = 1e-3


def leaf_frames(spans: list, centres: np.ndarray, positions: np.ndarray, plane) -> np.ndarray | None:
    """Each leaf's frame for its own-axis polar lines: h n, a, b, h t_n, t_n and t (module text).

    Parameters
    ----------
    spans : list of (int, int)
        The leaves' pulses.
    centres : float64 (S, 3)
        Their centres, m.
    positions : float64 (P, 3)
        Antenna positions, m.
    plane : ImagePlane
        The image plane (origin, azimuth and range axes).

    Returns
    -------
    float64 (S, 14) or None
        None where no leaf has a direction or one leaves the plane steeper than
        :data:`MIN_IN_PLANE` allows; a leaf without one (a single pulse, its ends at one place)
        takes the plane's azimuth axis.

    Examples
    --------
    >>> from salkit.geometry.collection import ImagePlane
    >>> pl = ImagePlane(np.zeros(3), np.array([1.0, 0, 0]), np.array([0, 1.0, 0]))
    >>> pos = np.stack([np.linspace(-1, 1, 4), np.full(4, -100.0), np.full(4, 50.0)], axis=1)
    >>> fr = leaf_frames([(0, 4)], pos.mean(axis=0)[None], pos, pl)
    >>> (fr[0].round(6) + 0.0).tolist()  # h n, a, b, h t_n, t_n, t: the plane axis for a straight level track
    [0.0, 0.0, -50.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]
    """
    ab = np.asarray(spans, np.int64).reshape(-1, 2)
    if ab.size == 0:
        return None
    ea, er = np.asarray(plane.azimuth, np.float64), np.asarray(plane.range, np.float64)
    t = positions[ab[:, 1] - 1] - positions[ab[:, 0]]
    length = np.linalg.norm(t, axis=1)
    # a leaf of one pulse (the last of a collection, 897 = 28 x 32 + 1) or whose ends coincide has no
    # direction: the plane's axis (one pulse's range against itself moves along no line)
    still = ~(length > 0.0)
    if still.all():
        return None
    t = np.where(still[:, None], ea, t / np.where(still, 1.0, length)[:, None])
    n = np.cross(ea, er)
    n /= np.linalg.norm(n)
    tn = t @ n
    tp = t - tn[:, None] * n
    tpl = np.linalg.norm(tp, axis=1)
    if not np.all(tpl >= MIN_IN_PLANE):
        return None
    a = tp / tpl[:, None]
    b = np.cross(n, a)
    b *= np.where(b @ er < 0.0, -1.0, 1.0)[:, None]
    h = (np.asarray(plane.origin, np.float64) - centres) @ n
    return np.column_stack([h[:, None] * n, a, b, h * tn, tn, t])


def line_points(frame: np.ndarray, r: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points x - c of own-axis polar lines, and which exist.

    Parameters
    ----------
    frame : float64 (S, 14)
        :func:`leaf_frames`.
    r : float64 (S, K)
        Ranges from each leaf's centre, m.
    u : float64 (S, L)
        Direction cosines to each leaf's own axis.

    Returns
    -------
    E : float64 (S, L, K, 3)
        x - c, m (where the point exists).
    ok : bool (S, L, K)
        Where it does (beta^2 >= 0).

    Examples
    --------
    >>> from salkit.geometry.collection import ImagePlane
    >>> pl = ImagePlane(np.zeros(3), np.array([1.0, 0, 0]), np.array([0, 1.0, 0]))
    >>> pos = np.array([[-1.0, -100.0, 50.0], [1.0, -99.0, 50.5]])
    >>> fr = leaf_frames([(0, 2)], pos.mean(axis=0)[None], pos, pl)
    >>> E, ok = line_points(fr, np.array([[120.0]]), np.array([[0.2]]))
    >>> bool(ok[0, 0, 0]), round(float(np.linalg.norm(E[0, 0, 0])), 9), round(float(E[0, 0, 0] @ fr[0, 11:]), 9)
    (True, 120.0, 24.0)
    """
    hn, a, b = frame[:, None, None, 0:3], frame[:, None, None, 3:6], frame[:, None, None, 6:9]
    htn, tn = frame[:, 9, None, None], frame[:, 10, None, None]
    h2 = np.einsum("sj,sj->s", frame[:, 0:3], frame[:, 0:3])[:, None, None]
    rr = r[:, None, :]
    alpha = (u[:, :, None] * rr - htn) / np.sqrt(1.0 - tn * tn)
    b2 = rr * rr - h2 - alpha * alpha
    E = hn + alpha[..., None] * a + np.sqrt(np.maximum(b2, 0.0))[..., None] * b
    return E, b2 >= 0.0


def line_start(frame: np.ndarray, r0: np.ndarray, dr: float, n: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The first index of each own-axis polar line (ranges r0 + k dr, k < n) whose point exists
    (n where none): :func:`_own_line_start` over arrays.

    Parameters
    ----------
    frame : float64 (S, 14)
    r0 : float64 (S,)
        m.
    dr : float
        m.
    n : int64 (S,)
    u : float64 (S, L)

    Returns
    -------
    int64 (S, L)
    """
    h2 = np.einsum("sj,sj->s", frame[:, 0:3], frame[:, 0:3])[:, None]
    htn, tn = frame[:, 9, None], frame[:, 10, None]
    A = 1.0 - tn * tn - u * u
    B = 2.0 * u * htn
    with np.errstate(invalid="ignore", divide="ignore"):
        rp = (-B + np.sqrt(B * B + 4.0 * A * h2)) / (2.0 * A)
        lo = np.where(A > 0.0, np.maximum(0.0, np.ceil((rp - r0[:, None]) / dr)), np.inf)
    lo = np.minimum(lo, n[:, None]).astype(np.int64)
    r = r0[:, None] + lo * dr
    alpha = (u * r - htn) / np.sqrt(1.0 - tn * tn)
    short = (r * r - h2 - alpha * alpha < 0.0) & (lo < n[:, None])  # rounding at the root
    return np.minimum(lo + short, n[:, None])


def rank_one(e_a: np.ndarray, e_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The model eps_p(r) ~ a_p b(r) of what moves along a line, from each pulse's eps at the line's
    first and last point: (v_a, v_b) the unit vector that best spans the pulses' (e_a, e_b) (the
    dominant eigenvector of their 2 x 2 scatter), a_p = v_a e_a + v_b e_b; b is then the quadratic
    through v_a at the first point, 0 at the middle and v_b at the last (:func:`_own_weights` does
    the same in the kernel).

    Parameters
    ----------
    e_a, e_b : float64 (..., P)
        eps of each pulse at the line's first and last point, m.

    Returns
    -------
    a : float64 (..., P)
        m.
    v : float64 (..., 2)

    Examples
    --------
    >>> a, v = rank_one(np.array([1.0, 2.0, -3.0]), np.array([-2.0, -4.0, 6.0]))
    >>> (a * v[0]).round(12).tolist(), (a * v[1]).round(12).tolist()
    ([1.0, 2.0, -3.0], [-2.0, -4.0, 6.0])
    """
    saa = np.einsum("...p,...p->...", e_a, e_a)
    sab = np.einsum("...p,...p->...", e_a, e_b)
    sbb = np.einsum("...p,...p->...", e_b, e_b)
    v = np.stack(_dominant(saa, sab, sbb), axis=-1)
    return v[..., 0:1] * e_a + v[..., 1:2] * e_b, v


def _dominant(saa, sab, sbb):
    """The unit dominant eigenvector (v_a, v_b) of [[saa, sab], [sab, sbb]] (zeros for a zero
    matrix), numpy or scalar."""
    lam = 0.5 * (saa + sbb) + np.sqrt(0.25 * (saa - sbb) ** 2 + sab * sab)
    x1, y1 = sab, lam - saa  # two forms of the same vector: the longer is the better conditioned
    x2, y2 = lam - sbb, sab
    n1, n2 = np.hypot(x1, y1), np.hypot(x2, y2)
    use1 = n1 >= n2
    x, y, nn = np.where(use1, x1, x2), np.where(use1, y1, y2), np.maximum(n1, n2)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(nn > 0.0, x / nn, 0.0), np.where(nn > 0.0, y / nn, 0.0)


def quadratic(v_a, v_b, k, lo, hi):
    """b at line indices ``k``: the quadratic through v_a at ``lo``, 0 at the middle and v_b at ``hi``
    (0 where hi <= lo).

    Parameters
    ----------
    v_a, v_b : float or ndarray
    k, lo, hi : ndarray or float
        Indices along the line.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> quadratic(1.0, 3.0, np.array([0.0, 1.0, 2.0]), 0.0, 2.0).tolist()
    [1.0, 0.0, 3.0]
    """
    H = 0.5 * (np.asarray(hi, np.float64) - lo)
    with np.errstate(invalid="ignore", divide="ignore"):
        b1 = np.where(H > 0.0, (v_b - v_a) / (2.0 * H), 0.0)
        b2 = np.where(H > 0.0, (v_a + v_b) / (2.0 * H * H), 0.0)
    x = k - 0.5 * (np.asarray(hi, np.float64) + lo)
    return b1 * x + b2 * x * x


def own_axis_residual(spans: list, centres: np.ndarray, frame: np.ndarray, grids, positions: np.ndarray,
                      dr: float, n_lines: int = 5, n_ranges: int = 17, block: int = 32) -> tuple[float, float]:
    """How far each pulse's range against its leaf's centre moves along the leaf's own-axis polar
    lines, and what the first-order correction leaves of it, m: the largest |eps_p(r)| (eps taken
    from the line's middle, as the kernel does) and the largest |eps_p - a_p b(r)| (:func:`rank_one`,
    :func:`quadratic`) over every leaf, all its pulses, ``n_lines`` of its lines (the edges among
    them) and ``n_ranges`` points along each between its first point in the plane and its last.

    Parameters
    ----------
    spans : list of (int, int)
    centres : float64 (S, 3)
        m.
    frame : float64 (S, 14)
        :func:`leaf_frames`.
    grids : tuple
        The leaves' own-axis polar grids (u0, du, nu, r0, nr).
    positions : float64 (P, 3)
        m.
    dr : float
        m.
    n_lines, n_ranges : int
    block : int
        Leaves at a time (bounded temporaries).

    Returns
    -------
    (float, float)
        m, m.
    """
    u0, du, nu, r0, nr = grids
    ab = np.asarray(spans, np.int64).reshape(-1, 2)
    width = int((ab[:, 1] - ab[:, 0]).max())
    frac = np.linspace(0.0, 1.0, n_lines)
    g = np.linspace(0.0, 1.0, n_ranges)
    eps_max = res_max = 0.0
    for s0 in range(0, ab.shape[0], block):
        sl = slice(s0, min(s0 + block, ab.shape[0]))
        u = u0[sl, None] + du[sl, None] * np.rint(frac[None, :] * (nu[sl, None] - 1))  # (S, L)
        lo = line_start(frame[sl], r0[sl], dr, nr[sl], u).astype(np.float64)
        hi = (nr[sl] - 1).astype(np.float64)[:, None] + 0.0 * lo
        live = lo < hi
        lo = np.where(live, lo, hi)
        kk = np.concatenate([lo[..., None] + (hi - lo)[..., None] * g, (0.5 * (lo + hi))[..., None]], axis=-1)
        # (S, L, K + 1): the sampled points, the middle last; each line's own ranges
        r = r0[sl, None, None] + kk * dr
        E = np.empty(r.shape + (3,))
        ok = np.empty(r.shape, bool)
        for j in range(r.shape[1]):
            Ej, okj = line_points(frame[sl], r[:, j, :], u[:, j:j + 1])
            E[:, j], ok[:, j] = Ej[:, 0], okj[:, 0]
        idx = ab[sl, 0, None] + np.minimum(np.arange(width)[None, :], (ab[sl, 1] - ab[sl, 0] - 1)[:, None])
        q = centres[sl, None, :] - positions[idx]  # (S, W, 3): c - p (short leaves repeat their last pulse)
        delta = pulse_range_differences(E, q)  # (S, L, K + 1, W)
        eps = delta[:, :, :-1] - delta[:, :, -1:]
        a, v = rank_one(eps[:, :, 0], eps[:, :, n_ranges - 1])
        b = quadratic(v[..., 0:1], v[..., 1:2], kk[..., :-1], lo[..., None], hi[..., None])  # (S, L, K)
        res = eps - b[..., None] * a[:, :, None, :]
        use = np.broadcast_to((live[..., None] & ok[..., :-1])[..., None], eps.shape)
        if use.any():
            eps_max = max(eps_max, float(np.abs(eps[use]).max()))
            res_max = max(res_max, float(np.abs(res[use]).max()))
    return eps_max, res_max


def pulse_range_differences(E: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Each pulse's range against its leaf's centre at points of the leaf's lines, |x - p| - |x - c|,
    from small differences: (2 q.(x - c) + |q|^2) / (|x - p| + |x - c|), q = c - p.

    Parameters
    ----------
    E : float64 (S, L, K, 3)
        x - c at K points of L lines of each of S leaves, m.
    q : float64 (S, W, 3)
        c - p of W pulses of each leaf, m.

    Returns
    -------
    float64 (S, L, K, W)
        m.

    Examples
    --------
    >>> E = np.array([3.0, 4.0, 0.0]).reshape(1, 1, 1, 3)
    >>> q = np.array([0.0, -1.0, 0.0]).reshape(1, 1, 3)  # the pulse 1 m further along y: x - p = (3, 3, 0)
    >>> bool(np.isclose(pulse_range_differences(E, q)[0, 0, 0, 0], np.hypot(3.0, 3.0) - 5.0, rtol=1e-14))
    True
    """
    E = np.ascontiguousarray(E, np.float64)
    q = np.ascontiguousarray(q, np.float64)
    out = np.empty(E.shape[:3] + (q.shape[1],))
    _range_differences(E, q, out)
    return out


@njit(cache=True, error_model="numpy")
def _range_differences(E, q, out):
    """:func:`pulse_range_differences` into ``out`` (one pass, no temporaries: the FFT leaves' check
    on the 4096^2 arc took 17 ms in NumPy's broadcast arrays)."""
    S, L, K, _ = E.shape
    W = q.shape[1]
    for s in range(S):
        for w in range(W):
            q0, q1, q2 = q[s, w, 0], q[s, w, 1], q[s, w, 2]
            qq = q0 * q0 + q1 * q1 + q2 * q2
            for i in range(L):
                for k in range(K):
                    e0, e1, e2 = E[s, i, k, 0], E[s, i, k, 1], E[s, i, k, 2]
                    p0, p1, p2 = e0 + q0, e1 + q1, e2 + q2
                    num = 2.0 * (e0 * q0 + e1 * q1 + e2 * q2) + qq
                    out[s, i, k, w] = num / (math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
                                             + math.sqrt(e0 * e0 + e1 * e1 + e2 * e2))


def frame_fits(frame: np.ndarray, centres: np.ndarray, points: np.ndarray) -> bool:
    """Whether the scene's ``points`` all lie where every leaf's own-axis lines are well formed:
    on the image's side of each leaf's turning line (beta > :data:`MIN_BETA` r) and inside the cone
    of real lines (u^2 < 1 - t_n^2).

    Parameters
    ----------
    frame : float64 (S, 14)
    centres : float64 (S, 3)
        m.
    points : float64 (K, 3)
        Plane points, m (the image's edge and a lattice inside it).

    Returns
    -------
    bool
    """
    for s0 in range(0, frame.shape[0], 64):
        sl = slice(s0, min(s0 + 64, frame.shape[0]))
        E = points[None] - centres[sl, None, :]
        r = np.linalg.norm(E, axis=-1)
        beta = np.einsum("skj,sj->sk", E, frame[sl, 6:9])
        u = np.einsum("skj,sj->sk", E, frame[sl, 11:14]) / r
        if not (np.all(beta > MIN_BETA * r) and np.all(u * u < 1.0 - frame[sl, 10, None] ** 2 - 1e-9)):
            return False
    return True


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _own_line_start(fr, r0, dr, n, u):
    """Where the own-axis polar line of cosine ``u`` (ranges r0 + k dr, k < n; ``fr`` the leaf's
    frame) enters the plane: its first index lo (n: never), and alpha's slope and offset in r and
    h^2 (alpha = sa r + sb, beta = sqrt(r^2 - h^2 - alpha^2))."""
    h2 = fr[0] * fr[0] + fr[1] * fr[1] + fr[2] * fr[2]
    tn = fr[10]
    inv_tp = 1.0 / math.sqrt(1.0 - tn * tn)
    sa = u * inv_tp
    sb = -fr[9] * inv_tp
    A = 1.0 - tn * tn - u * u
    if A <= 0.0:
        return n, sa, sb, h2
    B = 2.0 * u * fr[9]
    rp = (-B + math.sqrt(B * B + 4.0 * A * h2)) / (2.0 * A)
    lo = max(0, int(math.ceil((rp - r0) / dr)))
    while lo < n:
        r = r0 + lo * dr
        al = sa * r + sb
        if r * r - h2 - al * al >= 0.0:
            break
        lo += 1
    return min(lo, n), sa, sb, h2


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _own_point(fr, sa, sb, h2, r):
    """x - c of the own-axis line's point at range ``r`` (:func:`_own_line_start`'s constants)."""
    al = sa * r + sb
    be = math.sqrt(max(r * r - h2 - al * al, 0.0))
    return (fr[0] + al * fr[3] + be * fr[6], fr[1] + al * fr[4] + be * fr[7], fr[2] + al * fr[5] + be * fr[8])


@njit(cache=True, fastmath=True, inline="always", error_model="numpy")
def _own_weights(saa, sab, sbb):
    """:func:`_dominant` for scalars, in the kernel."""
    lam = 0.5 * (saa + sbb) + math.sqrt(0.25 * (saa - sbb) ** 2 + sab * sab)
    x1, y1 = sab, lam - saa
    x2, y2 = lam - sbb, sab
    n1 = math.sqrt(x1 * x1 + y1 * y1)
    n2 = math.sqrt(x2 * x2 + y2 * y2)
    if n1 >= n2:
        return (x1 / n1, y1 / n1) if n1 > 0.0 else (0.0, 0.0)
    return x2 / n2, y2 / n2
