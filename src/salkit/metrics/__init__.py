"""Quality metrics: point-target IPR analysis against theory, entropy, contrast and SNR.

Modules: :mod:`~salkit.metrics.measure` (``measure(image)``, the image's phase model),
:mod:`~salkit.metrics.pointtarget` (IRW, PSLR, ISLR, and their theory from a collection's
K-space support, ``support_ipr``), :mod:`~salkit.metrics.image` (entropy,
contrast, noise, SNR against the truth), :mod:`~salkit.metrics.snr` (photon-limited SNR), :mod:`~salkit.metrics.window` (an image larger
than memory: the window measured and the whole image's moments, in one pass).
"""
from .image import contrast, entropy, noise_power, snr_against_truth
from .measure import image_phase_model, measure
from .pointtarget import analyse_point, ipr_1d, support_ipr
from .snr import split_snr, stack_snr
from .window import brightest_window

__all__ = ["analyse_point", "brightest_window", "contrast", "entropy", "image_phase_model", "ipr_1d", "measure", "noise_power",
           "snr_against_truth", "split_snr", "stack_snr", "support_ipr"]
