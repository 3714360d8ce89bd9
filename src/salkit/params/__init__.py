"""Scenario parameter objects and YAML loading."""
from .models import (RelativeOrbit, Atmosphere, ExtendedScene, Grid, Noise, PhaseError, Platform, PointTarget, Processing, Receiver,
                     AnyScenario, DownlookingScenario, Scenario, Scene, Waveform)
from .scenario import (apply_overrides, dump_scenario, example_path, examples_dir, load_scenario, parse_scenario,
                       require_scenario, stored_scenario)

__all__ = ["example_path", "examples_dir", "RelativeOrbit", "Atmosphere", "ExtendedScene", "Grid", "Noise", "PhaseError", "Platform", "PointTarget", "Processing", "Receiver",
           "AnyScenario", "DownlookingScenario", "Scenario", "Scene", "Waveform", "apply_overrides", "dump_scenario", "load_scenario",
           "parse_scenario", "require_scenario", "stored_scenario"]
