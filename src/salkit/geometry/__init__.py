"""Trajectories, beam pointing, image planes and the sampling checks (all float64)."""
from .collection import Collection, ImagePlane, beam_gain_table, build_collection, image_plane, truth_positions
from .sampling import SamplingReport, check_sampling, resolution_theory

__all__ = ["Collection", "ImagePlane", "beam_gain_table", "build_collection", "image_plane",
           "resolution_theory", "truth_positions", "SamplingReport", "check_sampling"]
