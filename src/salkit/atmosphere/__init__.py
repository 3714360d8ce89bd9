"""Atmospheric turbulence: Cn^2 and r0, phase screens, structure functions."""
from .screens import phase_screens, structure_function_estimate
from .turbulence import (combine_r0, cn2_from_r0, max_layer_spacing, phase_variance, psd, r0_from_cn2,
                         r0_path, rytov_variance, structure_function, turbulence_class)

__all__ = ["combine_r0", "cn2_from_r0", "max_layer_spacing", "phase_screens", "phase_variance", "psd",
           "r0_from_cn2", "r0_path", "rytov_variance", "structure_function", "structure_function_estimate",
           "turbulence_class"]
