"""The former declarations: one signature, one normalisation, declared once and read everywhere;
a former declared in this file alone works through ``salkit.focus``, a scenario and the command
line (the recipe of docs/architecture.md)."""
import json
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from salkit import simulate
from salkit.errors import ResourceError, ScenarioError
from salkit.focus import ImageGrid, focus, get_former, phase_history, register_former
from salkit.focus.bp import backprojection_former, bp_memory
from salkit.focus.formers import Accuracy, former_help, former_table
from salkit.focus.tiles import memory_estimate, plan_tiling
from salkit.geometry.sampling import check_sampling
from salkit.io import open_dataset, write_dataset
from salkit.params import dump_scenario, parse_scenario
from salkit.registry import FORMERS
from salkit.signals.windows import Window

from ..conftest import SPOT, STRIP, merge

README = Path(__file__).resolve().parents[2] / "README.md"


def _declaration(**over):
    d = dict(summary="test former", modes=("spotlight",), tracks="any", phase_reference="aperture_centre",
             tiles=True, tile_overlap=0, blocks=None, memory=bp_memory,
             accuracy={"standard": Accuracy("x", None), "high": Accuracy("x", None)})
    d.update(over)
    return d


@pytest.fixture
def bp_nearest():
    """The issue's example: backprojection with nearest-neighbour profiles, declared here alone."""
    form, blocks = backprojection_former("nearest")
    register_former("bp_nearest", **_declaration(
        summary="backprojection, profiles read at the nearest bin", modes=("spotlight", "stripmap"), blocks=blocks,
        accuracy={"standard": Accuracy("16x profiles", None), "high": Accuracy("32x profiles", None)}))(form)
    yield form
    FORMERS.remove("bp_nearest")


def test_the_built_in_formers_are_declared():
    assert set(FORMERS.names()) >= {"bp", "ffbp", "pfa", "omegak", "exact"}
    assert FORMERS["omegak"].tracks == "straight" and FORMERS["omegak"].phase_reference == "track"
    assert [n for n, s in FORMERS.items() if s.blocks is not None] == ["bp", "bp_cubic", "bp_fitted", "ffbp"]  # module order


def test_unknown_names_are_refused_with_the_nearest():
    with pytest.raises(ScenarioError, match=r"processing.algorithm = 'fbp'.*did you mean 'ffbp'"):
        get_former("fbp")
    with pytest.raises(ValueError, match="already declared"):
        register_former("bp", **_declaration())(lambda *a, **k: None)


def test_an_unknown_or_undeclared_property_is_an_error():
    with pytest.raises(TypeError, match=r"'tile_overlp' is not a property.*did you mean 'tile_overlap'"):
        register_former("t1", **_declaration(tile_overlp=3))(lambda *a, **k: None)
    d = _declaration()
    del d["memory"]
    with pytest.raises(TypeError, match="undeclared memory"):
        register_former("t2", **d)(lambda *a, **k: None)
    with pytest.raises(ValueError, match="accuracy must map each of"):
        register_former("t3", **_declaration(accuracy={"standard": Accuracy("x", None)}))(lambda *a, **k: None)
    with pytest.raises(ValueError, match="modes"):
        register_former("t4", **_declaration(modes=("circular",)))(lambda *a, **k: None)
    with pytest.raises(ValueError, match="needs tiles=True"):
        register_former("t5", **_declaration(tiles=False, tile_overlap=4))(lambda *a, **k: None)
    for bad in ({"standard": 6}, {"standard": 1, "high": 8}, {"standard": 6, "high": 65}, {"standard": 6.0, "high": 8}):
        with pytest.raises(ValueError, match="upsample .* must map each of .* to an int in 2..64"):
            register_former("t6", **_declaration(upsample=bad))(lambda *a, **k: None)
    with pytest.raises(ValueError, match="support 'disc' must be one of"):
        register_former("t7", **_declaration(support="disc"))(lambda *a, **k: None)
    assert not {"t1", "t2", "t3", "t4", "t5", "t6", "t7"} & set(FORMERS.names())
    assert FORMERS["pfa"].support == "rectangle" and FORMERS["bp"].support == FORMERS["ffbp"].support == "collection"


def test_each_former_declares_its_upsampling_and_the_pipeline_reads_it():
    """bp forms at 6x (8x at high accuracy), the others at 16x (32x): the declaration is what the
    pipeline and the memory estimate read when nothing overrides it."""
    from salkit.focus.pipeline import range_upsample
    assert dict(FORMERS["bp"].upsample) == {"standard": 6, "high": 8}
    assert dict(FORMERS["bp_fitted"].upsample) == dict(FORMERS["ffbp"].upsample) == {"standard": 16, "high": 32}
    for name, spec in FORMERS.items():
        assert range_upsample(None, algorithm=name) == spec.upsample["standard"]
        assert range_upsample(None, "high", algorithm=name) == spec.upsample["high"]
    P, N = 300, 400
    assert memory_estimate(P, N, 64, 64, "bp")[0] == memory_estimate(P, N, 64, 64, "bp", upsample=6)[0]
    assert memory_estimate(P, N, 64, 64, "bp")[0] < memory_estimate(P, N, 64, 64, "bp", upsample=16)[0]


