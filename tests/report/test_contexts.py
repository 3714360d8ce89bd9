"""The seed pages' tables: Table 3 of seed 002 cell by cell against the published ratios."""
import numpy as np

from salkit import tolerances as tol
from salkit.papers import published
from salkit.report.contexts import table3_cells


def test_table3_cells_against_the_paper():
    t3 = published()["seed002"]["table3"]
    r2 = sorted(t3["rows"])[:2]
    r1 = t3["r1"][:2]
    shape = (len(r2), len(r1))
    ideal = np.full(shape, 0.01)
    irws = {"ideal": ideal, "paper": ideal * 2.0, "deskew": ideal * (1 + 0.5 * tol.CHIRP_IRW_OF_IDEAL),
            "resample": ideal}
    grids = {m: np.full(shape, 7.0) for m in ("paper", "deskew", "resample")}
    cells = table3_cells((r2, r1, grids, irws))
    assert len(cells) == shape[0] * shape[1]
    c = cells[0]
    assert c["published"] == t3["rows"][r2[0]][0]
    assert c["published_ok"] == (c["published"] >= t3["failure_below"])
    assert c["paper_ok"] is False and c["deskew_ok"] is True and c["resample_ok"] is True
    assert c["paper_irw_over_ideal"] == 2.0 and c["resample_ratio"] == 7.0
