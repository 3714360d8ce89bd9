"""Image formation: one entry point, ``focus(raw, processing) -> image``.

``focus`` dispatches on the kind of the data (:data:`PROCESSORS`: SAL raw data and phase
histories, down-looking SAL raw data); SAL images are formed by the registered formers
(:data:`FORMERS`: ``bp`` backprojection, ``pfa`` polar format, ``omegak`` wavenumber domain,
``ffbp`` fast factorised backprojection, ``exact`` the float64 matched filter), which share one
signature and one normalisation (:mod:`salkit.focus.formers`). The package is callable:
``salkit.focus(raw)`` is ``salkit.focus.focus(raw)``.

Modules: :mod:`~salkit.focus.pipeline` (``focus``, memory estimates, the image dataset),
:mod:`~salkit.focus.rangecomp` (range compression), :mod:`~salkit.focus.phasehistory`,
:mod:`~salkit.focus.formers` (the registry) and one module per former, :mod:`~salkit.focus.tiles`
(image formation in tiles and pulse blocks under a memory budget).
"""
from .formers import FORMERS, ImageGrid, ImageResult, get_former, register_former
from .phasehistory import PhaseHistory, default_grid, phase_history, theory_resolution
from .pipeline import (HIGH_ACCURACY_UPSAMPLE, PROCESSORS, add_collection_geometry, focus, focus_sal, focus_to_file,
                       form_image, grid_of, image_fits, memory_budget, memory_estimate, run_memory_estimate)
from .rangecomp import range_compress
from .._callable import make_callable as _make_callable

__all__ = ["FORMERS", "HIGH_ACCURACY_UPSAMPLE", "ImageGrid", "ImageResult", "PROCESSORS", "PhaseHistory",
           "add_collection_geometry", "default_grid", "focus", "focus_sal", "focus_to_file", "form_image", "get_former", "grid_of", "image_fits",
           "memory_budget", "memory_estimate", "phase_history", "range_compress", "register_former", "run_memory_estimate",
           "theory_resolution"]

_make_callable(__name__, "focus")