def test_the_readme_table_and_the_help_are_the_declarations():
    text = README.read_text()
    m = re.search(r"<!-- generated:formers -->\n(.*?)<!-- /generated:formers -->", text, re.S)
    assert m, "README has no generated:formers block"
    assert m.group(1) == former_table(), "README's table of formers differs from the declarations: run make docs-figures"
    for name in FORMERS.names():
        assert f"{name}: {FORMERS[name].summary}" in former_help()


def test_tiling_reads_the_declarations():
    # a former that does not tile is refused with the ones that do
    need = memory_estimate(512, 512, 300, 300, "pfa")[0]
    with pytest.raises(ResourceError, match="pfa cannot run in tiles: use --algorithm bp or bp_cubic or bp_fitted or ffbp"):
        plan_tiling(512, 512, 300, 300, "pfa", need / 4)
    # the declared overlap of ffbp's tiles enters the estimate of a tile
    t = plan_tiling(512, 512, 300, 300, "ffbp", memory_estimate(512, 512, 300, 300, "ffbp")[0] / 3)
    assert t.tiled
    with pytest.raises(ScenarioError, match="is not a declared image former"):
        memory_estimate(10, 10, 10, 10, "nope")


@pytest.mark.parametrize("alg,base", [("bp", SPOT), ("pfa", SPOT), ("bp", STRIP), ("omegak", STRIP)])
def test_every_former_normalises_a_unit_point_to_one(alg, base):
    sc = parse_scenario(merge(base, scene={"points": [{"x": 0.0, "y": 0.0}]}))
    ph = phase_history(simulate(sc))
    grid = ImageGrid.of(ph, sc.processing.grid)
    res = get_former(alg)(ph, grid, Window("none"))
    assert res.image.shape == grid.shape and res.image.dtype == np.complex64
    assert np.abs(res.image).max() == pytest.approx(1.0, abs=0.05)
    assert res.info["support_range"] > 0


def test_a_former_declared_in_a_test_works_everywhere(bp_nearest, tmp_path):
    from salkit.cli.main import app
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0.0, "y": 0.0}]},
                              processing={**SPOT["processing"], "algorithm": "bp_nearest"}))  # a scenario names it
    raw = simulate(sc)
    img = focus(raw, scenario=sc)  # through salkit.focus, from the scenario
    assert img.attrs["algorithm"] == "bp_nearest"
    ref = focus(raw, scenario=sc, algorithm="bp")
    a, b = np.abs(img["image"].values), np.abs(ref["image"].values)
    assert a.max() == pytest.approx(1.0, abs=0.05)
    assert np.unravel_index(a.argmax(), a.shape) == np.unravel_index(b.argmax(), b.shape)
    assert not np.array_equal(img["image"].values, ref["image"].values)  # its own interpolation
    # in tiles and pulse blocks, through its declared blocks: the same image
    tiled = focus(raw, scenario=sc, memory_limit=raw["signal"].nbytes + 0.9 * memory_estimate(
        *raw["signal"].shape, sc.processing.grid.nx, sc.processing.grid.ny, "bp_nearest")[0])
    assert "tiles" in tiled.attrs
    np.testing.assert_allclose(tiled["image"].values, img["image"].values, atol=2e-6)
    # the command line: accepted, listed in the help, and used
    write_dataset(raw, tmp_path / "raw.nc")
    runner = CliRunner()
    r = runner.invoke(app, ["focus", str(tmp_path / "raw.nc"), "--algorithm", "bp_nearest", "--out",
                            str(tmp_path / "out")])
    assert r.exit_code == 0, r.output
    shown = " ".join(runner.invoke(app, ["focus", "--help"]).output.split())
    assert "bp_nearest: backprojection, profiles read at the nearest bin" in shown
    r = runner.invoke(app, ["focus", str(tmp_path / "raw.nc"), "--algorithm", "bp_nearst", "--out", str(tmp_path / "o2")])
    assert r.exit_code == 2 and "did you mean 'bp_nearest'" in r.output
    # a scenario file run end to end (preflight, memory plan, workflow, report)
    (tmp_path / "s.yaml").write_text(dump_scenario(sc))
    r = runner.invoke(app, ["run", str(tmp_path / "s.yaml"), "--out", str(tmp_path / "run")])
    assert r.exit_code == 0, r.output
    assert json.loads((tmp_path / "run" / "metrics.json").read_text())["irw_range_m"] > 0
    assert open_dataset(tmp_path / "run" / "image.nc").attrs["algorithm"] == "bp_nearest"


def test_a_former_refuses_collections_it_does_not_declare():
    sc = parse_scenario(merge(STRIP, processing={**STRIP["processing"], "algorithm": "ffbp"}))
    with pytest.raises(ScenarioError, match="ffbp forms spotlight collections; this one is stripmap: use bp"):
        check_sampling(sc)
    raw = simulate(parse_scenario(STRIP))
    with pytest.raises(ScenarioError, match="exact forms spotlight collections; this one is stripmap: use bp"):
        focus(raw, algorithm="exact")
    with pytest.raises(ScenarioError, match=r"processing.algorithm = 'bpp'.*did you mean 'bp'"):
        parse_scenario(merge(SPOT, processing={**SPOT["processing"], "algorithm": "bpp"}))
