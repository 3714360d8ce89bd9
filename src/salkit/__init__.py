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

import lazy_loader as _lazy

from . import _openmp  # noqa: F401,E402  (before numba starts its threads: OpenMP's waiting policy)

from .errors import DataFileError, SalkitError, SamplingError, ScenarioError  # noqa: E402

# Everything else loads on first use (scikit-image's mechanism), so ``import salkit`` and
# ``salkit --help`` do not pay for numba, scipy.signal or matplotlib. ``salkit.focus`` and
# ``salkit.simulate`` are callable subpackages: ``salkit.simulate(sc)``, ``salkit.focus(raw)``.
__getattr__, __dir__, _ = _lazy.attach(
    __name__,
    submodules=["atmosphere", "autofocus", "focus", "geometry", "interferometry", "io", "metrics", "params",
                "plot", "report", "resources", "signals", "simulate", "stack", "studies", "systems", "choices", "papers",
                "tolerances"],
    submod_attrs={"params": ["Scenario", "load_scenario", "example_path"], "focus": ["range_compress"],
                  "metrics": ["measure"], "geometry": ["truth_positions"], "systems.study": ["sweep"]},
)

__all__ = [
    "__version__", "SalkitError", "ScenarioError", "SamplingError", "DataFileError",
    "Scenario", "load_scenario", "example_path", "simulate", "focus", "range_compress", "measure",
    "truth_positions", "sweep",
]
