"""salkit: synthetic aperture ladar simulation, image formation and metrics.

The pipeline has one calling convention per stage::

    scenario = salkit.load_scenario("examples/spotlight_points.yaml")
    raw = salkit.simulate(scenario)              # xarray.Dataset, dechirped phase history
    image = salkit.focus(raw, scenario.processing)  # xarray.Dataset, complex image
    metrics = salkit.measure(image, truth=salkit.truth_positions(scenario))
"""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("salkit")
except PackageNotFoundError:  # pragma: no cover - source tree without install
    __version__ = "0.0.0"

from .errors import SalkitError, ScenarioError, SamplingError, DataFileError  # noqa: E402
from .params import Scenario, load_scenario  # noqa: E402
from . import focus, simulate  # noqa: E402  callable subpackages: salkit.simulate(sc), salkit.focus(raw)
from .focus import range_compress  # noqa: E402
from .metrics import measure  # noqa: E402
from .geometry import truth_positions  # noqa: E402

__all__ = [
    "__version__", "SalkitError", "ScenarioError", "SamplingError", "DataFileError",
    "Scenario", "load_scenario", "simulate", "focus", "range_compress", "measure",
    "truth_positions",
]
