"""Units of salkit's named quantities, and their display.

Metric and parameter names carry their SI unit as a suffix (``irw_range_m``, ``pslr_azimuth_db``,
``t_focus_s``); a few older names do not (the sampling report, the down-looking design) and are
listed in :data:`NAMED`. :func:`unit_of` gives the unit of any name, :func:`display` a value rounded
to its meaning with a unit a person reads (lengths in km, m, cm, mm, um or nm).
"""
from __future__ import annotations

import math

import numpy as np

#: Suffixes and their units, longest first (the first that matches wins).
SUFFIXES: tuple[tuple[str, str], ...] = (
    ("_m_s", "m/s"), ("_per_s", "1/s"), ("_rad_m2", "rad/m^2"), ("_hz_m", "Hz/m"), ("_db", "dB"),
    ("_rad", "rad"), ("_deg", "deg"), ("_mhz", "MHz"), ("_hz", "Hz"), ("_m2", "m^2"), ("_m", "m"),
    ("_s", "s"), ("_w", "W"), ("_j", "J"), ("_bytes", "B"), ("_mib", "MiB"), ("_pct", "%"),
    ("_cn2", "m^(-2/3)"),
)

#: Names without a unit suffix: the sampling report (``sampling_*``), the down-looking design, and
#: dimensionless quantities whose names would otherwise look like a suffix.
NAMED: dict[str, str] = {
    "doppler_bandwidth": "Hz", "prf": "Hz", "beat_bandwidth": "Hz", "adc_rate": "Hz", "gate": "s",
    "delay_min": "s", "delay_max": "s", "resolution_range": "m", "resolution_azimuth": "m", "footprint": "m",
    "wavelength": "m", "magnification": "", "range": "m", "spot_x": "m", "spot_y": "m", "scan_factor": "",
    "xi_per_m": "Hz/m", "along_chirp": "rad/m^2", "resolution_x": "m", "resolution_y": "m",
    "width_x_eq23": "m", "width_y_eq22": "m", "irw_x": "m", "irw_y": "m", "fringe_period_xi": "Hz",
    "fringe_period_x": "m", "beat_min": "Hz", "beat_max": "Hz", "samples": "", "sample_rate": "Hz",
    "nyquist_spacing_y": "m", "lens_width_forward": "m", "lens_width_backward": "m",
    "lens_width_paper_forward": "m", "lens_width_paper_backward": "m", "transmit_pupil_diameter": "m",
    "coupling_length": "m", "wavelength_derived": "",
    # scenario fields a sweep varies (docs/studies.md)
    "cn2": "m^(-2/3)", "speed": "m/s", "altitude": "m", "standoff": "m", "aperture_length": "m",
    "screen_dx": "m", "outer_scale": "m", "inner_scale": "m", "signal_photons": "",
    # attributes of salkit's data files (docs/data-format.md)
    "carrier_frequency": "Hz", "chirp_rate": "Hz/s", "bandwidth": "Hz", "pulse_width": "s", "real_aperture": "m",
    "center_position": "m", "scene_center": "m", "aperture_center": "m", "plane_origin": "m", "grid_dx": "m",
    "grid_dy": "m", "frequency_min": "Hz", "frequency_max": "Hz", "fringe_period_theory": "m",
    "irw_azimuth_theory": "m", "irw_range_theory": "m", "islr_theory": "dB", "pslr_theory": "dB",
    "pslr_range_theory": "dB", "pslr_azimuth_theory": "dB", "window_irw_factor": "",
    "support_azimuth_extent": "rad/m", "support_range_extent": "rad/m", "islr_range_theory": "dB", "islr_azimuth_theory": "dB",
    "illuminated_azimuth": "m", "illuminated_range": "m", "range_reference": "m",
    # image measures
    "entropy": "nats", "contrast": "",
}

#: Yes/no quantities stored as 0/1 (NetCDF and metrics.json hold no booleans): shown as true/false,
#: never drawn or judged as a measurement.
FLAGS = frozenset({"iq", "wavelength_derived", "design_wavelength_derived", "speckle", "beam_weighting", "stack_model_3d",
                   "rvp_removed", "noise_added", "collection_time_nominal", "image_out_of_core", "extended_scene",
                   "sweep_perturbed", "sweep_in_clutter"})

#: Bookkeeping numbers of a run that are not measurements (indices, counts of what was done).
NOT_MEASUREMENTS = frozenset({"target_index", "tiles", "focus_s", "simulate_s", "form_s", "autofocus_s"})

def display_scale(unit: str, values) -> tuple[float, str]:
    """The factor and unit to draw ``values`` (in ``unit``) with, so that the largest stays between 1
    and 1000 (GHz, cm, us); other units unscaled.

    Parameters
    ----------
    unit : str
        SI unit of the values ("m", "Hz", "s", ...).
    values : array-like

    Returns
    -------
    (float, str)
        Divide by the factor; the unit to write.

    Examples
    --------
    >>> display_scale("Hz", [4e9, 1.6e10])
    (1000000000.0, 'GHz')
    >>> display_scale("m", [0.0125, 0.0188])
    (0.01, 'cm')
    """
    v = np.asarray(values, dtype=float)
    v = np.abs(v[np.isfinite(v)])
    if unit not in SCALES or not v.size or v.max() == 0:
        return 1.0, unit
    top = float(v.max())
    for factor, name in SCALES[unit]:
        if top >= factor * (1 - 1e-9):
            return factor, name
    return SCALES[unit][-1]


