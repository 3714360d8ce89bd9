"""Design and geometry of the self-interferometric down-looking SAL (seed 000, eqs 20-25, section 5).

All quantities in SI units (m, s, Hz, rad). ``x`` is across track, ``y`` along track, both on the
target at the reference distance, perpendicular to the boresight.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SamplingError, ScenarioError


def wavelength_from_resolution(resolution: float, magnification: float, focal: float, stop: float) -> float:
    """Wavelength (m) that gives a first-null resolution ``resolution`` (m).

    The PSF along track is sinc(M W_y y / (lambda M^2 f_y / 2)) (eq 21); its first null lies at
    y = lambda M f_y / (2 W_y), half the eq-22 width. Hence lambda = 2 delta W / (M f).

    Examples
    --------
    >>> round(wavelength_from_resolution(0.018, 1500, 0.06, 0.005) * 1e6, 6)
    2.0

    Parameters
    ----------
    resolution : float
        m.
    magnification : float
    focal : float
        m.
    stop : float
        Field-stop width, m.

    Returns
    -------
    float
        m.
    """
    for name, v in (("resolution", resolution), ("magnification", magnification), ("focal", focal),
                    ("stop", stop)):
        if not (v > 0 and math.isfinite(v)):
            raise ScenarioError(name, v, "must be a positive finite number")
    return 2.0 * resolution * stop / (magnification * focal)


def lens_extent(stop: float, centre_offset: float, scan_travel: float) -> tuple[float, float]:
    """Interval of a scanning cylindrical lens (m, in lens coordinates about its optical centre) that
    must be glass so that it covers the field stop throughout the scan.

    The lens centre sits at ``centre_offset + u`` with u in [-scan_travel/2, +scan_travel/2]
    (scan_travel = v_x T_f); the stop spans [-W/2, W/2].

    Parameters
    ----------
    stop : float
        Field-stop width W, m.
    centre_offset : float
        m.
    scan_travel : float
        m.

    Returns
    -------
    (float, float)
        m.
    """
    lo = -stop / 2 - centre_offset - scan_travel / 2
    hi = stop / 2 - centre_offset + scan_travel / 2
    return lo, hi


def paper_lens_width(stop: float, centre_offset: float) -> float:
    """Lens width by the formulas at the end of seed 000 section 5 (scan (-W_x/2, W_x/2)), m.

    Parameters
    ----------
    stop : float
        m.
    centre_offset : float
        m.

    Returns
    -------
    float
        m.
    """
    if centre_offset > stop / 2:
        return 1.5 * stop + centre_offset
    return 2.0 * stop


@dataclass(frozen=True)
class DLDesign:
    """Derived quantities of a down-looking SAL design (all SI)."""

    wavelength: float
    wavelength_derived: bool
    magnification: float          # M = Z / f_t
    range: float                  # Z, m
    spot_x: float                 # M W_x (swath X_p), m
    spot_y: float                 # M W_y, m
    scan_factor: float            # K = v_x T_f / W_x
    xi_per_m: float               # beat frequency per metre across track, Hz/m: 2 v_x / (M lambda f_x)
    along_chirp: float            # along-track history phase per m^2: 2 pi / (M^2 lambda f_y), rad/m^2
    resolution_x: float           # first null, m: M lambda f_x / (2 K W_x)
    resolution_y: float           # first null, m: lambda M f_y / (2 W_y)
    width_x_eq23: float           # eq 23 (null-to-null), m
    width_y_eq22: float           # eq 22 (null-to-null), m
    irw_x: float                  # 3 dB width, m (0.8859 x first null)
    irw_y: float
    fringe_period_xi: float       # eq 24, Hz
    fringe_period_x: float        # eq 25, m
    beat_min: float               # Hz, swath edge nearest DC
    beat_max: float               # Hz
    samples: int                  # fast-time samples per scan
    sample_rate: float            # Hz
    nyquist_spacing_y: float      # along-track Nyquist spacing of one scan direction's history, m
    lens_forward: tuple[float, float]
    lens_backward: tuple[float, float]
    lens_width_forward: float
    lens_width_backward: float
    lens_width_paper_forward: float
    lens_width_paper_backward: float
    transmit_pupil_diameter: float  # beam footprint on the transmit primary, m
    coupling_length: float        # lambda Z / D_r: cross-scatterer terms survive below it, m
    warnings: tuple[str, ...] = field(default_factory=tuple)

    def as_dict(self) -> dict:
        """Flat dict of the numbers (tuples expanded), for metrics and reports."""
        out = {}
        for k, v in self.__dict__.items():
            if k == "warnings":
                continue
            if isinstance(v, tuple):
                out[f"{k}_min_m"], out[f"{k}_max_m"] = float(v[0]), float(v[1])
            elif isinstance(v, bool):
                out[k] = int(v)
            else:
                out[k] = float(v) if isinstance(v, float) else v
        return out


def design(exp) -> DLDesign:
    """Derive the design quantities of a :class:`~salkit.params.downlooking.DownlookingExperiment`.

    Raises
    ------
    SamplingError
        When the fast-time sampling would alias the beat (ADC below twice the highest beat) or
        one scan direction samples the along-track quadratic phase history below its Nyquist rate.

    Examples
    --------
    >>> from salkit.params import load_scenario
    >>> d = design(load_scenario("examples/downlooking_3d.yaml").experiment)  # doctest: +SKIP
    >>> round(d.fringe_period_x, 4)  # doctest: +SKIP
    0.18

    Parameters
    ----------
    exp : DownlookingExperiment

    Returns
    -------
    DLDesign
    """
    o, s, tr = exp.optics, exp.scan, exp.track
    M = tr.range / o.focal_transmit
    warnings = []
    derived = o.wavelength is None
    if derived:
        lam = wavelength_from_resolution(exp.requirements.resolution, M, o.focal_y, o.stop_y)
    else:
        lam = o.wavelength
    if exp.requirements is not None:
        rq = exp.requirements
        if not math.isclose(rq.range, tr.range, rel_tol=1e-9):
            warnings.append(f"requirements.range {rq.range:g} m differs from track.range {tr.range:g} m")
        if not math.isclose(rq.spot, M * o.stop_x, rel_tol=1e-3):
            warnings.append(f"requirements.spot {rq.spot:g} m differs from M W_x = {M * o.stop_x:g} m")
    K = s.speed * s.duration / o.stop_x
    xi_per_m = 2 * s.speed / (M * lam * o.focal_x)
    res_x = M * lam * o.focal_x / (2 * K * o.stop_x)
    res_y = lam * M * o.focal_y / (2 * o.stop_y)
    beat_lo = 2 * (o.bias_common - o.stop_x / 2) * s.speed / (lam * o.focal_x)
    beat_hi = 2 * (o.bias_common + o.stop_x / 2) * s.speed / (lam * o.focal_x)
    nyq = 2 * max(abs(beat_lo), abs(beat_hi))
    if s.samples is None:
        n = 1 << int(math.ceil(math.log2(max(1.25 * nyq * s.duration, 16))))
    else:
        n = s.samples
    fs = n / s.duration
    if fs < nyq:
        raise SamplingError("experiment.scan.samples", n,
                            f"the ADC rate {fs:.6g} Hz (samples / T_f) is below twice the highest beat "
                            f"{nyq / 2:.6g} Hz = 2 (S_b + W_x/2) v_x / (lambda f_x): the beat would alias")
    nyq_y = lam * M * o.focal_y / (2 * o.stop_y)
    if 2 * tr.spacing > nyq_y * (1 + 1e-9):
        raise SamplingError("experiment.track.spacing", tr.spacing,
                            f"each scan direction samples the along-track quadratic phase every 2 Delta-Y = "
                            f"{2 * tr.spacing:.4g} m, above its Nyquist spacing lambda M f_y / (2 W_y) = "
                            f"{nyq_y:.4g} m; use Delta-Y <= {nyq_y / 2:.4g} m")
    if beat_lo * s.duration < 1.0 and not exp.allow_twin_overlap:
        warnings.append(
            f"sideband margin: M S_b = {M * o.bias_common:.4g} m against X_p/2 = {M * o.stop_x / 2:.4g} m; "
            f"targets within {res_x - M * (o.bias_common - o.stop_x / 2):.3g} m of the -x swath edge lie within "
            "one resolution cell of their twin at zero frequency")
    travel = s.speed * s.duration
    s1, s2 = o.bias_common + o.bias_opposite, o.bias_common - o.bias_opposite
    lf, lb = lens_extent(o.stop_x, s1, travel), lens_extent(o.stop_x, s2, travel)
    # beam footprint on the transmit primary: a stop point x_in leaves at angle (x_in - s)/f_x and
    # crosses the primary at x_in + f_t (x_in - s)/f_x
    far = o.stop_x / 2 + abs(o.bias_common) + o.bias_opposite + travel / 2
    pupil = 2 * (o.stop_x / 2 + o.focal_transmit * far / o.focal_x)
    return DLDesign(
        wavelength=lam, wavelength_derived=derived, magnification=M, range=tr.range,
        spot_x=M * o.stop_x, spot_y=M * o.stop_y, scan_factor=K, xi_per_m=xi_per_m,
        along_chirp=2 * math.pi / (M * M * lam * o.focal_y),
        resolution_x=res_x, resolution_y=res_y, width_x_eq23=2 * res_x, width_y_eq22=2 * res_y,
        irw_x=0.88589 * res_x, irw_y=0.88589 * res_y,
        fringe_period_xi=s.speed / o.bias_opposite if o.bias_opposite > 0 else math.inf,
        fringe_period_x=(M * lam * o.focal_x / (2 * o.bias_opposite)) if o.bias_opposite > 0 else math.inf,
        beat_min=beat_lo, beat_max=beat_hi, samples=n, sample_rate=fs, nyquist_spacing_y=nyq_y,
        lens_forward=lf, lens_backward=lb, lens_width_forward=lf[1] - lf[0], lens_width_backward=lb[1] - lb[0],
        lens_width_paper_forward=paper_lens_width(o.stop_x, s1),
        lens_width_paper_backward=paper_lens_width(o.stop_x, s2),
        transmit_pupil_diameter=pupil, coupling_length=lam * tr.range / o.receive_aperture,
        warnings=tuple(warnings))


def design_from_requirements(range_m: float, spot: float, resolution: float, stop: float,
                             focal: float, bias_common: float | None = None,
                             bias_opposite: float = 0.5e-3) -> dict:
    """The seed's design procedure: requirements in, optical parameters out.

    Parameters
    ----------
    range_m : float
        Working range Z, m.
    spot : float
        Side of the square illuminated spot, m.
    resolution : float
        First-null resolution, m.
    stop : float
        Field-stop width W (square), m.
    focal : float
        Focal length of the cylindrical lenses f_x = f_y, m.
    bias_common : float, optional
        S_b, m; default W/2 (the smallest that keeps one sideband).
    bias_opposite : float
        S_a, m.

    Returns
    -------
    dict
        ``magnification``, ``focal_transmit`` (m), ``wavelength`` (m), ``resolution_x``/``_y``
        (first null, m), ``width_eq22`` (m), ``fringe_period_x`` (eq 25, m), lens widths (m).

    Examples
    --------
    >>> d = design_from_requirements(1800.0, 7.5, 0.018, 0.005, 0.06)
    >>> round(d["focal_transmit"], 6), round(d["wavelength"] * 1e6, 6), round(d["fringe_period_x"], 6)
    (1.2, 2.0, 0.18)
    """
    for name, v in (("range", range_m), ("spot", spot), ("resolution", resolution), ("stop", stop),
                    ("focal", focal), ("bias_opposite", bias_opposite)):
        if not (v > 0 and math.isfinite(v)):
            raise ScenarioError(name, v, "must be a positive finite number")
    M = spot / stop
    ft = range_m / M
    lam = wavelength_from_resolution(resolution, M, focal, stop)
    sb = stop / 2 if bias_common is None else bias_common
    s1, s2 = sb + bias_opposite, sb - bias_opposite
    lf, lb = lens_extent(stop, s1, stop), lens_extent(stop, s2, stop)
    return {
        "magnification": M, "focal_transmit": ft, "wavelength": lam,
        "resolution_x": M * lam * focal / (2 * stop), "resolution_y": lam * M * focal / (2 * stop),
        "width_eq22": lam * M * focal / stop,
        "fringe_period_x": M * lam * focal / (2 * bias_opposite),
        "sideband_margin_m": M * sb - spot / 2,
        "lens_width_forward": lf[1] - lf[0], "lens_width_backward": lb[1] - lb[0],
        "lens_width_paper_forward": paper_lens_width(stop, s1),
        "lens_width_paper_backward": paper_lens_width(stop, s2),
    }


def boresight_frame(look_angle_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit vectors (e_x, e_y, b) of the beam frame in the ground frame.

    The ground frame is the foundation's: x along track, y across track, z up, scene centre at
    the origin. b points from the platform to the scene centre, tilted ``look_angle_deg`` from
    nadir towards +y; e_x (the beam's cross-track axis) is perpendicular to b in the y-z plane and
    e_y (along track) is the ground x axis.

    Parameters
    ----------
    look_angle_deg : float
        deg.

    Returns
    -------
    (float64 (3,), float64 (3,), float64 (3,))
    """
    th = math.radians(look_angle_deg)
    b = np.array([0.0, math.sin(th), -math.cos(th)])
    ex = np.array([0.0, math.cos(th), math.sin(th)])
    ey = np.array([1.0, 0.0, 0.0])
    return ex, ey, b


