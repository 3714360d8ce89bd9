"""Autofocus: phase gradient (PGA, three kernels) and minimum entropy on formed images, and the
per-pulse (data-domain) autofocus on phase histories.

``autofocus(image, method)`` removes the image's deterministic phase (see docs/data-format.md) so
that the azimuth transform is the aperture domain, estimates and removes the azimuth phase error,
puts the deterministic phase back and returns the image with its history. ``pulse_focus(raw, form)``
estimates one phase per pulse by backprojection sharpness and forms the image of the corrected data
with the former it is given.

Modules: :mod:`~salkit.autofocus.image` (``autofocus``), :mod:`~salkit.autofocus.pga` (PGA, minimum
entropy), :mod:`~salkit.autofocus.pulses` (per-pulse autofocus), :mod:`~salkit.autofocus.sharpness`.
"""
from .image import IMAGE_METHODS, METHODS, autofocus, history_metrics
from .pga import KERNELS, AutofocusResult, estimate_phase, min_entropy, pga
from .pulses import pulse_autofocus, pulse_correct, pulse_focus, pulse_metrics
from .sharpness import PulseAutofocusResult, pulse_sharpness

__all__ = ["AutofocusResult", "IMAGE_METHODS", "KERNELS", "METHODS", "PulseAutofocusResult", "autofocus",
           "estimate_phase", "history_metrics", "min_entropy", "pga", "pulse_autofocus", "pulse_correct",
           "pulse_focus", "pulse_metrics", "pulse_sharpness"]
