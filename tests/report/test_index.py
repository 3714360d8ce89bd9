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


def test_target_in_speckle_has_no_pslr_verdict():
    m = {"irw_range_m": 0.0180, "irw_range_theory_m": 0.0180, "pslr_range_db": -7.4, "pslr_range_theory_db": -13.26,
         "image_snr": 3.0}
    pslr = [i for i in headline(m) if "PSLR" in i["label"]][0]
    assert pslr["ok"] is None and "scene" in pslr["label"]
    m.pop("image_snr")
    m["extended_scene"] = 1  # a noiseless scene: the same
    assert [i for i in headline(m) if "PSLR" in i["label"]][0]["ok"] is None


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
    assert re.search(r'class="card ok"', html) and re.search(r'class="card bad"', html)