def beam_coordinates(points: np.ndarray, range_m: float, look_angle_deg: float) -> tuple[np.ndarray, ...]:
    """Beam-frame coordinates of ground points, relative to the platform at along-track position 0.

    Parameters
    ----------
    points : ndarray (N, 3)
        Ground coordinates (x along track, y across, z up), m, scene centre at the origin.
    range_m : float
        Boresight distance from the platform to the scene centre, m.
    look_angle_deg : float

    Returns
    -------
    d_x, y, d_z : ndarray
        Cross-track offset from the boresight, along-track ground position, and axial distance, m
        (float64). The platform at along-track position Y sees the point at d_y = y - Y.
    """
    ex, ey, b = boresight_frame(look_angle_deg)
    p = np.asarray(points, np.float64)
    rel = p + range_m * b  # the platform sits at -range * b when its along-track position is 0
    return rel @ ex, p[:, 0], rel @ b


def jones(hwp_angle_deg: float) -> tuple[float, float]:
    """(c, s) = (cos 2 theta, sin 2 theta) of the receiving half-wave plate.

    Parameters
    ----------
    hwp_angle_deg : float
        deg.

    Returns
    -------
    (float, float)

    Examples
    --------
    >>> [round(v, 6) for v in jones(22.5)]
    [0.707107, 0.707107]
    """
    th = math.radians(hwp_angle_deg)
    return math.cos(2 * th), math.sin(2 * th)
