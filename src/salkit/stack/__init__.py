"""Sub-images and their stacks (seed 001): one sub-aperture's image on the common target grid,
incoherent stacks on Dask (checkpointed in Zarr, resumable), coherent stacks with phase alignment.

Modules: :mod:`~salkit.stack.subapertures` (squints, the GEO base scenario, one sub-aperture's
scenario and complex sub-image) and :mod:`~salkit.stack.stacking` (incoherent and coherent stacks,
the Dask run with its Zarr checkpoint, the memory a stack needs, the coherent resolution study).
"""
from .stacking import (coherent_resolution, coherent_stack, incoherent_stack, run_stack, stack,
                       stack_memory_estimate)
from .subapertures import geo_base, nearest_squints, point_target, squint_of, subaperture, subimage, uncorrect

__all__ = ["coherent_resolution", "coherent_stack", "geo_base", "incoherent_stack", "nearest_squints",
           "point_target", "run_stack", "squint_of", "stack", "stack_memory_estimate", "subaperture", "subimage",
           "uncorrect"]
