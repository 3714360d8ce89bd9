"""Fast factorised backprojection (Ulander, Hellsten and Stenström 2003).

The aperture is split into sub-apertures of a few pulses; each is backprojected onto a polar
grid of its own (range r from its centre c and direction cosine u = (x - c).e_a / r along the
plane's azimuth axis), whose angular spacing only has to resolve what a short aperture can
resolve. Neighbouring sub-images are then merged, four at a time, onto the polar grid of their
union (four times the angular samples, a quarter as many images), the last merge by two, until
two remain; those are interpolated onto the output grid. Each level costs about one output image
of work, so the whole costs N^2 log N instead of the N^3 of direct backprojection.

Sub-images are stored at baseband: g(x) = v(x) exp(-j k |x - c|), v the backprojected value and
k = 4 pi f_c / c, so g is smooth (its range bandwidth is the pulse's, its angular bandwidth
L / lambda per unit u for a sub-aperture of length L) and can be interpolated; the phase
k (|x - c_child| - |x - c_parent|) is put back exactly, in float64, at every merge. A point in the
plane is found from (r, u) in closed form, so the antenna may follow any trajectory; the polar
grids of each level are sized from the image's extent as seen from each sub-aperture centre.

Interpolation: least-squares optimal kernels (``interpolation_table``) designed for each grid's
oversampling: 8 taps in angle, 8 in range, 8 on the pulses' range profiles. The profiles are
sampled at the polar grids' range spacing, so every step is a range pass along lines that move
one source bin per point. Each merge interpolates separably: the parent's line of points crosses
the child's range bins in order, so the child is first cut along the line in angle at its own
range bins, then the cut is interpolated in range (16 taps instead of 64); the last step does the
same along the image's rows. Both passes run in segments where the interpolation fraction moves
little and linearly, with weights linear along the segment, over contiguous floats (SIMD). The
last step's angle pass is the exception: along a row the direction cosine is exactly
u = (x - c).e_a / r with a numerator constant on the row, and away from the middle rows it moves
by a sizeable part of a sample within a few bins (segments of 1/32 sample were two bins long
there and cost half the step), so each bin's weights come from the kernel's polynomials in the
fraction (``polynomial_weights``, degree 6, within 1e-5 of the float64 weights), in runs of one
integer angle index, over contiguous floats.

Leaves by FFT: where each pulse's range against its leaf's centre, |x - p| - |x - c|, is constant
along every polar line of the leaf to :data:`FFT_LEAF_TOLERANCE` (a straight track: it moves by
|q|^2 (1 - u^2) / 2 times the spread of 1 / r, picometres; :func:`fft_leaves_fit`), a leaf's line is
the sum over its pulses of their profiles shifted by that constant, and each profile is the inverse
transform of the pulse's windowed spectrum: so the line is one inverse FFT of the sum of the pulses'
spectra, each times the phase ramp of its shift and its baseband phase (:func:`_fft_leaves`). Exact
(no interpolation of profiles, no profiles at all), a product a pulse and frequency and a transform a
line; leaves of :data:`FFT_LEAF_PULSES` then pay (one merge fewer). A curved or climbing track (an arc)
moves that range along the plane's lines in the first order of its pulses' offsets; its leaves are
formed by FFT on polar lines of constant cosine to each leaf's *own* track direction instead, where
only the offsets across it and the second order move (2 um over 16 pulses of the 4-degree X-band arc
where the plane's lines move 1.3 mm), with a first-order correction: a second sum and transform a
line (:mod:`salkit.focus.ffbp_axes`, :func:`own_leaves_fit`; the first merge reads each leaf on its
own axis). A track where neither fits keeps the interpolated leaves below.

Range sampling: a sub-image at baseband holds each pulse's echo at range frequency
(2 f / c) D - 2 f_c / c along the lines it is interpolated on, D the rate of the pulse's range
against the sub-image's (:func:`range_widening`). D is 1 for a short sub-aperture; over a wide
arc the parallax between the pulses and the line's centre, the aperture's curvature and the angle
its pulses subtend spread the spectrum past the pulse's band (by 3 % on the 4-degree arc at
4096^2, 80 % on a 30-degree arc over a ground plane, 4x on a 60-degree one), so the polar grids
are sampled in range at ``oversample_range`` times the widest sub-image band, not the pulse's
(before 0.24.0 a 30-degree arc over a ground plane imaged at -34 dB against the exact matched
filter, a 60-degree one at -6 dB; now -59.4 dB both).

Wide apertures: one tree's polar grids run from each sub-aperture across the scene along the
image's range axis, so it reaches the scene only from pulses before its near edge, and its
sub-images widen with the angle it spans. An aperture wider than :data:`PART_SPAN_DEG`, up to a full
circle, is formed in parts (:func:`plan_parts`): each run of pulses on the quarter turn of the grid
(:func:`quarter_turn`: the same pixels, the axes turned by a multiple of 90 degrees) whose range
axis looks from it at the scene, and the parts' images added (FFBP is linear in the pulses).

Precision: sub-images are at baseband about |x - c| - rho_c, rho_c = |c - o| (o the scene
centre), and every phase is formed from small differences (|x - a| - |x - b| =
(b - a).(2 (x - b) + (b - a)) / (|x - a| + |x - b|)), never from two ranges of hundreds of
kilometres each rounded to 6e-11 m. Each polar grid keeps :data:`MARGIN_ANGLE` and
:data:`MARGIN_RANGE` samples outside the image, enough for the next level's taps.

Accuracy knobs: ``oversample_angle`` and ``oversample_range`` (samples per Nyquist interval of
the polar grids), ``range_taps`` and ``leaf`` (pulses backprojected directly into each
first-level sub-image). Defaults (1.75, 2.0, 8, and leaves of 32 or 16 pulses by FFT, else 16
interpolated): -56.8 to -60.9 dB image error against the exact matched filter on the test geometries
(:mod:`salkit.simulate.testbeds`, arcs of 4 to 60 degrees among them), not growing with the
collection (1024^2 to 8192^2 pixels and pulses); :data:`ACCURATE` (3.0, 2.5): -70.1 to -76.6 dB.
docs/performance.md gives the accuracy-speed curve.
"""
from __future__ import annotations

import math
from decimal import Decimal, localcontext
from typing import NamedTuple

import numpy as np
import scipy.fft as sfft
from numba import njit

from ..choices import ACCURACY, check_choice
from ..constants import FFT_WORKERS, SPEED_OF_LIGHT
from ..errors import ScenarioError
from ..resources import check_memory, gib
from ..signals.windows import Window
from .profiles import profile_sampling, range_profiles, symmetric_coefficients
from .formers import Accuracy, ImageGrid, ImageResult, Sizes, register_former
from .phasehistory import PhaseHistory
from ..tolerances import BP_DEFAULT_UPSAMPLE, BP_UPSAMPLE
from .bp import bp_memory
from .bp_kernel import backproject

#: Default accuracy settings (image error -56.8 to -60.9 dB against the exact matched filter, to 8192^2).
LEAF_PULSES = 16
#: Sub-images merged into each parent (4: fewer levels than 2, the same accuracy; the last merge is by 2).
MERGE_FACTOR = 4
OVERSAMPLE_ANGLE = 1.75
OVERSAMPLE_RANGE = 2.0
#: Leaves use the series for R - |X - c| where it is exact enough (tests switch it off to compare).
SERIES = True
#: Taps of the merges' range interpolation.
RANGE_TAPS = 8
#: The accuracy setting (``processing.accuracy = "high"``): -70.1 to -76.6 dB against the exact
#: matched filter on the accuracy benchmark's geometries (-71.8 to -74.1 dB at 1024^2 to 8192^2 on the
#: wide-angle arc, ground and slant), about 2x the default's time.
ACCURATE = {"oversample_angle": 3.0, "oversample_range": 2.5}
#: Taps of the leaves' range interpolation of the pulses' profiles.
LEAF_TAPS = 8
#: Pulses a leaf where the leaves are formed by FFT (:func:`fft_leaves_fit`): their cost is a transform a
#: line and a product a pulse and frequency, so longer leaves pay (one merge fewer at 4096 pulses; on
#: the synthetic 1.55 um collection at 4096^2 1.74 s against 1.86 s with 16, and -57.7 against -57.1 dB).
FFT_LEAF_PULSES = 32
#: Form the leaves by FFT where they fit (:func:`fft_leaves_fit`): each polar line the inverse FFT
#: of the pulses' spectra with their range ramps, exact, instead of the interpolated range profiles
#: (tests switch it off to compare).
FFT_LEAVES = True
#: Form the FFT leaves a parent's at a time, each parent's merged at once (:func:`_fused_leaves`):
#: the leaves' grid is never held whole (tests switch it off to compare).
FUSED_LEAVES = True
#: Form the FFT leaves on each leaf's own axis where the plane's does not fit and that does
#: (:func:`own_leaves_fit`, :mod:`salkit.focus.ffbp_axes`: a curved or climbing track; tests switch it
#: off to compare).
OWN_AXIS_LEAVES = True
#: Polar lines the FFT leaves transform together (:func:`_fft_leaves`), in a scratch of that many
#: rows of the FFT length (17 MB at 8232 points): the leaves' grid holds each line's own points only.
FFT_LEAF_BATCH = 256
#: Largest phase, rad at the highest frequency, by which a pulse's range against its leaf's centre
#: may move along a polar line for the FFT leaves (they take it constant along the line): 1e-4 rad,
#: an error floor near -80 dB.
FFT_LEAF_TOLERANCE = 1e-4
#: Samples kept outside the image's extent on each side of a polar grid, in angle and in range:
#: enough that the next level's interpolation of its own margin finds every tap (4 were too few
#: for 8 taps: the image's edges lost 10 to 15 dB).
MARGIN_ANGLE = 5
MARGIN_RANGE = 6
#: Widest angle, degrees, that one FFBP tree spans around the scene (bearing in the image plane, seen
#: from its centre): a wider aperture is formed in parts of at most this span whose images are added
#: (FFBP is linear in the pulses, :func:`plan_parts`). One tree's sub-images widen in range
#: (:func:`range_widening`) and in angle (:func:`angle_lengths`) with the angle it spans, faster
#: than parts cost: a 120-degree arc (1024 pulses onto 101^2, 0.2 m pixels, Zen 3) took 4.1 s as one
#: tree, 2.4 s in two parts of 60 degrees, 1.2 s in four of 30, 1.0 s in eight of 15, each more exact.
PART_SPAN_DEG = 30.0
#: Fewest pulses a part is formed with by FFBP; shorter parts, and the pulses beside the scene that
#: no polar grid reaches, are backprojected directly.
MIN_PART_PULSES = 4 * LEAF_PULSES
#: Widest range widening (:func:`range_widening`) a part of a split aperture is formed with: a part
#: above it is halved (a narrow band widens most: its sub-images' spectrum, relative to the band,
#: spreads with the angles the part subtends), down to :data:`MIN_PART_PULSES`, below which it is
#: backprojected directly.
MAX_PART_WIDENING = 4.0
#: Fewest pixels a side FFBP forms: a narrower grid is formed this wide and cropped (a strip of a few
#: pixels formed as it is lost up to 16 dB: its pixels are all edge).
MIN_SIDE = 32


