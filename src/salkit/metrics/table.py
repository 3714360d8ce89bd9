"""The table of metrics: every figure a salkit run reports, declared once with its unit, its
meaning and its theory partner (:data:`salkit.registry.METRICS`).

A run's ``metrics.json`` names a metric plainly (``irw_range_m``), as a theory partner
(``irw_range_theory_m``), or under a label the run gives its cases (``medium_pga_entropy``: the
``medium`` turbulence class after PGA; ``A_deskew_irw_m``: link A, deskewed): a label is any prefix
ending in ``_`` before a declared name, since the cases are named by the user (turbulence classes)
or by a system (chirp links). Names with ``{}`` stand for a family: the braces match a number
(``snr_stack_{}``: the stack of 10, 13, ... sub-images; ``resolution_azimuth_squint_{}_m``), and
``{word}`` a field name (``sampling_{word}``: the fields of the sampling report).
:func:`lookup` resolves a name; :func:`check_metric` refuses one that resolves to nothing, with
the nearest declared name (``salkit sweep --metric`` and sweep files). Adding a metric is one
:func:`declare_metric` call here beside the code that measures it (docs/architecture.md).
"""
from __future__ import annotations

import difflib
import re
import warnings
from dataclasses import dataclass
from functools import lru_cache
from typing import Optional

import numpy as np

from ..errors import ScenarioError
from ..registry import METRICS, declare
from ..units import theory_name


@dataclass(frozen=True)
class MetricSpec:
    """One metric of the table.

    Attributes
    ----------
    name : str
        As in ``metrics.json`` (``{}``: a number, for a family).
    unit : str
        Its unit ("" when dimensionless).
    meaning : str
        What it measures, in one line.
    theory : str or None
        The name of its theory partner (:func:`salkit.units.theory_name`), or None when theory
        gives no value to compare with.
    """

    name: str
    unit: str
    meaning: str
    theory: Optional[str]

    @property
    def pattern(self) -> re.Pattern:
        """The regular expression of the names it stands for (itself and its theory partner)."""
        return _compiled((self.name,) + ((self.theory,) if self.theory else ()))


@lru_cache(maxsize=None)
def _compiled(alts: tuple) -> re.Pattern:
    """The pattern of a metric's names (compiled once: runs look every metric name up)."""
    return re.compile("|".join("(?:" + re.escape(a).replace(r"\{\}", r"[0-9][0-9.]*").replace(
        r"\{word\}", r"[a-z][a-z0-9_]*") + ")" for a in alts))


def declare_metric(name: str, unit: str, meaning: str, theory: bool | str | None = None) -> MetricSpec:
    """Declare a metric.

    Parameters
    ----------
    name : str
    unit : str
    meaning : str
    theory : bool or str, optional
        True: its theory partner is :func:`salkit.units.theory_name` of ``name``; a string: that
        name; None: none.

    Returns
    -------
    MetricSpec
    """
    partner = theory_name(name) if theory is True else (theory or None)
    spec = declare(MetricSpec, f"metric {name!r}", name=name, unit=unit, meaning=meaning, theory=partner)
    return METRICS.add(name.replace("{}", "N").replace("{word}", "X"), spec)  # its key an identifier


def lookup(name: str) -> Optional[MetricSpec]:
    """The declared metric ``name`` is, or is a labelled case or theory partner of (None if none).

    Parameters
    ----------
    name : str

    Returns
    -------
    MetricSpec or None

    Examples
    --------
    >>> lookup("medium_pga_entropy").name, lookup("irw_range_theory_m").name, lookup("snr_stack_13").name
    ('entropy', 'irw_range_m', 'snr_stack_{}')
    >>> lookup("bogus_rad") is None
    True
    """
    specs = [s for _, s in METRICS.items()]
    key = (str(name), len(specs))  # a declaration added later is looked up afresh
    if key in _LOOKED_UP:
        return _LOOKED_UP[key]
    found = None
    parts = str(name).split("_")
    for k in range(len(parts)):  # the name itself, then without one more leading label word
        tail = "_".join(parts[k:])
        found = next((s for s in specs if s.pattern.fullmatch(tail)), None)
        if found is not None:
            break
    if len(_LOOKED_UP) < 100_000:
        _LOOKED_UP[key] = found
    return found


#: Names already looked up (with the number of declarations then) -> their metric or None.
_LOOKED_UP: dict = {}


