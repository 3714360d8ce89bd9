"""Figures a person can look at. Only the interface layers (cli, report, systems) call these.

Modules: :mod:`~salkit.plot.canvas` (matplotlib on Agg, atomic PNG saves), :mod:`~salkit.plot.images`
(images, cuts, raw data), :mod:`~salkit.plot.turbulence` (seed 004), :mod:`~salkit.plot.studies`
(seed 002), :mod:`~salkit.plot.spaceborne` (seed 001), :mod:`~salkit.plot.downlooking` (seeds 000/003).
"""
from .canvas import PREVIEW_PIXELS, peak_magnitude, preview_step
from .images import (cuts, image_db, image_grid_figure, ipr_classes_figure, model_view_figure, range_profiles_figure,
                     raw_phase_history)
from .spaceborne import coherent_stack_figure, resolution_squint_figure, spaceborne_figures, trajectory_figure
from .studies import metric_theory, sweep_figure, sweep_heatmaps
from .turbulence import autofocus_history, pga_steps_figure, screen_image, screens_figure, structure_function_figure

__all__ = ["PREVIEW_PIXELS", "peak_magnitude", "preview_step", "autofocus_history", "coherent_stack_figure", "cuts", "image_db", "image_grid_figure", "ipr_classes_figure",
           "model_view_figure", "pga_steps_figure", "range_profiles_figure", "raw_phase_history", "resolution_squint_figure",
           "screen_image", "screens_figure", "spaceborne_figures", "structure_function_figure", "sweep_heatmaps",
           "metric_theory", "sweep_figure",
           "trajectory_figure"]
