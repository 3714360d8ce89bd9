"""Measured against theory, judged by one set of rules: the report's comparison table and the
index page's headlines give the same verdict on the same numbers."""
import pytest

from salkit import tolerances as tol
from salkit.report.judge import comparison_rows, difference_rule, headline, in_clutter, ratio_rule


def test_comparison_rows_only_for_present_metrics():
    assert comparison_rows({}) == []
    rows = comparison_rows({"pslr_range_db": -13.2, "pslr_range_theory_db": -13.26})
    assert [r["name"] for r in rows] == ["PSLR range (dB)"] and rows[0]["ok"]


def test_rules_at_their_edges():
    assert ratio_rule(1.0 + tol.IRW_RATIO * 0.99, 1.0, tol.IRW_RATIO)[1] is True
    assert ratio_rule(1.0 + tol.IRW_RATIO * 1.01, 1.0, tol.IRW_RATIO)[1] is False
    assert difference_rule(-13.26 + 0.99 * tol.PSLR_DB, -13.26, tol.PSLR_DB)[1] is True
    assert difference_rule(-13.26 - 1.01 * tol.PSLR_DB, -13.26, tol.PSLR_DB)[1] is False
    assert difference_rule(0.0, -13.26, tol.PSLR_DB, applies=False) == (pytest.approx(13.26), None)
    assert in_clutter({"image_snr": 3.0}) and in_clutter({"extended_scene": 1}) and not in_clutter({})


@pytest.mark.parametrize("irw,pslr,scene", [(0.0179, -13.2, 0), (0.0250, -13.2, 0), (0.0179, -9.0, 0),
                                            (0.0179, -9.0, 1)])
def test_table_and_headline_agree(irw, pslr, scene):
    m = {"irw_range_m": irw, "irw_range_theory_m": 0.0178, "pslr_range_db": pslr, "pslr_range_theory_db": -13.26,
         "extended_scene": scene}
    rows = {r["name"]: r["ok"] for r in comparison_rows(m)}
    heads = {h["label"].split(" (")[0]: h["ok"] for h in headline(m)}
    assert rows["IRW range (cm)"] == heads["range IRW"]
    if scene:  # a target in a scene: not judged in the table (with the reason), no headline at all
        assert rows["PSLR range (dB)"] is None and "range PSLR" not in heads
    else:
        assert rows["PSLR range (dB)"] == heads["range PSLR"]
