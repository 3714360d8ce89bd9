"""The table of metrics: names resolve plainly, as theory partners, under case labels and as
families; an unknown name is refused with the nearest declared one; the docs' table is the
declarations; a metric declared here (the recipe of docs/architecture.md) is accepted by a sweep."""
import re
from pathlib import Path

import pytest

from salkit.errors import ScenarioError
from salkit.metrics.table import check_metric, declare_metric, lookup, metrics_table, undeclared
from salkit.registry import METRICS
from salkit.studies.plan import make_plan
from salkit.studies.spec import Axis
from salkit.params import parse_scenario

from ..conftest import SPOT

DOCS = Path(__file__).resolve().parents[2] / "docs" / "metrics.md"


@pytest.mark.parametrize("name,declared", [
    ("irw_range_m", "irw_range_m"), ("irw_range_theory_m", "irw_range_m"), ("medium_pga_entropy", "entropy"),
    ("A_deskew_irw_m", "irw_m"), ("snr_stack_13", "snr_stack_{}"), ("resolution_azimuth_squint_14.37_m",
                                                                      "resolution_azimuth_squint_{}_m"),
    ("resolution_azimuth_squint_5_theory_m", "resolution_azimuth_squint_{}_m"), ("sampling_prf", "sampling_{word}"),
    ("strong_pga_phase_rms_4", "phase_rms_{}"), ("image_phase_at_peak_rad", "image_phase_at_peak_rad")])
def test_names_resolve_to_their_declaration(name, declared):
    assert lookup(name).name == declared


def test_unknown_names_are_refused_with_the_nearest():
    for bad in ("bogus_rad", "snr_stack_x", "pga_entropy_"):
        assert lookup(bad) is None
    with pytest.raises(ScenarioError, match=r"--metric = 'pslr_azimth_db'.*the nearest: 'pslr_azimuth_db'"):
        check_metric("pslr_azimth_db")
    with pytest.raises(ScenarioError, match=r"the nearest: 'medium_pga_entropy'"):
        check_metric("medium_pga_entropyy")
    assert undeclared({"irw_range_m": 1.0, "nested": {"bogus_rad": 2.0}, "label": "x", "flag": True}) == ["bogus_rad"]


def test_the_two_phases_have_two_names():
    a, b = METRICS["image_phase_at_peak_rad"], METRICS["peak_phase_rad"]
    assert a.meaning != b.meaning and a.unit == b.unit == "rad"


def test_docs_table_is_the_declarations():
    m = re.search(r"<!-- generated:metrics -->\n(.*?)<!-- /generated:metrics -->", DOCS.read_text(), re.S)
    assert m and m.group(1) == metrics_table(), "docs/metrics.md is stale: run make docs-figures"


def test_the_recipe_a_metric_declared_is_accepted():
    sc = parse_scenario(SPOT)
    axes = [Axis("waveform.bandwidth", (4e9, 5e9), "list", "4e9,5e9")]
    with pytest.raises(ScenarioError, match="metrics = 'glint_count'"):
        make_plan(sc, axes, metrics=("glint_count",))
    declare_metric("glint_count", "", "bright glints in the image (a test's metric)")
    try:
        assert make_plan(sc, axes, metrics=("glint_count", "medium_glint_count")).metrics == ("glint_count",
                                                                                            "medium_glint_count")
    finally:
        METRICS.remove("glint_count")