from .ffbp_axes import frame_fits, leaf_frames, own_axis_residual, pulse_range_differences
from .ffbp_leaves import (RAMP_BLOCK, _chunks, _leaf_kernel, _leaf_spectra, _leaf_spectra_own, _leaf_store,
                          _leaf_store_own, _windowed_spectra, interpolation_table, polynomial_weights)
from .ffbp_merges import ANGLE_TAPS, _final_kernel, _final_rows, _merge_kernel


def rho_residual(o: np.ndarray, c: np.ndarray, rho: float) -> float:
    """|o - c| - rho exactly (to float64 of the difference), m: what rounding |o - c| to the
    float64 ``rho`` left out, from the float64 coordinates in 50-digit decimal arithmetic.

    Parameters
    ----------
    o, c : float64 (3,)
        m.
    rho : float
        A float64 approximation of |o - c|, m.

    Returns
    -------
    float

    Examples
    --------
    >>> rho_residual(np.zeros(3), np.array([3.0, 4.0, 0.0]), 5.0)
    0.0
    """
    with localcontext() as ctx:
        ctx.prec = 50
        s = sum((Decimal(float(a)) - Decimal(float(b))) ** 2 for a, b in zip(o, c))
        return float(s.sqrt() - Decimal(float(rho)))


def _rows_in_order(o: np.ndarray, er: np.ndarray, centres: np.ndarray, rg: np.ndarray) -> bool:
    """Whether every image row (a line along ``er``) crosses each sub-aperture's range bins in
    order: the range from a centre c grows along the row wherever (x - c).er > 0, so it is
    enough that the row's first point lies beyond every centre along er."""
    return rg.size > 1 and float(np.min((o - centres) @ er)) + float(rg[0]) > 0.0


def _image_boundary(grid: ImageGrid, n: int = 64) -> np.ndarray:
    """Points (K, 3) on the edge of the pixel rectangle, half a pixel outside it."""
    az, rg = grid.azimuth, grid.range
    da = (az[1] - az[0]) if az.size > 1 else 0.0
    dg = (rg[1] - rg[0]) if rg.size > 1 else 0.0
    a = np.linspace(az[0] - da, az[-1] + da, n)
    g = np.linspace(rg[0] - dg, rg[-1] + dg, n)
    A = np.concatenate([a, a, np.full(n, a[0]), np.full(n, a[-1])])
    R = np.concatenate([np.full(n, g[0]), np.full(n, g[-1]), g, g])
    return grid.plane.points(A, R)


def _polar_grids(centres: np.ndarray, lengths: np.ndarray, grid: ImageGrid, wavelength: float, dr: float,
                 oversample_angle: float, block: int = 256, axes: np.ndarray | None = None):
    """Per sub-aperture: u origin, u step, u count, r origin, r count (r step ``dr`` for all);
    ``block`` sub-apertures at a time; u the direction cosine to the plane's azimuth axis, or to each
    sub-aperture's own axis ``axes`` (S, 3) (:mod:`salkit.focus.ffbp_axes`)."""
    pts = _image_boundary(grid)
    ea = grid.plane.azimuth
    S = centres.shape[0]
    u0 = np.empty(S)
    du = wavelength / (2.0 * np.maximum(lengths, 1e-9) * oversample_angle)
    nu = np.empty(S, np.int64)
    r0 = np.empty(S)
    nr = np.empty(S, np.int64)
    # the rectangle's nearest point to each centre bounds r from below
    o, er = grid.plane.origin, grid.plane.range
    az, rg = grid.azimuth, grid.range
    for s0 in range(0, S, block):
        sl = slice(s0, min(S, s0 + block))
        cen = centres[sl]
        d = pts[None] - cen[:, None]
        R = np.linalg.norm(d, axis=-1)
        U = (d @ ea if axes is None else np.einsum("skj,sj->sk", d, axes[sl])) / R
        rel = cen - o
        ca = np.clip(rel @ ea, az[0], az[-1])
        cg = np.clip(rel @ er, rg[0], rg[-1])
        near = np.linalg.norm(o + ca[:, None] * ea + cg[:, None] * er - cen, axis=-1)
        rmin = np.minimum(near, R.min(axis=1))
        lo, hi = U.min(axis=1), U.max(axis=1)
        nu[sl] = np.ceil((hi - lo) / du[sl]).astype(np.int64) + 1 + 2 * MARGIN_ANGLE
        u0[sl] = lo - MARGIN_ANGLE * du[sl]
        r0[sl] = rmin - MARGIN_RANGE * dr
        nr[sl] = np.ceil((R.max(axis=1) - rmin) / dr).astype(np.int64) + 1 + 2 * MARGIN_RANGE
    return u0, du, nu, r0, nr


def _lengths(positions: np.ndarray, groups: list, centres: np.ndarray, ea: np.ndarray, step: float) -> np.ndarray:
    """Effective length of each group of pulses: its span along ea plus twice its largest
    excursion across ea (track curvature widens the angular band too), plus one pulse step
    (``ea`` (3,), or (S, 3) an axis a group)."""
    ab = np.asarray(groups, np.int64).reshape(-1, 2)
    idx = np.repeat(np.arange(len(ab)), ab[:, 1] - ab[:, 0])
    d = positions[ab[0, 0]:ab[-1, 1]] - centres[idx]
    axis = ea if np.ndim(ea) == 1 else ea[idx]
    along = d @ ea if np.ndim(ea) == 1 else np.einsum("ij,ij->i", d, axis)
    across = np.linalg.norm(d - along[:, None] * axis, axis=1)
    starts = ab[:, 0] - ab[0, 0]
    span = np.maximum.reduceat(along, starts) - np.minimum.reduceat(along, starts)
    return span + 2.0 * np.maximum.reduceat(across, starts) + step


def _tree(positions: np.ndarray, w: np.ndarray, leaf: int, factor: int) -> list:
    """The factorisation's levels, leaves first: each level's pulse spans, centres (the leaves'
    their pulses' mean, a parent's its children's weighted by the window) and window weights, and
    the number of children merged into each of its sub-apertures (None for the leaves: ``factor``
    while more than ``factor`` remain, then 2), until two sub-apertures remain."""
    P = positions.shape[0]
    spans = [(a, min(a + leaf, P)) for a in range(0, P, leaf)]
    weights = np.array([max(float(w[a:b].sum()), 1e-30) for a, b in spans])
    centres = np.array([positions[a:b].mean(axis=0) for a, b in spans])
    levels = [(spans, centres, weights, None)]
    while len(spans) > 2:
        S = len(spans)
        f = factor if S > factor else 2
        parents = [(i, min(i + f, S)) for i in range(0, S, f)]
        spans = [(spans[a][0], spans[b - 1][1]) for a, b in parents]
        pw = np.array([weights[a:b].sum() for a, b in parents])
        centres = np.array([(centres[a:b] * weights[a:b, None]).sum(axis=0) / pw[k]
                            for k, (a, b) in enumerate(parents)])
        weights = pw
        levels.append((spans, centres, weights, f))
    return levels


def _scene_points(grid: ImageGrid, n: int = 5, n_edge: int = 16) -> np.ndarray:
    """``n_edge`` points a side on the image's edge (:func:`_image_boundary`) and an ``n`` x ``n``
    lattice inside it, (K, 3)."""
    a = np.linspace(grid.azimuth[0], grid.azimuth[-1], n)
    g = np.linspace(grid.range[0], grid.range[-1], n)
    A, R = np.meshgrid(a, g, indexing="ij")
    return np.concatenate([_image_boundary(grid, n_edge), grid.plane.points(A.ravel(), R.ravel())])


def polar_tangent(x: np.ndarray, centre: np.ndarray, ea: np.ndarray, er: np.ndarray) -> np.ndarray:
    """dx/dr along the polar lines through the plane points ``x``: the lines of constant direction
    cosine u = (x - C).e_a / r from ``centre`` C, r = |x - C|, in the plane spanned by e_a and e_r.

    Along such a line (x - C).e_a = u r moves by u dr and (x - C).e_r by r (1 - u^2) / ((x - C).e_r)
    dr, so dx/dr = u e_a + r (1 - u^2) / ((x - C).e_r) e_r (a unit vector only where the line is
    straight: a line over a plane below the centre bends as its depression falls).

    Parameters
    ----------
    x : float64 (K, 3)
        Plane points, m.
    centre : float64 (3,) or (S, 1, 3)
        m (several: the lines of each, (S, K, 3)).
    ea, er : float64 (3,)
        The plane's unit azimuth and range axes.

    Returns
    -------
    float64 (K, 3) or (S, K, 3)
        Metres of x a metre of r.

    Examples
    --------
    >>> ea, er = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    >>> polar_tangent(np.array([[0.0, 5.0, 0.0]]), np.array([0.0, 0.0, 0.0]), ea, er).tolist()
    [[0.0, 1.0, 0.0]]
    """
    d = x - centre
    r = np.linalg.norm(d, axis=-1)
    u = d @ ea / r
    dg = np.maximum(d @ er, 1e-9 * r)  # the polar lines run away from the centre along e_r
    return u[..., None] * ea + (r * (1.0 - u * u) / dg)[..., None] * er


def _sampled_pulses(spans: list, n_pulses: int) -> np.ndarray:
    """``n_pulses`` pulse indices spread over each span (a, b), its ends among them: int64 (S, n)."""
    ab = np.asarray(spans, np.float64).reshape(-1, 2)
    frac = np.linspace(0.0, 1.0, n_pulses)
    return np.rint(ab[:, :1] + (ab[:, 1:] - 1.0 - ab[:, :1]) * frac).astype(np.int64)


