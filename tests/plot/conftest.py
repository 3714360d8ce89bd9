"""A small focused image for the figure tests (module-scoped: simulated once per module)."""
import pytest

from salkit import focus, simulate
from salkit.params import parse_scenario

from ..conftest import SPOT


@pytest.fixture(scope="module")
def small_image():
    sc = parse_scenario(SPOT)
    return focus(simulate(sc), sc.processing)
