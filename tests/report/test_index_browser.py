"""The demo's index page and a sweep report as a person sees them: rendered by headless Chromium
(Debian's package; the Makefile's test target installs it where it can), a screenshot taken, and the
rendered page checked: the legend names every state a card or a figure is in.

Skipped, saying why, where no Chromium can be had."""
from __future__ import annotations

import re
import shutil
import subprocess

import pytest
import yaml

from salkit.report.judge import VERDICTS

from ..conftest import SPOT, STRIP

BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def _browser() -> str:
    for name in BROWSERS:
        path = shutil.which(name)
        if path:
            return path
    pytest.skip("no headless Chromium here (make test installs Debian's chromium as root; "
                "apt-get install chromium): the rendered pages are not checked")


def _render(browser: str, page, png) -> str:
    """The DOM Chromium renders from ``page`` (a file), and a 1200 px wide screenshot into ``png``."""
    base = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            "--allow-file-access-from-files"]
    subprocess.run([*base, f"--screenshot={png}", "--window-size=1200,1600", page.as_uri()], check=True,
                   capture_output=True, timeout=120)
    r = subprocess.run([*base, "--dump-dom", page.as_uri()], check=True, capture_output=True, text=True, timeout=120)
    return r.stdout


def _legend_states(dom: str) -> set[str]:
    legend = re.search(r'<p class="legend"[^>]*>(.*?)</p>', dom, re.S)
    assert legend, "no legend on the page"
    return set(re.findall(r'class="key (\w+)"', legend.group(1)))


def test_index_and_a_sweep_report_show_a_legend_for_every_state(tmp_path):
    browser = _browser()
    from salkit.params import parse_scenario
    from salkit.report import run_scenario
    from salkit.report.index import write_index
    from salkit.report.sweeps import run_sweep
    from salkit.studies.engine import plan_of
    runs = []
    for d in (SPOT, STRIP):  # a point target (judged) and a target in a scene (IRWs judged, PSLR not)
        sc = parse_scenario(d)
        m = run_scenario(sc, tmp_path / sc.name)
        runs.append({"name": sc.name, "description": "", "seconds": 1.0, "metrics": m})
    runs.append({"name": "wide", "description": "an IRW outside tolerance", "seconds": 1.0,
                 "metrics": {"irw_range_m": 0.03, "irw_range_theory_m": 0.018}})
    runs.append({"name": "unjudged", "description": "nothing with a rule", "seconds": 1.0,
                 "metrics": {"snr_single": 0.3, "snr_single_theory": 0.33, "snr_stack": 1.0}})
    index = write_index(tmp_path, runs)
    dom = _render(browser, index, tmp_path / "index.png")
    assert (tmp_path / "index.png").stat().st_size > 10_000  # a page was drawn
    cards = set(re.findall(r'class="card (\w+)"', dom))
    figures = set(re.findall(r'<td class="(\w+)" data-verdict', dom))
    legend = _legend_states(dom)
    assert cards == {v["css"] for v in VERDICTS.values()}  # this index has a card in every state
    assert cards | figures <= legend
    # a sweep's report: its verdicts and legend
    sc = parse_scenario(SPOT)
    plan = plan_of(sc, {"waveform.bandwidth": "5e9,7.5e9"}, metrics=("irw_range_m", "pslr_range_db"))
    run_sweep(sc, plan, {}, tmp_path / "sweep", workers=0)
    dom = _render(browser, tmp_path / "sweep" / "report.html", tmp_path / "sweep.png")
    states = set(re.findall(r'data-verdict="(\w+)"', dom))
    assert states and states <= _legend_states(dom)
    with open(tmp_path / "sweep" / "scenario.yaml") as f:
        assert yaml.safe_load(f)
