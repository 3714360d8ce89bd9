"""Interferometry: interferograms, phase unwrapping, fringe measurement and height models."""
from .core import (carrier_phase, fringe_period, height_from_fringe_shift, interferogram, unwrap_phase,
                   wrap)
from .height import recover_height
from .terrain import terrain_height, terrain_scatterers

__all__ = ["carrier_phase", "fringe_period", "height_from_fringe_shift", "interferogram", "recover_height", "terrain_height",
           "terrain_scatterers", "unwrap_phase", "wrap"]