def angle_lengths(spans: list, centres: np.ndarray, positions: np.ndarray, grid: ImageGrid,
                  n_pulses: int = 9, axes: np.ndarray | None = None) -> np.ndarray:
    """Each sub-aperture's length as its polar grid's angle sampling must see it, m: the L for which
    the sub-image's highest frequency along the direction cosine u, L / lambda cycles, is reached.

    A sub-image at baseband holds each pulse p's echo at phase k (|x - p| - |x - c|); along its
    polar grid's u at constant range r (x = foot + r u e_a + t e_r, t = (x - c).e_r, so
    dx/du = r e_a - (r^2 u / t) e_r) that phase moves at (2 / lambda) (n_p - n_c).dx/du cycles, n the
    unit vectors from p and from c to x. Straight ahead (u = 0) that is the pulse's offset along e_a,
    at most L / 2 for a sub-aperture of length L; a sub-aperture that looks at the scene at an angle
    theta off the plane's range axis sees its band stretched by 1 / cos(theta) (twice at 60 degrees:
    the ends of a 120-degree arc). The largest over the scene's edge and a lattice inside it and up
    to ``n_pulses`` of each sub-aperture's pulses (its ends among them), times 2.

    Parameters
    ----------
    spans : list of (int, int)
        Each sub-aperture's pulses.
    centres : float64 (S, 3)
        Their centres, m.
    positions : float64 (P, 3)
        Antenna positions, m.
    grid : ImageGrid
    n_pulses : int
        Pulses sampled in each sub-aperture.
    axes : float64 (S, 3), optional
        Each sub-aperture's own axis, where its u is the cosine to that (:mod:`salkit.focus.ffbp_axes`):
        at constant range x moves along v = n x (x - c) (n the plane's normal), so dx/du = r v / (t.v).

    Returns
    -------
    float64 (S,)
        m.
    """
    x = _scene_points(grid)
    nrm = np.cross(grid.plane.azimuth, grid.plane.range)
    nrm = nrm / np.linalg.norm(nrm)
    ea, er = grid.plane.azimuth, grid.plane.range
    pulses = _sampled_pulses(spans, n_pulses)
    out = np.empty(len(pulses))
    for s0 in range(0, len(pulses), 64):  # blocks of sub-apertures: bounded temporaries
        sl = slice(s0, min(s0 + 64, len(pulses)))
        d = x - centres[sl][:, None, :]  # (S, K, 3)
        r = np.sqrt(np.einsum("skj,skj->sk", d, d))
        if axes is None:
            t = np.maximum(d @ er, 1e-9 * r)
            dxdu = r[..., None] * ea - (r * r * (d @ ea) / r / t)[..., None] * er  # (S, K, 3)
        else:
            v = np.cross(nrm, d)
            tv = np.einsum("skj,sj->sk", v, axes[sl])
            tv = np.where(np.abs(tv) > 1e-9 * r, tv, 1e-9 * r)
            dxdu = (r / tv)[..., None] * v
        out[sl] = 2.0 * _band_rates(x, positions[pulses[sl]], d / r[..., None], np.ascontiguousarray(dxdu))
    return out


@njit(cache=True, error_model="numpy")
def _band_rates(x, p, nc, dxdu):
    """:func:`angle_lengths`' largest |(n_p - n_c).dx/du| of each sub-aperture s over its sampled
    pulses ``p[s]`` (float64 (S, n, 3)) and the points ``x`` (K, 3): n_p = (x - p) / |x - p|, and
    ``nc`` the unit vectors from the centre (S, K, 3). One pass, no temporaries (NumPy's broadcast
    arrays took 10-15 ms of each FFBP at 4096^2)."""
    S, n = p.shape[0], p.shape[1]
    K = x.shape[0]
    out = np.zeros(S)
    for s in range(S):
        m = 0.0
        for i in range(n):
            for k in range(K):
                v0, v1, v2 = x[k, 0] - p[s, i, 0], x[k, 1] - p[s, i, 1], x[k, 2] - p[s, i, 2]
                nv = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
                a = ((v0 / nv - nc[s, k, 0]) * dxdu[s, k, 0] + (v1 / nv - nc[s, k, 1]) * dxdu[s, k, 1]
                     + (v2 / nv - nc[s, k, 2]) * dxdu[s, k, 2])
                m = max(m, abs(a))
        out[s] = m
    return out


