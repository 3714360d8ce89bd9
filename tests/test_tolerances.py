"""The acceptance tolerances colour the report's rows exactly at their boundaries."""
import pytest

from salkit import tolerances as tol
from salkit.report import comparison_rows


def _row(m, name):
    return next(r for r in comparison_rows(m) if r["name"].startswith(name))


@pytest.mark.parametrize("ratio,ok", [(1 + 0.99 * tol.IRW_RATIO, True), (1 + 1.01 * tol.IRW_RATIO, False)])
def test_irw_ratio_boundary(ratio, ok):
    assert _row({"irw_range_m": ratio * 0.02, "irw_range_theory_m": 0.02}, "IRW range")["ok"] is ok


@pytest.mark.parametrize("err,ok", [(0.99 * tol.PEAK_PHASE_RAD, True), (1.01 * tol.PEAK_PHASE_RAD, False)])
def test_peak_phase_boundary(err, ok):
    assert _row({"peak_phase_error_rad": err}, "peak phase")["ok"] is ok


def test_values_are_sane():
    assert 0 < tol.IRW_RATIO < 0.1 and 0 < tol.PSLR_DB <= 1 and tol.GRID_SPACING_OF_RESOLUTION > 1
