# Type stub of salkit's face: ``salkit/__init__.py`` loads these names lazily (lazy_loader), so type
# checkers and editors read them here. ``salkit.focus`` and ``salkit.simulate`` are subpackages that
# can be called like their main function; the stub gives them as the functions.
from . import (atmosphere as atmosphere, autofocus as autofocus, choices as choices, geometry as geometry,
               interferometry as interferometry, io as io, metrics as metrics, papers as papers, params as params,
               plot as plot, report as report, resources as resources, signals as signals, stack as stack,
               studies as studies, systems as systems, tolerances as tolerances)
from .errors import DataFileError as DataFileError
from .errors import SalkitError as SalkitError
from .errors import SamplingError as SamplingError
from .errors import ScenarioError as ScenarioError
from .focus.pipeline import focus as focus
from .focus.rangecomp import range_compress as range_compress
from .geometry import truth_positions as truth_positions
from .metrics.measure import measure as measure
from .params import Scenario as Scenario
from .params import example_path as example_path
from .params import load_scenario as load_scenario
from .simulate.registry import simulate as simulate
from .systems.study import sweep as sweep

__version__: str
__all__: list[str]