#: Units a value is shown in so that it stays between 1 and 1000 (largest first).
SCALES = {
    "m": ((1e3, "km"), (1.0, "m"), (1e-2, "cm"), (1e-3, "mm"), (1e-6, "um"), (1e-9, "nm")),
    "Hz": ((1e12, "THz"), (1e9, "GHz"), (1e6, "MHz"), (1e3, "kHz"), (1.0, "Hz"), (1e-3, "mHz")),
    "s": ((1.0, "s"), (1e-3, "ms"), (1e-6, "us"), (1e-9, "ns"), (1e-12, "ps")),
}


def unit_of(name: str) -> str:
    """The unit of a metric or parameter name ("" when dimensionless or unknown).

    Parameters
    ----------
    name : str
        A key of ``metrics.json`` or of a report (``sampling_`` prefixes are looked through).

    Returns
    -------
    str

    Examples
    --------
    >>> unit_of("irw_range_theory_m"), unit_of("pslr_azimuth_db"), unit_of("sampling_prf")
    ('m', 'dB', 'Hz')
    >>> unit_of("lens_forward_min_m"), unit_of("stack_count")
    ('m', '')
    """
    key = name.lower()
    for prefix in ("sampling_", "design_"):
        if key.startswith(prefix) and key[len(prefix):] in NAMED:
            return NAMED[key[len(prefix):]]
    if key in NAMED:
        return NAMED[key]
    for suffix, unit in SUFFIXES:
        if key.endswith(suffix):
            return unit
    return ""


#: Unit suffixes of metric names before which a metric's theory value carries ``_theory``.
THEORY_SUFFIXES = ("_m", "_db", "_rad", "_s", "_hz", "_deg", "_w")


def theory_name(name: str) -> str:
    """The name of a metric's theory value: ``irw_range_m`` -> ``irw_range_theory_m``,
    ``snr_single`` -> ``snr_single_theory``.

    Parameters
    ----------
    name : str

    Returns
    -------
    str

    Examples
    --------
    >>> theory_name("irw_range_m"), theory_name("pslr_azimuth_db"), theory_name("image_snr")
    ('irw_range_theory_m', 'pslr_azimuth_theory_db', 'image_snr_theory')
    """
    for suf in THEORY_SUFFIXES:
        if name.endswith(suf):
            return name[: -len(suf)] + "_theory" + suf
    return name + "_theory"


def round_sig(x: float, digits: int = 4) -> str:
    """``x`` to ``digits`` significant digits, without exponent between 1e-3 and 1e6.

    Parameters
    ----------
    x : float
    digits : int

    Returns
    -------
    str

    Examples
    --------
    >>> round_sig(0.017971234), round_sig(123456.7), round_sig(3.2e-9), round_sig(0.0)
    ('0.01797', '123457', '3.2e-09', '0')
    """
    if x == 0 or not math.isfinite(x):
        return str(x) if not math.isfinite(x) else "0"
    mag = math.floor(math.log10(abs(x)))
    if -3 <= mag < 6:
        dec = max(digits - 1 - mag, 0)
        return f"{x:.{dec}f}"
    return f"{x:.{digits - 1}e}".replace(".000e", "e").replace("00e", "e").replace("0e", "e")


def display(name: str, value, digits: int = 4) -> tuple[str, str]:
    """A value as a person reads it: rounded to ``digits`` significant digits, lengths, frequencies
    and times in the unit that keeps them between 1 and 1000 (:data:`SCALES`; times of a second
    and more stay in seconds), booleans and counts as such.

    Parameters
    ----------
    name : str
        The quantity's name (its unit from :func:`unit_of`).
    value : object
    digits : int

    Returns
    -------
    (str, str)
        The number and its unit.

    Examples
    --------
    >>> display("irw_range_m", 0.017971), display("pslr_range_db", -13.2512), display("stack_count", 64)
    (('1.797', 'cm'), ('-13.25', 'dB'), ('64', ''))
    >>> display("sampling_adc_rate", 2e7), display("sampling_gate", 9.992e-6)
    (('20.00', 'MHz'), ('9.992', 'us'))
    """
    unit = unit_of(name)
    if isinstance(value, bool):
        return ("yes" if value else "no"), ""
    if isinstance(value, int):
        return str(value), unit
    if not isinstance(value, float):
        return str(value), unit
    if unit in SCALES and value != 0 and math.isfinite(value):
        steps = SCALES[unit]
        for scale, u in steps:
            if abs(value) >= scale or u == steps[-1][1]:
                return round_sig(value / scale, digits), u
    return round_sig(value, digits), unit