def range_widening(levels: list, positions: np.ndarray, grid: ImageGrid, freq: np.ndarray,
                   n_pulses: int = 9, rows: bool = True) -> float:
    """How much wider than the pulse's band the sub-images' range spectrum is, where they are
    interpolated in range: the factor by which the polar grids' range sampling must exceed the
    pulse band's to keep their oversampling.

    A sub-image at baseband, g(x) = v(x) exp(-j k |x - c|), holds each pulse p's echo at phase
    k_f |x - p| - k |x - c| (k_f = 4 pi f / c, k at the band's reference frequency). A merge
    interpolates a child in its range r_c = |x - c| along its parent's polar line (and the last
    step along the image's rows), where that phase moves at (2 f / c) D - 2 f_c / c cycles a metre
    of r_c, D = (dR_p/ds) / (dr_c/ds) along the line (dx/ds = u e_a + r (1 - u^2) / ((x - C).e_r)
    e_r for the polar line from the parent's centre C at direction cosine u; e_r along a row).
    D is 1 where the sub-apertures are short against their range; over a wide aperture it departs
    from 1 in first order by the parallax between the child's pulses and the line's centre and by
    the aperture's curvature, and in second order by the angle its pulses subtend (1 - cos), so the
    spectrum spreads past the band's edges (at X band on a 30-degree arc at 7 km over a ground
    plane, by 80 %). The largest half-width over every child of every merge and the last step, at
    the scene's edge and on a lattice inside it, for up to ``n_pulses`` pulses of each child (its
    ends among them), over the pulse's half-band (at least 1).

    Parameters
    ----------
    levels : list
        :func:`_tree`'s levels.
    positions : float64 (P, 3)
        Antenna positions, m.
    grid : ImageGrid
    freq : float64 (M,)
        Frequencies, Hz, increasing and uniform (the baseband's reference is ``freq[M // 2]``).
    n_pulses : int
        Pulses sampled in each sub-aperture.
    rows : bool
        The last step reads the sub-images along the image's rows (``_final_rows``); False: at each
        pixel along their own polar lines (``_final_kernel``, a grid of one range column).

    Returns
    -------
    float
        The widening factor, >= 1.
    """
    c = SPEED_OF_LIGHT
    k_lo, k_hi, k_c = 2.0 * float(freq[0]) / c, 2.0 * float(freq[-1]) / c, 2.0 * float(freq[freq.size // 2]) / c
    half = max(k_c - k_lo, k_hi - k_c)
    if half <= 0.0:
        return 1.0
    x = _scene_points(grid)
    ea, er = grid.plane.azimuth, grid.plane.range
    lo, hi = 1.0, 1.0
    # (children, their lines' centres): each merge's children along their parent's polar lines, the
    # last level's sub-apertures along the image's rows (a centre of None) or, in a one-column grid, their own lines
    work = [(cl, pl[1][np.arange(len(cl[0])) // pl[3]]) for cl, pl in zip(levels[:-1], levels[1:])]
    work.append((levels[-1], None if rows else levels[-1][1]))
    for (spans, centres, _, _), line_centres in work:
        pulses = _sampled_pulses(spans, n_pulses)
        for s0 in range(0, len(spans), 64):  # blocks of children: bounded temporaries
            sl = slice(s0, min(s0 + 64, len(spans)))
            p = positions[pulses[sl]]  # (S, n, 3)
            if line_centres is None:
                t = np.broadcast_to(er, (p.shape[0],) + x.shape)
            else:
                t = polar_tangent(x, line_centres[sl][:, None, :], ea, er)  # (S, K, 3)
            uc = x - centres[sl][:, None, :]
            drc = np.einsum("skj,skj->sk", uc, t) / np.sqrt(np.einsum("skj,skj->sk", uc, uc))
            d_lo, d_hi = _range_rates(x, p, np.ascontiguousarray(t), np.maximum(drc, 1e-9))
            lo, hi = min(lo, d_lo), max(hi, d_hi)
    return max(1.0, max(abs(k * d - k_c) for k in (k_lo, k_hi) for d in (lo, hi)) / half)


@njit(cache=True, error_model="numpy")
def _range_rates(x, p, t, drc):
    """:func:`range_widening`'s D = ((x - p).t / |x - p|) / ``drc`` at the points ``x`` (K, 3) for the
    pulses ``p`` (float64 (S, n, 3)), ``t`` (S, K, 3) and ``drc`` (S, K) each child's: its least and
    largest value. One pass, no temporaries."""
    lo = np.inf
    hi = -np.inf
    for s in range(p.shape[0]):
        for i in range(p.shape[1]):
            for k in range(x.shape[0]):
                v0, v1, v2 = x[k, 0] - p[s, i, 0], x[k, 1] - p[s, i, 1], x[k, 2] - p[s, i, 2]
                D = (v0 * t[s, k, 0] + v1 * t[s, k, 1] + v2 * t[s, k, 2]) / math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
                D = D / drc[s, k]
                lo = min(lo, D)
                hi = max(hi, D)
    return lo, hi


class Layout(NamedTuple):
    """How FFBP cuts a collection and what it holds, known before any work (:func:`ffbp_layout`).

    Attributes
    ----------
    levels : list
        The factorisation's levels, leaves first (pulse spans, centres, weights, children merged).
    widen : float
        The sub-images' range widening (:func:`range_widening`), >= 1.
    nfft : int
        The range profiles' FFT length.
    dr : float
        Their bin spacing and the polar grids' range step, m.
    grids : list
        Each level's polar grids: u origin, u step, u count, r origin, r count per sub-aperture.
    grid_bytes : list of float
        Each level's grid buffer, bytes (complex64, the largest sub-image's shape for all).
    profile_bytes : float
        The range profiles, bytes (complex64, pulses x nfft; with FFT leaves the pulses' spectra,
        pulses x frequencies, and the transforms of :data:`FFT_LEAF_BATCH` lines, each nfft long).
    image_bytes : float
        The output image, bytes (complex64).
    fft_leaves : bool
        Whether the leaves are formed by FFT (:func:`fft_leaves_fit`, :func:`own_leaves_fit`).
    frame : float64 (S, 14) or None
        The leaves' frames where they are formed on their own axes (:func:`own_leaves_fit`).
    """

    levels: list
    widen: float
    nfft: int
    dr: float
    grids: list
    grid_bytes: list
    profile_bytes: float
    image_bytes: float
    fft_leaves: bool = False
    frame: np.ndarray | None = None

    def inputs(self, pulses: int, frequencies: int) -> str:
        """What the leaves read, for messages: the range profiles (pulses x FFT length) or, with FFT
        leaves, the pulses' spectra (pulses x frequencies)."""
        if self.fft_leaves:
            return f"pulses' spectra ({pulses} x {frequencies})"
        return f"range profiles ({pulses} x {self.nfft})"

    @property
    def peak(self) -> float:
        """Peak bytes: the profiles, twice while they are transformed, then beside them the two grid
        buffers the levels take in turn (the even levels' largest and the odd levels') and the image."""
        even = max(self.grid_bytes[0::2])
        odd = max(self.grid_bytes[1::2], default=0.0)
        return self.profile_bytes + max(self.profile_bytes, even + odd + self.image_bytes)


def leaf_shift_spread(spans: list, centres: np.ndarray, grids, positions: np.ndarray, grid: ImageGrid,
                      dr: float, n_lines: int = 5, n_ranges: int = 17) -> float:
    """How far a pulse's range against its leaf's centre, |x - p| - |x - c|, moves along a polar
    line of its leaf, m: the largest spread over each leaf's first, middle and last pulse,
    ``n_lines`` of its lines (the edges among them) and ``n_ranges`` points along each, in the
    plane. The FFT leaves (:func:`_fft_leaves`) take it constant along a line; a straight track
    moves it by |q|^2 (1 - u^2) / 2 times the spread of 1 / r (q the pulse's offset from the
    centre), a curved or climbing one by the offset across the track times the turn of the line's
    direction.

    Parameters
    ----------
    spans : list of (int, int)
        The leaves' pulses.
    centres : float64 (S, 3)
        The leaves' centres, m.
    grids : tuple
        The leaves' polar grids (:func:`_polar_grids`: u0, du, nu, r0, nr).
    positions : float64 (P, 3)
        Antenna positions, m.
    grid : ImageGrid
    dr : float
        The grids' range step, m.
    n_lines, n_ranges : int
        Lines a leaf and points a line sampled.

    Returns
    -------
    float
        m (0 where no sampled line meets the plane).
    """
    u0, du, nu, r0, nr = grids
    plane = grid.plane
    o, ea, er = plane.origin, plane.azimuth, plane.range
    ab = np.asarray(spans, np.int64).reshape(-1, 2)
    pulses = np.stack([ab[:, 0], (ab[:, 0] + ab[:, 1] - 1) // 2, ab[:, 1] - 1], axis=1)  # (S, 3)
    frac = np.linspace(0.0, 1.0, n_lines)
    u = u0[:, None] + du[:, None] * np.rint(frac[None, :] * (nu[:, None] - 1))  # (S, n_lines)
    r = r0[:, None] + dr * np.linspace(0.0, 1.0, n_ranges)[None, :] * (nr[:, None] - 1)  # (S, n_ranges)
    d = o - centres
    da, dg = d @ ea, d @ er
    h2 = np.einsum("ij,ij->i", d, d) - da * da - dg * dg
    foot = o - da[:, None] * ea - dg[:, None] * er
    t2 = r[:, None, :] ** 2 * (1.0 - u * u)[:, :, None] - h2[:, None, None]  # (S, lines, ranges)
    x = (foot[:, None, None, :] + (r[:, None, :] * u[:, :, None])[..., None] * ea
         + np.sqrt(np.maximum(t2, 0.0))[..., None] * er)
    E = x - centres[:, None, None, :]  # (S, lines, ranges, 3)
    q = centres[:, None, :] - positions[pulses]  # (S, 3, 3): c - p
    delta = pulse_range_differences(E, q)  # (S, lines, ranges, pulses)
    inside = (t2 >= 0.0)[..., None] & np.isfinite(delta)
    hi = np.where(inside, delta, -np.inf).max(axis=2)
    lo = np.where(inside, delta, np.inf).min(axis=2)
    met = np.isfinite(hi) & np.isfinite(lo)
    return float((hi - lo)[met].max()) if met.any() else 0.0


def fft_leaves_fit(spans: list, centres: np.ndarray, grids, positions: np.ndarray, grid: ImageGrid,
                   freq: np.ndarray, dr: float, nfft: int) -> bool:
    """Whether the leaves can be formed by FFT (:func:`_fft_leaves`, :data:`FFT_LEAVES`): every
    leaf line shorter than the profiles' period, and each pulse's range against its leaf's centre
    constant along every line to :data:`FFT_LEAF_TOLERANCE` radians of phase at the highest
    frequency (:func:`leaf_shift_spread`).

    Parameters
    ----------
    spans, centres, grids, positions, grid, dr
        As :func:`leaf_shift_spread`.
    freq : float64 (M,)
        Frequencies, Hz.
    nfft : int
        The profiles' FFT length (:func:`salkit.focus.profiles.profile_sampling`).

    Returns
    -------
    bool
    """
    if not FFT_LEAVES or int(np.max(grids[4])) > nfft:
        return False
    spread = leaf_shift_spread(spans, centres, grids, positions, grid, dr)
    return 4.0 * math.pi * float(freq[-1]) / SPEED_OF_LIGHT * spread <= FFT_LEAF_TOLERANCE


def own_leaves_fit(spans: list, centres: np.ndarray, frame: np.ndarray | None, grids, positions: np.ndarray,
                   grid: ImageGrid, freq: np.ndarray, dr: float, nfft: int) -> bool:
    """Whether the leaves can be formed by FFT on their own axes (:mod:`salkit.focus.ffbp_axes`,
    :data:`OWN_AXIS_LEAVES`): every leaf line shorter than the profiles' period, the scene where
    every leaf's lines are well formed (:func:`~salkit.focus.ffbp_axes.frame_fits`), and the phase
    the first-order correction leaves, k |eps - a b| + (k |eps|)^2 / 2 at the highest frequency
    (:func:`~salkit.focus.ffbp_axes.own_axis_residual`), within :data:`FFT_LEAF_TOLERANCE`.

    Parameters
    ----------
    spans, centres, positions, grid, dr
        As :func:`leaf_shift_spread`.
    frame : float64 (S, 14) or None
        :func:`~salkit.focus.ffbp_axes.leaf_frames` (None: no).
    grids : tuple
        The leaves' own-axis polar grids.
    freq : float64 (M,)
        Frequencies, Hz.
    nfft : int
        The profiles' FFT length.

    Returns
    -------
    bool
    """
    if not (OWN_AXIS_LEAVES and FFT_LEAVES) or frame is None or int(np.max(grids[4])) > nfft:
        return False
    if not frame_fits(frame, centres, _scene_points(grid)):
        return False
    eps, res = own_axis_residual(spans, centres, frame, grids, positions, dr)
    k = 4.0 * math.pi * float(freq[-1]) / SPEED_OF_LIGHT
    return k * res + 0.5 * (k * eps) ** 2 <= FFT_LEAF_TOLERANCE


def _leaf_inputs(ph, range_window) -> tuple[np.ndarray, np.ndarray]:
    """The FFT leaves' inputs: the pulses' windowed spectra, real and imaginary parts apart
    (float32 (P, M') each, M frequencies padded with zeros to a multiple of :data:`RAMP_BLOCK`)."""
    P, M = ph.shape
    padded = -(-M // RAMP_BLOCK) * RAMP_BLOCK
    are = np.empty((P, padded), np.float32)  # written whole by the kernel: its pages faulted in on both cores
    aim = np.empty((P, padded), np.float32)
    _windowed_spectra(ph, np.ascontiguousarray(range_window, np.float32), are, aim)
    return are, aim


def _fft_work(rows: int, nfft: int, own: bool) -> tuple:
    """:func:`_fft_leaves`'s scratch for up to ``rows`` polar lines (at most :data:`FFT_LEAF_BATCH` at
    a time) of FFT length ``nfft``: the sums' rows (complex64), the lines' limits, and with ``own``
    (leaves on their own axes) the correction's rows and the lines' coefficients (else None)."""
    n = max(1, min(rows, FFT_LEAF_BATCH))
    scratch = np.empty((n, nfft), np.complex64)
    return (scratch, np.empty((n, 2), np.int64), np.empty_like(scratch) if own else None,
            np.empty((n, 3)) if own else None)


def _fft_leaves(are, aim, M, dr, ref_range, qrel, w, first, count, centres, o, ea, er, u0, du, nu, r0, nr,
                cyc_per_m, nfft, G, frame=None, work=None) -> None:
    """The leaves by FFT into ``G`` (complex64 (S, NU, NR): a line a row, NR its longest length;
    the leaves those of ``first``, ``count``, ``centres`` and the grids, S of them): for each polar
    line the pulses' windowed spectra (:func:`_leaf_inputs`, M frequencies) summed with the phase
    ramps of their ranges (:func:`salkit.focus.ffbp_leaves._leaf_spectra`) and transformed in
    place in a scratch of :data:`FFT_LEAF_BATCH` rows of the profiles' FFT length ``nfft``, whose
    first NR points are kept (:func:`salkit.focus.ffbp_leaves._leaf_store`); exact where
    :func:`fft_leaves_fit` holds, with no range profiles and no interpolation. With the leaves'
    ``frame`` (:func:`own_leaves_fit`), on their own axes with the first-order correction: a second
    scratch of its sums, transformed too (:func:`salkit.focus.ffbp_leaves._leaf_spectra_own`).
    ``work``: the scratch (:func:`_fft_work`) where the caller keeps it across calls (fresh pages
    cost a fault each, taken inside the parallel kernels), else allocated here."""
    S, NU, NR = G.shape
    lines = G.reshape(S * NU, NR)
    scratch, lims, scratch1, bq = _fft_work(S * NU, nfft, frame is not None) if work is None else work
    batch = scratch.shape[0]
    for j0 in range(0, S * NU, batch):
        n = min(batch, S * NU - j0)
        blk = scratch[:n]
        if frame is None:
            _leaf_spectra(are, aim, M, ref_range, qrel, w, first, count, centres, o, ea, er, u0, du, nu, r0, dr, nr,
                          cyc_per_m, j0, NU, blk.view(np.float32), lims[:n], _chunks())
            out = sfft.ifft(blk, axis=1, norm="forward", workers=FFT_WORKERS, overwrite_x=True)
            _leaf_store(out, lims[:n], lines[j0:j0 + n])
        else:
            blk1 = scratch1[:n]
            _leaf_spectra_own(are, aim, M, ref_range, qrel, w, first, count, frame, u0, du, nu, r0, dr, nr, cyc_per_m,
                              j0, NU, blk.view(np.float32), blk1.view(np.float32), lims[:n], bq[:n], _chunks())
            out = sfft.ifft(blk, axis=1, norm="forward", workers=FFT_WORKERS, overwrite_x=True)
            out1 = sfft.ifft(blk1, axis=1, norm="forward", workers=FFT_WORKERS, overwrite_x=True)
            _leaf_store_own(out, out1, lims[:n], bq[:n], lines[j0:j0 + n])


def leaf_pulses(spans: list, centres: np.ndarray, positions: np.ndarray, ref_range: np.ndarray,
                origin: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """What the leaf kernels read of each leaf and pulse: each leaf's first pulse and count, its
    centre's distance rho from the plane's origin, and each pulse's row (c - p, |c - p|^2,
    R_ref - rho) against its leaf's centre c.

    Parameters
    ----------
    spans : list of (int, int)
        The leaves' pulses.
    centres : float64 (S, 3)
        Their centres, m.
    positions : float64 (P, 3)
        Antenna positions, m.
    ref_range : float64 (P,)
        Reference ranges, m.
    origin : float64 (3,)
        The image plane's origin, m.

    Returns
    -------
    first, count : int64 (S,)
    rho : float64 (S,)
        m.
    qrel : float64 (P, 5)
        m, m^2, m.
    """
    first = np.array([a for a, _ in spans], np.int64)
    count = np.array([b - a for a, b in spans], np.int64)
    rho = np.linalg.norm(centres - origin, axis=1)
    leaf_of = np.repeat(np.arange(len(spans)), count)
    q = centres[leaf_of] - positions
    qrel = np.ascontiguousarray(np.column_stack([q, np.einsum("ij,ij->i", q, q), ref_range - rho[leaf_of]]))
    return first, count, rho, qrel


def _fuses_leaves(fft_leaves: bool, levels: list) -> bool:
    """Whether FFBP forms its leaves a parent's at a time (:func:`_fused_leaves`): FFT leaves with a
    merge after them, and :data:`FUSED_LEAVES`."""
    return fft_leaves and len(levels) > 1 and FUSED_LEAVES


def _fused_leaves(scratch, out, factor, leaves, children, parent, dr, o, ea, er, cyc_per_m, tu, tr,
                  frame=None) -> None:
    """The FFT leaves and the first merge together, a parent at a time: parent s's ``factor``
    leaves (children s factor ..) formed by :func:`_fft_leaves` into ``scratch`` (complex64
    (factor, NU, NR)) and merged at once into ``out[s]`` by the merge kernel, so that the leaves'
    grid is never held whole (a thirtieth of it at 4096^2) and each parent reads its children where
    they were just written.

    ``leaves`` = (first, count, qrel, are, aim, M, ref_range, w, nfft); ``children`` = (u0, du, nu,
    r0, nr, centres, rho) of the leaves; ``parent`` = (centres, rho, u0, du, nu, r0, nr) of the
    first merge's sub-images; ``frame`` the leaves' frames where they lie on their own axes."""
    first, count, qrel, are, aim, M, ref_range, w, nfft = leaves
    u0, du, nu, r0, nr, centres, rho = children
    pcen, prho, pu0, pdu, pnu, pr0, pnr = parent
    n_child = first.shape[0]
    # one scratch for every parent's transforms: 32 parents at 4096^2 took 19 MB of fresh pages each
    # (0.1-0.14 s of page faults a call)
    work = _fft_work(scratch.shape[0] * scratch.shape[1], nfft, frame is not None)
    for s in range(pcen.shape[0]):
        a, b = s * factor, min(s * factor + factor, n_child)
        G = scratch[:b - a]
        fr = None if frame is None else frame[a:b]
        _fft_leaves(are, aim, M, dr, ref_range, qrel, w, first[a:b], count[a:b], centres[a:b], o, ea, er, u0[a:b],
                    du[a:b], nu[a:b], r0[a:b], nr[a:b], cyc_per_m, nfft, G, fr, work)
        p = slice(s, s + 1)
        cax, own = _child_axes(fr)
        _merge_kernel(G.view(np.float32), u0[a:b], du[a:b], nu[a:b], r0[a:b], nr[a:b], centres[a:b], rho[a:b], dr,
                      factor, o, ea, er, pcen[p], prho[p], pu0[p], pdu[p], pnu[p], pr0[p], dr, pnr[p], cyc_per_m, tu,
                      tr, out[p].view(np.float32), _chunks(), cax, own)


def _child_axes(frame):
    """The merge kernel's children's axes and whether to use them: the own axes of leaves with
    ``frame``, else a placeholder (their direction cosines to the plane's axis)."""
    if frame is None:
        return np.zeros((1, 3)), False
    return np.ascontiguousarray(frame[:, 11:14]), True


def _check_in_front(leaves, grid: ImageGrid) -> None:
    """Refuse a collection whose sub-apertures do not all lie before the scene along the image's
    range axis: the polar grids run from each centre across the scene towards +e_r
    (:func:`~salkit.focus.ffbp_leaves._polar_line`), which a centre past the scene's near edge
    cannot see (an aperture of more than 180 degrees around the scene, a track over it). The
    leaves suffice: every parent's centre is a weighted mean of theirs, and the distance is linear."""
    spans, centres = leaves[0], leaves[1]
    lead = _lead(centres, grid)
    k = int(np.argmin(lead))
    if lead[k] <= 0.0:
        a, b = spans[k]
        raise ScenarioError("processing.algorithm", "ffbp",
                            "FFBP's polar grids run from every sub-aperture across the scene along the image's "
                            f"range axis, so every pulse must lie before the scene's near edge; pulses {a} to {b - 1} "
                            f"lie {-float(lead[k]):.4g} m past it (an aperture of more than 180 degrees around the "
                            "scene, or a track over it): one FFBP tree cannot form it; ffbp forms such an aperture in "
                            "parts (plan_parts), or use bp (any trajectory)")


def _knobs(accuracy: str) -> dict:
    """The polar grids' oversampling at an accuracy level (the module defaults, or :data:`ACCURATE`)."""
    return {"oversample_angle": OVERSAMPLE_ANGLE, "oversample_range": OVERSAMPLE_RANGE,
            **(ACCURATE if accuracy == "high" else {})}


def _lead(positions: np.ndarray, grid: ImageGrid) -> np.ndarray:
    """How far each pulse lies before the scene's near edge along the image's range axis, m: FFBP's
    polar grids reach the scene from a pulse where it is positive (:func:`_check_in_front`)."""
    rg = grid.range
    near = float(rg[0]) - (0.5 * float(rg[1] - rg[0]) if rg.size > 1 else 0.0)
    return (grid.plane.origin - positions) @ grid.plane.range + near


def quarter_turn(grid: ImageGrid, quarter: int) -> ImageGrid:
    """The same pixels with the plane's axes turned by ``quarter`` x 90 degrees about its normal
    (the range axis turned from ``e_r`` towards ``-e_a``): seen through it, pulses at that bearing
    around the scene lie before its near edge. :func:`from_quarter_turn` brings an image formed on
    it back to ``grid``'s pixel order.

    Parameters
    ----------
    grid : ImageGrid
    quarter : int
        0 (``grid`` itself), 1, 2 or 3.

    Returns
    -------
    ImageGrid
    """
    q = int(quarter) % 4
    if q == 0:
        return grid
    p, az, rg = grid.plane, np.asarray(grid.azimuth, np.float64), np.asarray(grid.range, np.float64)
    ea, er = np.asarray(p.azimuth, np.float64), np.asarray(p.range, np.float64)
    spec = grid.spec
    if q == 2:  # a point az e_a + rg e_r is (-az) (-e_a) + (-rg) (-e_r)
        return ImageGrid(type(p)(origin=p.origin, azimuth=-ea, range=-er), -az[::-1].copy(), -rg[::-1].copy(), spec)
    swapped = spec.model_copy(update={"nx": spec.ny, "ny": spec.nx, "dx": spec.dy, "dy": spec.dx})
    if q == 1:  # azimuth e_r, range -e_a: the point is rg e_a' + (-az) e_r'
        return ImageGrid(type(p)(origin=p.origin, azimuth=er, range=-ea), rg.copy(), -az[::-1].copy(), swapped)
    return ImageGrid(type(p)(origin=p.origin, azimuth=-er, range=ea), -rg[::-1].copy(), az.copy(), swapped)


def from_quarter_turn(img: np.ndarray, quarter: int) -> np.ndarray:
    """An image formed on :func:`quarter_turn` ``(grid, quarter)`` in ``grid``'s pixel order (a view).

    Parameters
    ----------
    img : ndarray (nx', ny')
    quarter : int

    Returns
    -------
    ndarray (nx, ny)
    """
    q = int(quarter) % 4
    if q == 0:
        return img
    if q == 2:
        return img[::-1, ::-1]
    if q == 1:
        return img.T[::-1, :]
    return img[::-1, :].T


#: Names of the quarter turns in :func:`aperture_parts`.
QUARTERS = ("front", "left", "back", "right")


def aperture_parts(positions: np.ndarray, grid: ImageGrid, span_deg: float = PART_SPAN_DEG,
                   min_pulses: int = MIN_PART_PULSES) -> list:
    """How FFBP forms a collection: runs of consecutive pulses, each formed on the quarter turn of
    ``grid`` (:func:`quarter_turn`) whose range axis looks most nearly from them at the scene
    (``"front"``: ``grid`` itself; ``"left"``, ``"back"``, ``"right"``: turned by 90, 180, 270
    degrees), every part spanning at most ``span_deg`` of bearing around the scene centre; pulses no
    quarter turn sees from before the scene (over it), and the runs of a split aperture too short for
    a tree, ``"direct"`` (backprojected). One ``"front"`` part for an aperture of up to ``span_deg`` before the scene (the
    usual case); a full circle is twelve or thirteen parts at 30 degrees.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    grid : ImageGrid
    span_deg : float
        Widest bearing span of a part, degrees.
    min_pulses : int
        Fewest pulses of an FFBP part.

    Returns
    -------
    list of (str, int, int)
        (kind, first pulse, end pulse), in pulse order, covering every pulse once.

    Examples
    --------
    >>> from salkit.focus.formers import ImageGrid
    >>> from salkit.geometry.collection import ImagePlane
    >>> from salkit.params.models import Grid
    >>> g = ImageGrid(ImagePlane(np.zeros(3), np.array([1.0, 0, 0]), np.array([0, 1.0, 0])),
    ...               np.arange(-8, 8.0), np.arange(-8, 8.0), Grid(nx=16, ny=16, dx=1.0, dy=1.0))
    >>> phi = np.radians(np.arange(0, 360, 0.5))  # a full circle of 720 pulses, starting before the scene
    >>> pos = np.stack([1000 * np.sin(phi), -1000 * np.cos(phi), np.full(phi.size, 800.0)], axis=1)
    >>> parts = aperture_parts(pos, g, min_pulses=16)
    >>> len(parts), parts[:4]
    (13, [('front', 0, 46), ('front', 46, 91), ('left', 91, 151), ('left', 151, 211)])
    >>> aperture_parts(pos[:100], g, min_pulses=16)  # a 50-degree arc; its last 9 pulses backprojected
    [('front', 0, 46), ('front', 46, 91), ('direct', 91, 100)]
    """
    P = positions.shape[0]
    d = positions - grid.plane.origin
    bearing = np.unwrap(np.arctan2(d @ grid.plane.azimuth, -(d @ grid.plane.range)))
    quarter = np.mod(np.rint(bearing / (0.5 * math.pi)).astype(np.int64), 4)
    for q in range(4):  # a pulse its quarter turn does not see from before the scene: backprojected
        sel = quarter == q
        if sel.any():
            quarter[np.flatnonzero(sel)[_lead(positions[sel], quarter_turn(grid, q)) <= 0.0]] = 4
    limit = math.radians(span_deg)
    runs, a = [], 0
    for b in range(1, P + 1):
        if b == P or quarter[b] != quarter[a]:
            runs.append((int(quarter[a]), a, b))
            a = b
    parts = []
    for q, a, b in runs:
        if q == 4:
            parts.append(("direct", a, b))
            continue
        span = float(bearing[a:b].max() - bearing[a:b].min())
        each = span / max(1, math.ceil(span / limit - 1e-9)) * (1.0 + 1e-9)
        start, lo, hi = a, bearing[a], bearing[a]
        for i in range(a, b + 1):
            if i < b:
                lo2, hi2 = min(lo, bearing[i]), max(hi, bearing[i])
                if hi2 - lo2 <= each:
                    lo, hi = lo2, hi2
                    continue
            parts.append((QUARTERS[q], start, i))
            if i < b:
                start, lo, hi = i, bearing[i], bearing[i]
    if len(parts) == 1:  # one part, however short, is one tree
        return parts
    out = []
    for kind, a, b in parts:  # short parts of a split aperture backprojected
        _add_part(out, "direct" if b - a < min_pulses else kind, a, b)
    return out


def _add_part(parts: list, kind: str, a: int, b: int) -> None:
    """Append the part (kind, a, b), joined with the last one where both are ``"direct"``."""
    if parts and kind == "direct" and parts[-1][0] == "direct":
        parts[-1] = ("direct", parts[-1][1], b)
    else:
        parts.append((kind, a, b))


def plan_parts(positions: np.ndarray, freq: np.ndarray, grid: ImageGrid, span_deg: float = PART_SPAN_DEG,
               min_pulses: int = MIN_PART_PULSES, max_widening: float = MAX_PART_WIDENING) -> list:
    """The parts :func:`ffbp` forms a collection in: :func:`aperture_parts`, each FFBP part whose range
    widening on its quarter turn exceeds ``max_widening`` halved until it does not, one too short to
    halve backprojected (``"direct"``). An aperture that is one part within ``span_deg`` before the
    scene and within ``max_widening`` stays one tree.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    freq : float64 (M,)
        Frequencies, Hz.
    grid : ImageGrid
    span_deg, min_pulses : float, int
        As :func:`aperture_parts`.
    max_widening : float
        Widest range widening of a part.

    Returns
    -------
    list of (str, int, int)
        (kind, first pulse, end pulse), in pulse order, covering every pulse once.
    """
    positions = np.asarray(positions, np.float64)
    freq = np.asarray(freq, np.float64)
    first = aperture_parts(positions, grid, span_deg, min_pulses)
    out, todo = [], list(reversed(first))
    while todo:
        kind, a, b = todo.pop()
        if kind != "direct":
            g = quarter_turn(grid, QUARTERS.index(kind))
            levels = _tree(positions[a:b], np.ones(b - a, np.float32), LEAF_PULSES, MERGE_FACTOR)
            if range_widening(levels, positions[a:b], g, freq, rows=g.range.size > 1) > max_widening:
                if b - a >= 2 * min_pulses:
                    m = (a + b) // 2
                    todo += [(kind, m, b), (kind, a, m)]
                    continue
                kind = "direct" if len(first) > 1 else kind  # one short collection stays one tree
        _add_part(out, kind, a, b)
    return out


def _layout(positions: np.ndarray, freq: np.ndarray, grid: ImageGrid, w: np.ndarray, leaf: int | None, factor: int,
            oversample_angle: float, oversample_range: float) -> Layout:
    """:class:`Layout` of FFBP with these settings (the window ``w`` weighs the sub-apertures'
    centres; ``leaf`` None: leaves of :data:`FFT_LEAF_PULSES` where they can be formed by FFT,
    else of :data:`LEAF_PULSES`; only the leaves' grids are sized before that is known). At each leaf
    size the FFT leaves are tried on the plane's axis (:func:`fft_leaves_fit`), then on the leaves'
    own axes (:func:`own_leaves_fit`, where a merge follows them)."""
    P = positions.shape[0]
    if leaf is None:
        _check_in_front(_tree(positions, w, LEAF_PULSES, factor)[0], grid)  # named by the shorter leaves
    ea = np.ascontiguousarray(grid.plane.azimuth, np.float64)
    step = float(np.median(np.linalg.norm(np.diff(positions, axis=0), axis=1))) if P > 1 else 0.0
    lam_min = SPEED_OF_LIGHT / float(freq[-1])

    def polar_grids(spans, cen, dr, axes=None):
        # the angle sampling: the span and curvature of each sub-aperture, or its band as seen from
        # the scene where that is wider (a sub-aperture off the plane's range axis); u the cosine to
        # the plane's azimuth axis, or to each sub-aperture's own
        lengths = np.maximum(_lengths(positions, spans, cen, ea if axes is None else axes, step),
                             angle_lengths(spans, cen, positions, grid, axes=axes))
        return _polar_grids(cen, lengths, grid, lam_min, dr, oversample_angle, axes=axes)

    for size in (FFT_LEAF_PULSES, LEAF_PULSES) if leaf is None else (leaf,):
        levels = _tree(positions, w, size, factor)
        if leaf is not None:
            _check_in_front(levels[0], grid)
        # range profiles sampled at the polar grids' range spacing (at least oversample_range per
        # resolution cell, and per the sub-images' range spectrum where a wide aperture widens it): a
        # polar line then moves one profile bin per point
        widen = range_widening(levels, positions, grid, freq, rows=grid.range.size > 1)
        nfft, dr = profile_sampling(freq, oversample_range * widen)
        leaves = polar_grids(levels[0][0], levels[0][1], dr)
        fft = fft_leaves_fit(levels[0][0], levels[0][1], leaves, positions, grid, freq, dr, nfft)
        frame = None
        if fft:
            break
        if len(levels) > 1 and OWN_AXIS_LEAVES and FFT_LEAVES:  # a merge reads them on their own axes
            frame = leaf_frames(levels[0][0], levels[0][1], positions, grid.plane)
            if frame is not None:
                own = polar_grids(levels[0][0], levels[0][1], dr, frame[:, 11:14])
                if own_leaves_fit(levels[0][0], levels[0][1], frame, own, positions, grid, freq, dr, nfft):
                    fft, leaves = True, own
                    break
            frame = None
    grids = [leaves] + [polar_grids(spans, cen, dr) for spans, cen, _, _ in levels[1:]]
    nbytes = [8.0 * len(lv[0]) * int(g[2].max()) * int(g[4].max()) for lv, g in zip(levels, grids)]
    inputs = 8.0 * P * nfft
    if fft:  # the pulses' spectra instead of profiles, and a batch of lines a transform long
        lines = len(levels[0][0]) * int(grids[0][2].max())
        inputs = 8.0 * P * (-(-freq.size // RAMP_BLOCK) * RAMP_BLOCK) + 8.0 * min(lines, FFT_LEAF_BATCH) * nfft
        if frame is not None:  # the correction's own batch of transforms
            inputs += 8.0 * min(lines, FFT_LEAF_BATCH) * nfft
        if _fuses_leaves(fft, levels):  # formed a parent's leaves at a time
            nbytes[0] = 8.0 * levels[1][3] * int(grids[0][2].max()) * int(grids[0][4].max())
    return Layout(levels, widen, nfft, dr, grids, nbytes, inputs, 8.0 * grid.azimuth.size * grid.range.size, fft,
                  frame)


def ffbp_layout(positions: np.ndarray, freq: np.ndarray, grid: ImageGrid, accuracy: str = "standard") -> Layout:
    """FFBP's factorisation of a collection onto ``grid`` and the memory it holds, from the
    geometry alone (no signal): what :func:`ffbp` sizes before any work, and what the tiling
    planner (:mod:`salkit.focus.tiles`) weighs tiles and pulse blocks by.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    freq : float64 (M,)
        Frequencies, Hz, increasing and uniform.
    grid : ImageGrid
    accuracy : {"standard", "high"}

    Returns
    -------
    Layout
        ``peak`` its peak memory, bytes.

    Raises
    ------
    ScenarioError
        For an undeclared accuracy.
    """
    check_choice("processing.accuracy", accuracy, ACCURACY)
    knobs = _knobs(accuracy)
    positions = np.asarray(positions, np.float64)
    grown = _grown(grid)
    if grown is not None:  # a narrow grid is formed wider (ffbp)
        grid = grown[0]
    return _layout(positions, np.asarray(freq, np.float64), grid, np.ones(positions.shape[0], np.float32),
                   None, MERGE_FACTOR, **knobs)


def ffbp_footprint(positions: np.ndarray, freq: np.ndarray, grid: ImageGrid, accuracy: str = "standard") -> float:
    """Bytes FFBP adds to what every former holds, from the collection's geometry (the ``footprint``
    of ``ffbp``'s declaration): its peak (:func:`ffbp_layout`) less the image; for an aperture formed
    in parts (:func:`plan_parts`), the largest part's peak (its image beside the one they are
    added into).

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    freq : float64 (M,)
        Frequencies, Hz.
    grid : ImageGrid
    accuracy : {"standard", "high"}

    Returns
    -------
    float
    """
    check_choice("processing.accuracy", accuracy, ACCURACY)
    positions = np.asarray(positions, np.float64)
    grown = _grown(grid)
    g = grid if grown is None else grown[0]
    parts = plan_parts(positions, freq, g)
    if len(parts) == 1 and parts[0][0] == "front":
        lay = ffbp_layout(positions, freq, grid, accuracy)
        return lay.peak - lay.image_bytes
    # in parts: the largest part's peak (its own image beside the one the parts are added into)
    knobs = _knobs(accuracy)
    needs = _part_needs(parts, positions, freq, g, np.ones(positions.shape[0], np.float32), None,
                        MERGE_FACTOR, **knobs)
    return max(n for n, _ in needs)


def _grown(grid: ImageGrid):
    """A grid of at least :data:`MIN_SIDE` pixels a side holding ``grid`` at its centre (the same
    plane, spacing and pixel coordinates), and where ``grid`` starts in it; None when ``grid`` is
    that large already."""
    axes = []
    for ax, step in ((grid.azimuth, grid.spec.dx), (grid.range, grid.spec.dy)):
        n = ax.size
        d = float(ax[1] - ax[0]) if n > 1 else float(step)
        lo = max(0, (MIN_SIDE - n) // 2)
        hi = max(0, MIN_SIDE - n - lo)
        axes.append((np.concatenate([ax[0] - d * np.arange(lo, 0, -1), ax, ax[-1] + d * np.arange(1, hi + 1)]), lo))
    (az, i0), (rg, j0) = axes
    if az.size == grid.azimuth.size and rg.size == grid.range.size:
        return None
    return ImageGrid(grid.plane, az, rg, grid.spec.model_copy(update={"nx": az.size, "ny": rg.size})), i0, j0


def ffbp(ph: np.ndarray, freq: np.ndarray, positions: np.ndarray, ref_range: np.ndarray, grid: ImageGrid,
         azimuth_window: np.ndarray, range_window: np.ndarray, leaf: int | None = None, factor: int = MERGE_FACTOR,
         oversample_angle: float = OVERSAMPLE_ANGLE, oversample_range: float = OVERSAMPLE_RANGE,
         range_taps: int = RANGE_TAPS, progress=None, split: bool = True) -> tuple[np.ndarray, dict]:
    """Fast factorised backprojection onto ``grid``, unnormalised (as direct backprojection).

    An aperture wider than :data:`PART_SPAN_DEG` around the scene, or reaching past it (more than
    180 degrees, up to a full circle), is formed in parts (:func:`plan_parts`) and their images
    added.

    Parameters
    ----------
    ph : complex (P, M)
        Phase history.
    freq : float64 (M,)
        Frequencies, Hz, increasing and uniform.
    positions : float64 (P, 3)
        Antenna positions, m (any trajectory).
    ref_range : float64 (P,)
        Reference ranges, m.
    grid : ImageGrid
    azimuth_window : float (P,)
        Per-pulse weights.
    range_window : float (M,)
    leaf : int, optional
        Pulses per first-level sub-image (default: :data:`FFT_LEAF_PULSES` where the leaves can be
        formed by FFT, :func:`fft_leaves_fit`, else :data:`LEAF_PULSES`).
    factor : int
        Sub-images merged into each parent.
    oversample_angle, oversample_range : float
        Polar-grid samples per Nyquist interval (the range profiles are sampled at the grids'
        range spacing, ``oversample_range`` or a little more: an FFT length).
    range_taps : int
        Taps of the merges' range interpolation (even).
    progress : callable, optional
        ``progress(done, total)`` in levels (of every part, for an aperture formed in parts).
    split : bool
        Form a wide aperture in parts (False: as one tree, or refused where it reaches past the scene).

    Returns
    -------
    (complex64 (nx, ny), dict)
        The image and the sizes of the factorisation (levels, polar samples; ``ffbp_parts`` and
        ``ffbp_direct_pulses`` for an aperture formed in parts, whose widening is its widest part's).
    """
    widened = _grown(grid)
    if widened is not None:  # a narrow grid is formed wider and cropped: FFBP's edges are its least exact pixels
        big, i0, j0 = widened
        img, info = ffbp(ph, freq, positions, ref_range, big, azimuth_window, range_window, leaf, factor,
                         oversample_angle, oversample_range, range_taps, progress)
        return np.ascontiguousarray(img[i0:i0 + grid.azimuth.size, j0:j0 + grid.range.size]), info
    if split:
        parts = plan_parts(positions, freq, grid)
        if len(parts) > 1 or parts[0][0] != "front":
            return _ffbp_in_parts(parts, ph, freq, positions, ref_range, grid, azimuth_window, range_window, leaf,
                                  factor, oversample_angle, oversample_range, range_taps, progress)
    P, M = ph.shape
    f_c = float(freq[M // 2])
    cyc_per_m = 2.0 * f_c / SPEED_OF_LIGHT
    w = np.asarray(azimuth_window, np.float32)
    # every level's polar grids, sized before any work: the range profiles (twice while they are
    # transformed), then beside them the two grid buffers the levels take in turn and the image, must
    # fit the memory this process may still use (a wide arc's profiles and grids hold several times
    # what the sizes alone say: the range widening, and the leaves' margins over a small scene)
    lay = _layout(positions, freq, grid, w, leaf, factor, oversample_angle, oversample_range)
    levels, widen, nfft, dr, grids = lay.levels, lay.widen, lay.nfft, lay.dr, lay.grids
    leaf = max(b - a for a, b in levels[0][0])
    check_memory(lay.peak, f"FFBP's {lay.inputs(P, M)} and polar grids ({len(levels)} levels, up to "
                 f"{gib(max(lay.grid_bytes))} a level), their range sampling widened {widen:.3g}x for the "
                 f"sub-images' spectrum, and the {grid.azimuth.size} x {grid.range.size} image",
                 "use --algorithm bp, a smaller grid, fewer pulses or a narrower aperture")
    plane = grid.plane
    o = np.ascontiguousarray(plane.origin, np.float64)
    ea = np.ascontiguousarray(plane.azimuth, np.float64)
    er = np.ascontiguousarray(plane.range, np.float64)
    lam_min = SPEED_OF_LIGHT / float(freq[-1])
    nx, ny = grid.azimuth.size, grid.range.size
    tu = interpolation_table(ANGLE_TAPS, oversample_angle)
    # the leaves read the pulses' profiles (the pulse's band); the merges and the last step the
    # sub-images (their band widened by ``widen``)
    os_sub = nfft / M / widen
    tr = interpolation_table(range_taps, os_sub)
    try:  # the interpolating leaves' kernel (the FFT leaves read no profiles)
        tl = None if lay.fft_leaves else interpolation_table(LEAF_TAPS, nfft / M)
    except np.linalg.LinAlgError:  # sampled so far above the band that no kernel fits it
        raise ScenarioError("processing.algorithm", "ffbp",
                            f"these {P} pulses' sub-images spread over {widen:.3g} times the pulse's band in range "
                            "(a narrow band seen over a wide angle), more than FFBP's range kernels can be designed "
                            "for: use bp") from None
    # level 0: leaves of `leaf` pulses
    groups, centres, _, _ = levels[0]
    n_levels = len(levels) + 1  # leaves, merges, final
    done = 0
    u0, du, nu, r0, nr = grids[0]
    # two buffers used in turn by the levels (one read, one written): their pages are faulted in
    # once, not at every level (page faults inside the parallel kernels cost up to half a merge)
    pool = [np.empty(0, np.complex64), np.empty(0, np.complex64)]

    def grid_buffer(level, shape):
        size = int(np.prod(shape))
        if pool[level % 2].size < size:
            pool[level % 2] = np.empty(size, np.complex64)
        return pool[level % 2][:size].reshape(shape)

    # FFT leaves beneath a merge are formed a parent at a time, into a buffer of one parent's
    # children, and merged at once (:func:`_fused_leaves`): the leaves' grid is never whole
    fused = _fuses_leaves(lay.fft_leaves, levels)
    G = grid_buffer(0, (levels[1][3] if fused else len(groups), int(nu.max()), int(nr.max())))
    first, count, rho, qrel = leaf_pulses(groups, centres, positions, ref_range, o)
    q = qrel[:, :3]
    # the leaves' series for R - |X - c| (no sqrt or division) where its truncation, about
    # 5 x^4 / (2 r)^3 with x the leaf's extent and r the nearest polar range, stays below 1e-5 rad
    x_max = float(np.max(np.linalg.norm(q, axis=1))) if q.size else 0.0
    r_min = float(np.min(r0))
    series = SERIES and r_min > 0 and 5.0 * x_max ** 4 / (2.0 * r_min) ** 3 * 4.0 * math.pi / lam_min < 1e-5
    if lay.fft_leaves:
        are, aim = _leaf_inputs(ph, range_window)
        if not fused:
            _fft_leaves(are, aim, M, dr, ref_range, qrel, w, first, count, centres, o, ea, er, u0, du, nu, r0, nr,
                        cyc_per_m, nfft, G, lay.frame)
            are = aim = None
    else:
        prof, rp0, _, _ = range_profiles(ph, freq, oversample_range * widen, np.asarray(range_window, np.float64))
        _leaf_kernel(prof.view(np.float32), rp0, 1.0 / dr, positions, ref_range, qrel, w, first, count, centres, o,
                     ea, er, u0, du, nu, r0, dr, nr, cyc_per_m, tl, G, series, _chunks())
        prof = None
    samples = [int((nu * nr).sum())]
    done += 1
    if progress and not fused:  # fused: the leaves are done with the first merge
        progress(done, n_levels)
    # merge `factor` at a time, the last merge by two, until two sub-images remain for the final step
    for (spans, pcen, _, f_level), (pu0, pdu, pnu, pr0, pnr) in zip(levels[1:], grids[1:]):
        out = grid_buffer(done, (len(spans), int(pnu.max()), int(pnr.max())))
        prho = np.linalg.norm(pcen - o, axis=1)
        if fused and done == 1:  # the leaves, a parent's at a time, each parent's merged at once
            _fused_leaves(G, out, f_level, (first, count, qrel, are, aim, M, ref_range, w, nfft),
                          (u0, du, nu, r0, nr, centres, rho), (pcen, prho, pu0, pdu, pnu, pr0, pnr), dr, o, ea, er,
                          cyc_per_m, tu, tr, lay.frame)
            are = aim = None  # the spectra freed before the next level's buffer is faulted in
            if progress:
                progress(done, n_levels)
        else:  # the first merge reads leaves on their own axes where they are so
            cax, own = _child_axes(lay.frame if done == 1 else None)
            _merge_kernel(G.view(np.float32), u0, du, nu, r0, nr, centres, rho, dr, f_level, o, ea, er, pcen, prho,
                          pu0, pdu, pnu, pr0, dr, pnr, cyc_per_m, tu, tr, out.view(np.float32), _chunks(), cax, own)
        G, centres, rho = out, pcen, prho
        u0, du, nu, r0, nr = pu0, pdu, pnu, pr0, pnr
        samples.append(int((nu * nr).sum()))
        done += 1
        if progress:
            progress(done, n_levels)
    # the image into the buffer the last level did not write, where it fits (its pages are in
    # already: first touches of fresh memory cost up to 0.2 s at 4096^2), shrunk to the image after
    # (every pixel is written by either kernel)
    spare = next((b for b in pool if b.size >= nx * ny and not np.shares_memory(b, G)), None)
    img = np.empty((nx, ny), np.complex64) if spare is None else spare[:nx * ny].reshape(nx, ny)
    az, rg = np.asarray(grid.azimuth, np.float64), np.asarray(grid.range, np.float64)
    res = np.array([rho_residual(o, c, r) for c, r in zip(centres, rho)])
    if _rows_in_order(o, er, centres, rg):
        cr = polynomial_weights(range_taps, os_sub)
        cps = symmetric_coefficients(polynomial_weights(ANGLE_TAPS, oversample_angle), 0.0).astype(np.float32)
        _final_rows(G.view(np.float32), u0, du, nu, r0, nr, centres, rho, res, dr, o, ea, er, az, rg, cyc_per_m, cps,
                    cr, symmetric_coefficients(cr, 0.0).astype(np.float32), img, _chunks())
    else:
        _final_kernel(G, u0, du, nu, r0, nr, centres, rho, res, dr, o, ea, er, az, rg, cyc_per_m, tu, tr, img)
    if spare is not None:  # the image alone keeps its buffer: shrunk in place (realloc), no copy
        img = G = out = pool = None
        try:
            spare.resize(nx * ny)  # refused (ValueError) while any other reference or view is alive
            img = spare.reshape(nx, ny)
        except ValueError:
            img = spare[:nx * ny].reshape(nx, ny).copy()
    done += 1
    if progress:
        progress(done, done)
    return img, {"ffbp_levels": done, "ffbp_leaf_pulses": leaf, "ffbp_polar_samples": int(np.mean(samples)),
                 "ffbp_range_widening": round(widen, 4)}


def _part_needs(parts, positions, freq, grid, w, leaf, factor, oversample_angle, oversample_range) -> list:
    """Peak bytes of forming each of ``parts`` (:func:`plan_parts`) beside the image they are added
    into, and its :class:`Layout` (None for a ``"direct"`` part)."""
    nx, ny = grid.azimuth.size, grid.range.size
    freq = np.asarray(freq, np.float64)
    out = []
    for kind, a, b in parts:
        if kind == "direct":  # the float32 sums, the weights, one kernel call's profiles (bp's count)
            out.append((8.0 * nx * ny + 4.0 * nx * (b - a)
                        + bp_memory(Sizes(b - a, freq.size, nx, ny, nx * ny, BP_DEFAULT_UPSAMPLE)), None))
        else:
            lay = _layout(positions[a:b], freq, quarter_turn(grid, QUARTERS.index(kind)), w[a:b], leaf, factor,
                          oversample_angle, oversample_range)
            out.append((lay.peak, lay))
    return out


def _ffbp_in_parts(parts, ph, freq, positions, ref_range, grid, azimuth_window, range_window, leaf, factor,
                   oversample_angle, oversample_range, range_taps, progress):
    """:func:`ffbp` of a wide aperture, its parts' images added: each FFBP part formed on its quarter
    turn of ``grid`` and turned back, the ``"direct"`` pulses backprojected directly with ``bp``'s
    profiles (6x, fitted taps: more exact than FFBP)."""
    nx, ny = grid.azimuth.size, grid.range.size
    wa = np.asarray(azimuth_window, np.float32)
    needs = _part_needs(parts, positions, freq, grid, wa, leaf, factor, oversample_angle, oversample_range)
    k = int(np.argmax([n for n, _ in needs]))
    kind, a, b = parts[k]
    lay = needs[k][1]
    what = (f"direct backprojection of {b - a} pulses" if lay is None else
            f"{lay.inputs(b - a, freq.size)} and polar grids ({len(lay.levels)} levels, up to "
            f"{gib(max(lay.grid_bytes))} a level), their range sampling widened {lay.widen:.3g}x,")
    check_memory(8.0 * nx * ny + needs[k][0],
                 f"FFBP of {len(positions)} pulses in {len(parts)} parts of up to {PART_SPAN_DEG:g} degrees around "
                 f"the scene: the largest part's {what} and the {nx} x {ny} image they are added into",
                 "use --algorithm bp, a smaller grid, fewer pulses or a narrower aperture")
    img = np.zeros((nx, ny), np.complex64)
    info, direct, widest = {}, 0, 1.0
    # progress in levels over all the parts (a directly backprojected part counts as one)
    steps = [1 if lay_k is None else len(lay_k.levels) + 1 for _, lay_k in needs]
    total, before = sum(steps), np.concatenate([[0], np.cumsum(steps)[:-1]]).astype(int)
    for k, (kind, a, b) in enumerate(parts):
        step = (lambda done, _total, k=k: progress(int(before[k]) + done, total)) if progress else None
        if kind == "direct":
            row_origin = grid.plane.points(grid.azimuth, np.zeros_like(grid.azimuth))
            W = np.ascontiguousarray(np.broadcast_to(wa[None, a:b], (nx, b - a)))
            re, im = np.zeros((nx, ny), np.float32), np.zeros((nx, ny), np.float32)
            backproject(ph[a:b], freq, positions[a:b], ref_range[a:b], row_origin, grid.plane.range, grid.range, W,
                        range_window, upsample=BP_DEFAULT_UPSAMPLE, out=(re, im), interpolation="fitted")
            img.real += re
            img.imag += im
            direct += b - a
        else:
            q = QUARTERS.index(kind)
            part, info = ffbp(ph[a:b], freq, positions[a:b], ref_range[a:b], quarter_turn(grid, q),
                              azimuth_window[a:b], range_window, leaf, factor, oversample_angle, oversample_range,
                              range_taps, step, split=False)
            img += from_quarter_turn(part, q)
            widest = max(widest, info["ffbp_range_widening"])
        if progress and kind == "direct":
            progress(int(before[k]) + 1, total)
    info = {**info, "ffbp_parts": len(parts), "ffbp_direct_pulses": direct, "ffbp_range_widening": widest}
    return img, info


def ffbp_blocks(pulses, grid: ImageGrid, window: Window, ranges, upsample: int, accuracy: str):
    """Spotlight FFBP of one tile a pulse block at a time: each block's image (its own tree, the
    collection's window over its pulses) added up and normalised as :func:`form_ffbp` over all the
    pulses (FFBP is linear in the data). The ``blocks`` of ``ffbp``'s declaration.

    Parameters
    ----------
    pulses : object
        ``n_pulses`` and ``block(a, b) -> PhaseHistory``.
    grid : ImageGrid
    window : Window
    ranges : list of (int, int)
        The pulse blocks.
    upsample : int
        Not used.
    accuracy : {"standard", "high"}

    Returns
    -------
    (complex64 ndarray, dict)
    """
    P = pulses.n_pulses
    wa = window(P)
    knobs = ACCURATE if accuracy == "high" else {}
    img, info, wr = None, {}, None
    for a, b in ranges:
        ph = pulses.block(a, b)
        if wr is None:
            wr = window(ph.freq.size)
        part, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, grid, wa[a:b], wr, **knobs)
        if img is None:
            img = part
        else:
            img += part
    norm = max(float(wa.sum()), 1e-30) * float(wr.sum())
    info.update({"support_azimuth": P, "support_range": int(wr.size)})
    img *= np.float32(1.0 / norm)  # in place (fresh memory is faulted in again)
    return img, info


def ffbp_memory(sizes: Sizes) -> float:
    """Bytes FFBP adds, from the sizes alone: two buffers of polar grids (each up to 3 times the
    pixels, complex64: margins and padding) and the range profiles (about twice the signal). Where
    the geometry is known, :func:`ffbp_footprint` counts them exactly (a wide arc holds several
    times more).

    Parameters
    ----------
    sizes : Sizes

    Returns
    -------
    float
    """
    return 2 * 3.0 * 8.0 * sizes.nx * sizes.ny + 2 * 8.0 * sizes.pulses * sizes.samples


#: Pixels each side by which an FFBP tile is formed larger than it is kept (its edge error cropped off).
TILE_OVERLAP = 16


@register_former(
    "ffbp", summary="fast factorised backprojection (Ulander 2003), any trajectory: sub-apertures merged on polar grids; "
            "an aperture wider than 30 degrees, to a full circle, formed in parts",
    modes=("spotlight",), tracks="any", phase_reference="aperture_centre", tiles=True, tile_overlap=TILE_OVERLAP,
    blocks=ffbp_blocks, memory=ffbp_memory, footprint=ffbp_footprint,
    accuracy={"standard": Accuracy("polar grids oversampled 1.75 (angle), 2.0 (range)", -55.0,
                                   "-56.8 to -60.9 dB measured to 8192^2, bright-pixel phase p99 < 1 deg"),
              "high": Accuracy("oversampled 3.0 (angle), 2.5 (range), about 2x the time", -65.0,
                               "-70.1 to -76.6 dB measured")})
def form_ffbp(ph: PhaseHistory, grid: ImageGrid, window: Window, *, upsample: int = BP_UPSAMPLE,
              accuracy: str = "standard", progress=None) -> ImageResult:
    """Fast factorised backprojection (the ``ffbp`` former), normalised as ``bp``.

    Parameters
    ----------
    ph : PhaseHistory
        Spotlight collection, any trajectory.
    grid : ImageGrid
    window : Window
        Over the pulses and in range.
    upsample : int
        Not used (the shared calling convention of the formers): the leaves read range profiles
        sampled at the polar grids' range spacing through an 8-tap least-squares kernel.
    accuracy : {"standard", "high"}
        "standard" (the module defaults) or "high" (:data:`ACCURATE`).
    progress : callable, optional
        ``progress(done, total)`` in levels.

    Returns
    -------
    ImageResult

    Raises
    ------
    ScenarioError
        For stripmap data (its beam equalisation is done by ``bp``).
    """
    if ph.beam_limited:
        raise ScenarioError("processing.algorithm", "ffbp", form_ffbp.spec.refusal("stripmap", True))
    P, M = ph.data.shape
    wa = window(P)
    wr = window(M)
    check_choice("processing.accuracy", accuracy, ACCURACY)
    knobs = ACCURATE if accuracy == "high" else {}
    img, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, grid, wa, wr, progress=progress, **knobs)
    norm = max(float(wa.sum()), 1e-30) * float(wr.sum())
    info.update({"support_azimuth": P, "support_range": M})
    img *= np.float32(1.0 / norm)  # in place: a new array is fresh memory, faulted in again
    return ImageResult(img, info)
