"""Scenario parameter objects and YAML loading."""
from .models import (Atmosphere, ExtendedScene, Grid, Noise, PhaseError, Platform, PointTarget, Processing, Receiver,
                     AnyScenario, DownlookingScenario, Scenario, Scene, Waveform)
from .scenario import apply_overrides, dump_scenario, load_scenario, parse_scenario, stored_scenario

__all__ = ["Atmosphere", "ExtendedScene", "Grid", "Noise", "PhaseError", "Platform", "PointTarget", "Processing", "Receiver",
           "AnyScenario", "DownlookingScenario", "Scenario", "Scene", "Waveform", "apply_overrides", "dump_scenario", "load_scenario",
           "parse_scenario", "stored_scenario"]