def check_metric(name: str, field: str = "--metric") -> MetricSpec:
    """The declared metric of ``name``, or the error naming the nearest declared one.

    Parameters
    ----------
    name : str
    field : str
        The option or sweep-file key that named it.

    Returns
    -------
    MetricSpec

    Raises
    ------
    ScenarioError
        For a name that is no declared metric, no labelled case of one and no theory partner.
    """
    spec = lookup(name)
    if spec is None:
        names = [s.name for _, s in METRICS.items()]
        parts = str(name).split("_")
        best, hint = -1.0, None
        for k in range(len(parts)):  # the nearest declared name to any tail, its labels kept
            tail = "_".join(parts[k:])
            for cand in names:
                r = difflib.SequenceMatcher(None, tail, cand).ratio()
                if r > best:
                    best, hint = r, "_".join(parts[:k] + [cand])
        raise ScenarioError(field, name, f"is not a metric salkit measures (the nearest: '{hint}'); the table of "
                            "metrics is docs/metrics.md")
    return spec


class UndeclaredMetricWarning(UserWarning):
    """A run reported a metric the table does not declare (the test suite makes it an error)."""


def undeclared(metrics: dict) -> list[str]:
    """The numeric metrics of ``metrics`` (nested dicts looked into) that resolve to no declared one.

    Parameters
    ----------
    metrics : dict

    Returns
    -------
    list of str
    """
    out = []
    for k, v in metrics.items():
        if isinstance(v, dict):
            out += undeclared(v)
        elif isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) and not str(k).startswith("_"):
            if lookup(str(k)) is None:
                out.append(str(k))
    return out


def warn_undeclared(metrics: dict, where: str) -> None:
    """Warn (:class:`UndeclaredMetricWarning`) of the metrics of ``metrics`` not in the table.

    Parameters
    ----------
    metrics : dict
    where : str
        What reported them, for the message.
    """
    missing = undeclared(metrics)
    if missing:
        warnings.warn(f"{where} reported metrics not in the table of metrics (salkit.metrics.table): "
                      f"{', '.join(sorted(missing))}", UndeclaredMetricWarning, stacklevel=2)


def metrics_table() -> str:
    """The table of metrics as Markdown (docs/metrics.md), from the declarations.

    Returns
    -------
    str
    """
    rows = ["| metric | unit | meaning | theory partner |", "|---|---|---|---|"]
    for _, s in METRICS.items():
        rows.append(f"| `{s.name}` | {s.unit or '-'} | {s.meaning} | {f'`{s.theory}`' if s.theory else '-'} |")
    return "\n".join(rows) + "\n"


_D = declare_metric
# ---------------------------------------------------------------- a point target (metrics.measure)
_D("irw_range_m", "m", "impulse response width (-3 dB) along range", True)
_D("irw_azimuth_m", "m", "impulse response width (-3 dB) along azimuth", True)
_D("pslr_range_db", "dB", "peak sidelobe ratio along range", True)
_D("pslr_azimuth_db", "dB", "peak sidelobe ratio along azimuth", True)
_D("islr_range_db", "dB", "integrated sidelobe ratio along range", True)
_D("islr_azimuth_db", "dB", "integrated sidelobe ratio along azimuth", True)
_D("peak_offset_range_m", "m", "upsampled peak's range minus the true target's (theory 0)", True)
_D("peak_offset_azimuth_m", "m", "upsampled peak's azimuth minus the true target's (theory 0)", True)
_D("peak_range_m", "m", "range of the upsampled peak of the brightest target")
_D("peak_azimuth_m", "m", "azimuth of the upsampled peak of the brightest target")
_D("peak_amplitude", "", "magnitude of the upsampled peak (a unit point at the beam centre: 1)")
_D("image_phase_at_peak_rad", "rad", "phase of the image at its upsampled peak, as formed (deterministic phase in)")
_D("peak_phase_rad", "rad", "the target's phase: the image's, its deterministic phase restored at the true "
   "target position (the reflectivity's phase when ideal)")
_D("peak_phase_error_rad", "rad", "peak_phase_rad minus the reflectivity's phase (theory 0)", True)
_D("target_index", "", "which truth target the brightest peak is nearest")
_D("target_azimuth_m", "m", "azimuth of that truth target")
_D("target_range_m", "m", "range of that truth target")
_D("target_amplitude", "", "reflectivity amplitude of that truth target")
_D("resolution_range_m", "m", "range resolution c/2B of the band processed (theory only)",
   "resolution_range_theory_m")
_D("resolution_azimuth_m", "m", "azimuth resolution lambda R / 2 L of the aperture processed (theory only)",
   "resolution_azimuth_theory_m")
