"""The index page: headline figures against theory with pass/fail, per kind of run."""
import re

from salkit.report.index import headline, passed, write_index


def test_headline_of_a_plain_run_judges_irw_and_pslr():
    m = {"irw_range_m": 0.0180, "irw_range_theory_m": 0.0178, "irw_azimuth_m": 0.0177, "irw_azimuth_theory_m": 0.0177,
         "pslr_range_db": -13.26, "pslr_range_theory_db": -13.26}
    items = headline(m)
    assert [i["ok"] for i in items] == [True, True, True] and passed(items) is True
    m["irw_range_m"] = 0.0190  # 6.7 % wide: outside the 3 % tolerance
    assert passed(headline(m)) is False


def test_target_in_speckle_is_judged_only_on_what_theory_predicts():
    """A target in a speckled scene (the shipped stripmap example: -7.4 dB 'PSLR', the brightest
    speckle beside it): no PSLR headline, so its card is within tolerance on its IRWs; the report's
    table keeps the row, not judged, saying why."""
    from salkit.report.judge import comparison_rows
    m = {"irw_range_m": 0.0180, "irw_range_theory_m": 0.0180, "pslr_range_db": -7.4, "pslr_range_theory_db": -13.26,
         "image_snr": 3.0, "image_snr_theory": 3.0}
    assert not [i for i in headline(m) if "PSLR" in i["label"]] and passed(headline(m)) is True
    m.pop("image_snr")
    m["extended_scene"] = 1  # a noiseless scene: the same
    assert not [i for i in headline(m) if "PSLR" in i["label"]]
    row = [r for r in comparison_rows(m) if r["name"].startswith("PSLR range")][0]
    assert row["ok"] is None and "speckle" in row["tol"]


def test_stack_judged_by_its_gain_not_by_eq15_on_a_shaped_target():
    m = {"snr_single": 0.275, "snr_single_theory": 0.333, "snr_stack": 2.30, "snr_stack_theory": 2.67,
         "stack_count": 64}
    items = headline(m)
    assert items[0]["ok"] is None  # eq 15 is for a uniform area
    assert items[1]["ok"] is True  # 2.30 / 0.275 = 8.4, sqrt(64) = 8: within 10 %


def test_write_index_links_every_run(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "image.png").write_bytes(b"png")
    runs = [{"name": "a", "description": "first", "seconds": 1.5,
             "metrics": {"irw_range_m": 0.018, "irw_range_theory_m": 0.018}},
            {"name": "b", "description": "second", "seconds": 2.0,
             "metrics": {"irw_range_m": 0.030, "irw_range_theory_m": 0.018}}]
    html = write_index(tmp_path, runs).read_text()
    assert 'href="a/report.html"' in html and 'src="a/image.png"' in html and 'href="b/report.html"' in html
    assert re.search(r'class="card pass"', html) and re.search(r'class="card fail"', html)


def test_every_card_state_has_a_colour_and_a_legend_entry(tmp_path):
    """Within, outside and nothing judged: each card state has its own class, the legend names every
    state, the summary line names the cards that are not within."""
    from markupsafe import escape as html_escape

    from salkit.report.judge import VERDICTS
    runs = [{"name": "good", "description": "", "seconds": 1.0,
             "metrics": {"irw_range_m": 0.018, "irw_range_theory_m": 0.018}},
            {"name": "wide", "description": "", "seconds": 1.0,
             "metrics": {"irw_range_m": 0.030, "irw_range_theory_m": 0.018}},
            {"name": "unjudged", "description": "", "seconds": 1.0,
             "metrics": {"snr_single": 0.3, "snr_single_theory": 0.33, "snr_stack": 1.0}}]
    html = write_index(tmp_path, runs).read_text()
    legend = re.search(r'<p class="legend".*?</p>', html, re.S).group(0)
    for v in VERDICTS.values():
        assert f'class="card {v["css"]}"' in html
        assert f'key {v["css"]}' in legend and str(html_escape(v["legend"])) in legend
    summary = html.split('<p class="legend"')[0]
    assert "wide" in summary and "unjudged" in summary
