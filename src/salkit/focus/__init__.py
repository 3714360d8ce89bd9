"""Image formation: one entry point, ``focus(raw, processing) -> image``.

``focus`` dispatches on the kind of the data (:data:`PROCESSORS`: SAL raw data and phase
histories, down-looking SAL raw data); SAL images are formed by the declared formers
(:data:`FORMERS`, :data:`salkit.registry.FORMERS`: ``bp`` and ``bp_cubic`` backprojection,
``ffbp`` fast factorised backprojection, ``pfa`` polar format, ``omegak`` wavenumber domain,
``exact`` the float64 matched filter), which share one signature and one normalisation and declare
what the rest of salkit needs to know of them (:mod:`salkit.focus.formers`). The package is
callable: ``salkit.focus(raw)`` is ``salkit.focus.focus(raw)``.

Modules: :mod:`~salkit.focus.pipeline` (``focus``, memory estimates, the image dataset),
:mod:`~salkit.focus.rangecomp` (range compression), :mod:`~salkit.focus.phasehistory`,
:mod:`~salkit.focus.formers` (the declaration) and the formers, each apart from its kernels
(:mod:`~salkit.focus.bp` over :mod:`~salkit.focus.bp_kernel` and :mod:`~salkit.focus.profiles`;
:mod:`~salkit.focus.ffbp` over :mod:`~salkit.focus.ffbp_leaves` and :mod:`~salkit.focus.ffbp_merges`),
:mod:`~salkit.focus.tiles` (image formation in tiles and pulse blocks under a memory budget).
"""
from .formers import FORMERS, Accuracy, FormerSpec, ImageGrid, ImageResult, former_spec, get_former, register_former
from .phasehistory import PhaseHistory, default_grid, phase_history, theory_resolution
from .pipeline import (PROCESSORS, add_collection_geometry, focus, focus_sal, focus_to_file, form_image, grid_of,
                       image_fits, memory_budget, memory_estimate, run_memory_estimate)
from .rangecomp import range_compress
from ..tolerances import HIGH_ACCURACY_UPSAMPLE
from .._callable import make_callable as _make_callable

__all__ = ["Accuracy", "FORMERS", "FormerSpec", "HIGH_ACCURACY_UPSAMPLE", "former_spec", "ImageGrid", "ImageResult", "PROCESSORS", "PhaseHistory",
           "add_collection_geometry", "default_grid", "focus", "focus_sal", "focus_to_file", "form_image", "get_former", "grid_of", "image_fits",
           "memory_budget", "memory_estimate", "phase_history", "range_compress", "register_former", "run_memory_estimate",
           "theory_resolution"]

_make_callable(__name__, "focus")