_D("entropy", "nats", "image entropy of the normalised intensity")
_D("contrast", "", "image contrast std(I) / mean(I)")
_D("image_snr", "", "speckle image SNR mean(I)^2 / var(I) of an extended scene", True)
_D("peak_ratio", "", "peak amplitude relative to the undisturbed image's")
# ---------------------------------------------------------------- photon noise (seed 001's model)
_D("noise_power", "", "image noise power measured where the scene is empty", True)
_D("equalisation_efficiency", "", "coherent gain of the processing window and beam equalisation over the ideal")
_D("image_cnr", "", "carrier-to-noise ratio eta Ns of a unit cell (theory only)", "image_cnr_theory")
_D("cnr_peak", "", "the brightest target's peak power over the noise power", True)
_D("image_snr_mean_cell_cnr", "", "mean cell power of the speckled scene over the noise power (theory)")
_D("unmeasured", "", "metrics a point could not measure (a sweep's text variable)")
# ---------------------------------------------------------------- a run's bookkeeping
_D("n_pulses", "", "pulses of the collection")
_D("n_samples", "", "fast-time samples a pulse")
_D("scene_scatterers", "", "scatterers simulated")
_D("scatterers", "", "scatterers simulated (a case's)")
_D("extended_scene", "", "the scene has an extended part (flag)")
_D("image_out_of_core", "", "the image was formed into its file tile by tile (flag)")
_D("simulate_s", "s", "wall time simulating")
_D("focus_s", "s", "wall time forming the image")
_D("run_s", "s", "wall time of the run")
_D("time_{word}_s", "s", "wall time of a stage")
_D("time_total_s", "s", "wall time of the experiment")
_D("sampling_{word}", "", "the fields of the sampling report (salkit.geometry.sampling.SamplingReport; units: "
   "salkit.units.NAMED)")
_D("design_{word}", "", "the fields of the down-looking design (salkit.geometry.downlooking; docs/downlooking.md)")
# ---------------------------------------------------------------- turbulence (seed 004)
_D("cn2", "m^(-2/3)", "refractive-index structure constant of the class")
_D("r0_plane_m", "m", "Fried parameter, plane wave, over the path")
_D("r0_spherical_m", "m", "Fried parameter, spherical wave, over the path")
_D("r0_two_way_m", "m", "two-way coherence length of the path")
_D("strehl_at_target", "", "intensity at the target over the turbulence-free one", True)
_D("rytov_spherical", "", "Rytov variance of a spherical wave over the path (scintillation strength)")
# ---------------------------------------------------------------- 3-D objects
_D("object_samples_hidden_fraction", "", "fraction of the objects' surface samples facing the sensor that another "
   "surface hides (shadows)")
# ---------------------------------------------------------------- lasers of finite linewidth
_D("peak_power_loss", "", "intensity at the target over a perfectly coherent laser's (theory: the ensemble mean, "
   "exp(-sigma^2) and the pedestal the phase noise leaves)", True)
_D("phase_noise_variance", "rad^2", "variance of the beat's phase error, 2 pi linewidth |tau - tau_LO| (theory only)",
   "phase_noise_variance_theory")
# ---------------------------------------------------------------- wave optics (salkit propagate)
_D("rytov_variance", "", "Rytov variance of the wave over the path")
_D("scintillation_index", "", "normalised intensity variance at a point receiver", True)
_D("scintillation_index_theory_zero_inner_scale", "", "Andrews-Phillips scintillation index without the inner scale")
_D("inner_scale_m", "m", "inner scale l0 of the turbulence")
_D("inner_scale_q", "", "Q_l = 10.89 L / (k l0^2), the inner scale's Fresnel parameter")
_D("grid_n", "", "propagation grid side, samples")
_D("grid_dx_m", "m", "propagation grid spacing (at the receiver)")
_D("source_dx_m", "m", "grid spacing at the source (spherical wave)")
_D("layers", "", "phase screens on the path")
_D("layer_r0_m", "m", "Fried parameter of one layer's slab")
_D("receiver_m", "m", "side of the receiver region (spherical wave)")
_D("realisations", "", "realisations of the ensemble")
# ---------------------------------------------------------------- autofocus (labelled pga_ or autofocus_)
_D("iterations", "", "autofocus iterations (sweeps) run")
_D("best_iteration", "", "the iteration autofocus kept (lowest entropy)")
_D("converged", "", "autofocus met its stopping rule (flag)")
_D("entropy_{}", "nats", "image entropy after autofocus iteration n")
_D("phase_rms_{}", "", "RMS of the phase correction of autofocus iteration n, rad")
_D("phase_rms", "", "RMS of the per-pulse phase autofocus estimated, rad")
_D("pixels", "", "pixels the per-pulse sharpness is measured on")
_D("sharpness_{}", "", "sharpness of the image after per-pulse autofocus sweep n")
_D("autofocus_s", "s", "wall time of autofocus")
_D("screen_n", "", "side of the wave-optics phase screens, samples")
_D("screens_sf_ratio_at_N4", "", "phase screens' structure function over theory at a quarter of the screen")
_D("screens_sf_max_deviation_2px_to_N4", "", "largest relative deviation of the screens' structure function from theory")
# ---------------------------------------------------------------- nonlinear chirp (seed 002)
_D("irw_m", "m", "range IRW of the compressed pulse")
_D("pslr_db", "dB", "range PSLR of the compressed pulse")
_D("islr_db", "dB", "range ISLR of the compressed pulse")
_D("compression_ratio", "", "beat-spectrum width before over after the correction")
_D("width_after_hz", "Hz", "beat-spectrum width after the correction")
_D("c2_hz_per_s2", "Hz/s^2", "quadratic coefficient of the chirp's frequency, fitted from the reference channel")
_D("c3_hz_per_s3", "Hz/s^3", "cubic coefficient of the chirp's frequency, fitted from the reference channel")
_D("cells", "", "cells of the paper's table reproduced")
_D("cells_within_5pct_of_ideal", "", "cells within 5 % of the ideal (linear) chirp's")
# ---------------------------------------------------------------- GEO target (seed 001)
_D("snr_single", "", "SNR of one sub-image (eta Ns / (1 + eta Ns))", True)
_D("snr_stack", "", "SNR of the incoherent stack of every sub-image", True)
_D("snr_stack_{}", "", "SNR of the stack of the first n sub-images")
_D("stack_count", "", "sub-images stacked")
_D("stack_coherent", "", "the coherent stack was formed (flag)")
_D("stack_model_3d", "", "the stacked target is a 3-D model (flag)")
_D("snr_stack_coherent", "", "SNR of the coherent stack")
_D("snr_stack_coherent_over_incoherent", "", "coherent stack's SNR over the incoherent stack's")
_D("phase_offsets_std_rad", "rad", "spread of the phase offsets between sub-images of the coherent stack")
_D("irw_azimuth_{}_m", "m", "azimuth IRW of the coherent stack of n sub-images", "irw_azimuth_{}_theory_m")
_D("subimages_in_collection", "", "sub-images the collection holds")
_D("computed_subimages", "", "sub-images formed")
_D("subaperture_length_m", "m", "length of a sub-aperture")
_D("closest_distance_m", "m", "closest approach to the target")
_D("collection_span_m", "m", "track length of the collection")
_D("relative_speed_m_s", "m/s", "speed relative to the target")
_D("max_squint_within_1p1_deg", "deg", "largest squint whose azimuth resolution stays within 1.1 x broadside's")
_D("resolution_azimuth_squint_{}_m", "m", "azimuth IRW of a sub-image at that squint (deg)",
   "resolution_azimuth_squint_{}_theory_m")
# ---------------------------------------------------------------- down-looking SAL (seeds 000, 003)
_D("fringe_modulation_point", "", "fringe modulation of a point's interferogram", True)
_D("fringe_modulation_point_paper_order", "", "the same in the paper's order of the terms")
_D("fringe_period_m", "m", "fringe period in the image", "fringe_period_theory_m")
_D("fringe_phase_rad", "rad", "interferometric phase at the point")
_D("max_change_over_peak", "", "largest image change over the undisturbed peak")
_D("ground_fringe_phase_rms_rad", "rad", "RMS fringe phase of the flat ground")
_D("ground_fringe_phase_span_rad", "rad", "span of the fringe phase of the flat ground")
_D("height_rms_m", "m", "RMS height of the terrain")
_D("height_max_m", "m", "highest point of the terrain")
_D("height_recovered_rms_m", "m", "RMS of the height recovered from the fringes")
_D("height_error_rms_m", "m", "RMS error of the recovered height")
_D("height_error_over_height_rms", "", "that error over the terrain's RMS height")
_D("image_shift_per_height_theory", "", "image shift per metre of height (theory)")
_D("look_angle_deg", "deg", "look angle of the terrain experiment")
_D("phase_per_height_rad_per_m", "rad/m", "fringe phase gained per metre of height, measured")
_D("phase_per_height_model_rad_per_m", "rad/m", "the same in the paper's projection picture")
_D("residual_height_correlation", "", "correlation of the phase residual with the height")
_D("residual_phase_rms_rad", "rad", "RMS of the phase residual")
