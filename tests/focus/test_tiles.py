"""Image formation under a memory budget: the plan (tiles cover the grid once, each within the
budget; refusals name the memory and the budget), tiled backprojection equal to the untiled image
(-120 dB: pulse blocks read from a lazily opened file included), tiled FFBP within FFBP's accuracy
of direct backprojection with no seam at the tile borders."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.errors import ResourceError
from salkit.focus import memory_estimate
from salkit.focus import phase_history
from salkit.focus.formers import ImageGrid
from salkit.focus.tiles import Geometry, plan_tiling
from salkit.io import open_dataset, write_dataset
from salkit.params import parse_scenario

from ..conftest import SPOT, merge


def _db(err, ref):
    return 10 * np.log10(max(np.sum(np.abs(err) ** 2), 1e-300) / np.sum(np.abs(ref) ** 2))


@pytest.fixture(scope="module")
def scene():
    """60 points spread over a 256 x 192 grid: errors everywhere, not only at one target."""
    rng = np.random.default_rng(3)
    pts = [{"x": float(x), "y": float(y), "amplitude": 1.0, "phase": float(f)} for x, y, f in
           zip(rng.uniform(-1.8, 1.8, 60), rng.uniform(-1.4, 1.4, 60), rng.uniform(-3, 3, 60))]
    sc = parse_scenario(merge(SPOT, scene={"points": pts},
                              processing={"grid": {"nx": 256, "ny": 192, "dx": 0.015, "dy": 0.015}}))
    return sc, simulate(sc)


@pytest.mark.parametrize("alg", ["bp", "ffbp"])
def test_plan_covers_the_grid_once_within_the_budget(alg):
    P, N, nx, ny = 2000, 1000, 4000, 3000  # the pixels dominate: the grid is what tiles shrink
    whole = memory_estimate(P, N, nx, ny, alg)[0]
    assert not plan_tiling(P, N, nx, ny, alg, whole).tiled
    t = plan_tiling(P, N, nx, ny, alg, whole / 2)  # the assembled image (8 bytes a pixel) counted
    assert t.tiled and 8.0 * nx * ny < t.need <= whole / 2
    t = plan_tiling(P, N, nx, ny, alg, whole / 5, hold_image=False)  # tiles written out as they finish
    assert t.tiled and t.need <= whole / 5
    cover = np.zeros((nx, ny), int)
    for i0, i1, j0, j1 in t.tiles:
        cover[i0:i1, j0:j1] += 1
    assert (cover == 1).all() and len(t.tiles) == t.n_tiles
    if alg == "bp":  # pulses too, in blocks of whole kernel calls, covering every pulse once
        t = plan_tiling(20 * P, 4 * N, 1000, 700, alg, memory_estimate(20 * P, 4 * N, 1000, 700, alg)[0] / 20)
        assert t.pulse_block < 20 * P and t.pulse_block % 32 == 0
        assert [a for a, _ in t.blocks][1:] == [b for _, b in t.blocks][:-1] and t.blocks[-1][1] == 20 * P
    assert str(t.n_tiles) in t.describe() and "budget" in t.describe()


def test_refusals_name_the_memory_and_the_budget():
    with pytest.raises(ResourceError, match=r"pfa cannot run in tiles.*bp or bp_cubic or bp_fitted or ffbp"):
        plan_tiling(4000, 3000, 1000, 700, "pfa", 2 ** 20)
    with pytest.raises(ResourceError, match=r"one tile of 32 x 32 pixels.* needs about [0-9.]+ MiB of memory.*, more "
                                            r"than the 1 MiB available"):
        plan_tiling(4000, 3000, 1000, 700, "ffbp", 2 ** 20)
    with pytest.raises(ResourceError, match=r"one tile of 32 x 32 pixels.* needs about [0-9.]+ MiB of memory \(32 MiB "
                                            r"of it the whole image, assembled in memory; `salkit focus`"):
        plan_tiling(243, 201, 2048, 2048, "bp", 16 * 2 ** 20)  # the image alone is over the budget
    with pytest.raises(ResourceError, match=r"pulses needs about [0-9.]+ MiB of memory, more than"):
        plan_tiling(243, 201, 2048, 2048, "bp", 2 ** 10, hold_image=False)  # into a file: the tile alone


def test_tiled_backprojection_equals_the_untiled_image(scene, tmp_path):
    """bp in tiles and pulse blocks, from memory and from a lazily opened file read a block at a time."""
    sc, raw = scene
    whole = focus(raw, sc.processing, algorithm="bp")
    ref = whole["image"].values
    P, N = raw["signal"].shape
    need = memory_estimate(P, N, 256, 192, "bp")[0]
    held = raw["signal"].nbytes
    t = focus(raw, sc.processing, algorithm="bp", memory_limit=held + 0.6 * need)
    assert "tiles" in t.attrs["tiling"] and (t.attrs["tiles"] > 1 or t.attrs["pulse_block"] < P)
    assert _db(t["image"].values - ref, ref) < -120
    path = write_dataset(raw, tmp_path / "raw.nc")
    lazy = open_dataset(path, lazy=True)
    assert not lazy["signal"].variable._in_memory
    b = focus(lazy, sc.processing, algorithm="bp", memory_limit=0.6 * need)
    assert b.attrs["pulse_block"] < P
    assert _db(b["image"].values - ref, ref) < -120
    np.testing.assert_array_equal(b["collection_position"].values, whole["collection_position"].values)
    assert b.attrs["resolution_azimuth"] == whole.attrs["resolution_azimuth"]


def _ffbp_need(raw, sc, **grid):
    """FFBP's whole-job estimate from the collection's geometry (what the planner weighs it by)."""
    ph = phase_history(raw)
    g = sc.processing.grid.model_copy(update=grid)
    return memory_estimate(*ph.data.shape, g.nx, g.ny, "ffbp", raw=raw.attrs.get("salkit_kind") == "raw",
                           geometry=Geometry(ph.positions, ph.freq, ImageGrid.of(ph, g)))[0]


def test_tiled_ffbp_has_no_seam(scene):
    """Against direct backprojection at high accuracy: the tiled FFBP image is as accurate as the
    whole one, and its error within 3 pixels of a tile border is no more than 1 dB further above its
    error elsewhere than the whole image's is in the same bands (the targets' sidelobes put more or
    less error in any band: 1.1 dB more in the bands of the 8-tile plan, untiled)."""
    sc, raw = scene
    ref = focus(raw, sc.processing, algorithm="bp", accuracy="high")["image"].values
    whole = focus(raw, sc.processing, algorithm="ffbp")["image"].values
    P, N = raw["signal"].shape
    t = focus(raw, sc.processing, algorithm="ffbp", memory_limit=raw["signal"].nbytes + 0.3 * _ffbp_need(raw, sc))
    tiled = t["image"].values
    assert t.attrs["tiles"] >= 4
    assert _db(whole - ref, ref) < -50 and _db(tiled - ref, ref) < _db(whole - ref, ref) + 1.0
    e = np.abs(tiled - ref) ** 2
    border = np.zeros(e.shape, bool)
    for i in range(t.attrs["tile_nx"], e.shape[0], t.attrs["tile_nx"]):
        border[i - 3:i + 3, :] = True
    for j in range(t.attrs["tile_ny"], e.shape[1], t.attrs["tile_ny"]):
        border[:, j - 3:j + 3] = True
    assert 0.05 < border.mean() < 0.5
    ew = np.abs(whole - ref) ** 2
    excess = 10 * np.log10(e[border].mean() / e[~border].mean())
    assert excess - 10 * np.log10(ew[border].mean() / ew[~border].mean()) < 1.0


def test_image_written_tile_by_tile_into_a_chunked_file(scene, tmp_path):
    """focus_to_file: the image goes tile by tile into a chunked NetCDF (the chunks are the
    tiles), equal to the image formed in memory, attributes and collection geometry included,
    opened lazily; a refusal leaves no file."""
    from salkit.focus import focus_to_file
    sc, raw = scene
    ref = focus(raw, sc.processing, algorithm="bp")
    P, N = raw["signal"].shape
    lazy = open_dataset(write_dataset(raw, tmp_path / "raw.nc"), lazy=True)
    img = focus_to_file(lazy, tmp_path / "image.nc", sc.processing, algorithm="bp",
                        memory_limit=0.45 * memory_estimate(P, N, 256, 192, "bp")[0])
    assert not img["image"].variable._in_memory and img.attrs["tiles"] > 1
    assert img["image"].encoding["chunksizes"] == (min(img.attrs["tile_nx"], 1024), min(img.attrs["tile_ny"], 1024))
    assert _db(img["image"].values - ref["image"].values, ref["image"].values) < -120
    for k in ("resolution_azimuth", "irw_range_theory", "algorithm", "salkit_kind", "support_range"):
        assert img.attrs[k] == ref.attrs[k], k
    np.testing.assert_array_equal(img["collection_position"].values, ref["collection_position"].values)
    np.testing.assert_array_equal(img["azimuth"].values, ref["azimuth"].values)
    with pytest.raises(ResourceError):
        focus_to_file(lazy, tmp_path / "no.nc", sc.processing, algorithm="bp", memory_limit=2 ** 10)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["image.nc", "raw.nc"]


try:
    from distributed import WorkerPlugin as _WorkerPlugin
except ImportError:  # pragma: no cover - dask is a dependency
    _WorkerPlugin = object


class DieOnFirstTile(_WorkerPlugin):
    """Dask worker plugin: the first worker to start a tile task dies (a marker file says it did)."""

    def __init__(self, marker):
        self.marker = str(marker)

    def setup(self, worker):
        self.worker = worker

    def transition(self, key, start, finish, **kwargs):
        import os
        from pathlib import Path
        if finish == "executing" and "_tile_task" in str(key) and not Path(self.marker).exists():
            Path(self.marker).write_text("died")
            os._exit(1)


def test_tiles_on_dask_equal_the_tiles_here_even_when_a_worker_dies(scene, tmp_path):
    """Two Dask workers: bp with each worker reading its pulse blocks from the file itself, ffbp from a
    phase history scattered to them; the images equal the ones formed in this process, though the
    first worker to start a tile is killed (Dask runs that tile again elsewhere); formed twice in a
    row from the same phase history, the same image."""
    dd = pytest.importorskip("dask.distributed")
    sc, raw = scene
    P, N = raw["signal"].shape
    lazy = open_dataset(write_dataset(raw, tmp_path / "raw.nc"), lazy=True)
    limit = 0.6 * memory_estimate(P, N, 256, 192, "bp")[0]
    here_bp = focus(lazy, sc.processing, algorithm="bp", memory_limit=limit)
    here_ffbp = focus(raw, sc.processing, algorithm="ffbp")
    marker = tmp_path / "died"
    # FFBP's kernels compiled afresh and the same kernels loaded from numba's cache differ in the last
    # bits (docs: a numba effect, not the tiles'); a first cluster compiles and caches the workers'
    # kernels, so that every worker below, the one started after the death too, loads the same code
    with dd.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cl0, \
            dd.Client(cl0) as client0:
        focus(raw, sc.processing, algorithm="ffbp", client=client0)
    with dd.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl, \
            dd.Client(cl) as client:
        client.register_plugin(DieOnFirstTile(marker))
        # two tiles in work at once on this machine's budget (a local cluster): twice the limit
        there_bp = focus(lazy, sc.processing, algorithm="bp", memory_limit=2 * limit, client=client)
        # the tiles follow the workers alive (two a worker): the one killed is back before the next image,
        # or the two FFBP images below are tiled differently (they differed at -60 dB, FFBP's accuracy)
        client.wait_for_workers(2, timeout=60)
        there_ffbp = focus(raw, sc.processing, algorithm="ffbp", client=client)
        # the same phase history again at once: its own scattered copy (an equal one shared a key
        # with the last, which Dask was releasing: "lost dependencies")
        client.wait_for_workers(2, timeout=60)
        again = focus(raw, sc.processing, algorithm="ffbp", client=client)
        assert again.attrs["tiles"] == there_ffbp.attrs["tiles"]
    assert marker.read_text() == "died"
    np.testing.assert_array_equal(again["image"].values, there_ffbp["image"].values)
    assert there_bp.attrs["pulse_block"] < P and there_bp.attrs["tiles"] >= 2 and there_ffbp.attrs["tiles"] >= 2  # two a worker
    np.testing.assert_array_equal(there_bp["image"].values, here_bp["image"].values)
    ref = here_ffbp["image"].values  # one image here; on Dask tiles (its own accuracy, no seam: above)
    assert _db(there_ffbp["image"].values - ref, ref) < -50


def test_ffbp_in_pulse_blocks_from_a_file(scene, tmp_path):
    """FFBP with its pulses in blocks read from a lazily opened file: each block's FFBP image added
    up, as accurate against direct BP as the whole FFBP image."""
    sc, raw = scene
    ref = focus(raw, sc.processing, algorithm="bp", accuracy="high")["image"].values
    whole = focus(raw, sc.processing, algorithm="ffbp")["image"].values
    P, N = raw["signal"].shape
    lazy = open_dataset(write_dataset(raw, tmp_path / "raw.nc"), lazy=True)
    b = focus(lazy, sc.processing, algorithm="ffbp", memory_limit=0.5 * _ffbp_need(raw, sc))
    assert b.attrs["pulse_block"] < P
    assert _db(b["image"].values - ref, ref) < _db(whole - ref, ref) + 1.0 < -50


def test_a_wide_arc_is_cut_by_its_geometry_not_its_sizes():
    """Over a 30-degree arc over a ground plane (one tree: wider arcs are formed in parts) FFBP's
    polar grids and range profiles hold twice what the sizes say (the range widening): the planner, given the geometry, cuts the job so that every tile and
    pulse block (not only the ones it weighs) fits the budget by FFBP's own count, where the
    sizes-only plan would have run it whole and FFBP refused it; focus() then forms it within the
    budget, as the untiled image to FFBP's accuracy."""
    from salkit.focus.ffbp import ffbp_layout, plan_parts
    from salkit.simulate.testbeds import wide_angle
    tb = wide_angle(30.0, 0.5, "ground", pulses=1024)
    pts, amp = tb.point_targets(96, count=5)
    raw = tb.dataset(pts, amp)
    ph = phase_history(raw)
    P, M = ph.data.shape
    ig = ImageGrid.of(ph, tb.grid(96))
    geo = Geometry(ph.positions, ph.freq, ig)
    assert len(plan_parts(ph.positions, ph.freq, ig)) == 1
    lay = ffbp_layout(ph.positions, ph.freq, ig)
    assert lay.widen > 1.5
    exact = memory_estimate(P, M, 96, 96, "ffbp", raw=False, geometry=geo)[0]
    sizes = memory_estimate(P, M, 96, 96, "ffbp", raw=False)[0]
    assert exact > 1.5 * sizes
    budget = 0.5 * exact
    assert not plan_tiling(P, M, 96, 96, "ffbp", budget, raw=False).tiled  # the sizes say it fits whole
    t = plan_tiling(P, M, 96, 96, "ffbp", budget, raw=False, geometry=geo)
    assert t.tiled and t.need <= budget
    worst = 0.0
    for i0, i1, j0, j1 in t.tiles:
        box = (max(0, i0 - 16), min(96, i1 + 16), max(0, j0 - 16), min(96, j1 + 16)) if t.n_tiles > 1 else (
            i0, i1, j0, j1)
        for a, b in t.blocks:
            worst = max(worst, memory_estimate(b - a, M, box[1] - box[0], box[3] - box[2], "ffbp", raw=False,
                                               geometry=geo.part(a, b, *box))[0] + 8.0 * 96 * 96)
    assert worst <= budget
    whole = focus(raw, algorithm="ffbp", grid=tb.grid(96))
    cut = focus(raw, algorithm="ffbp", grid=tb.grid(96), memory_limit=raw["signal"].nbytes + budget)
    assert cut.attrs["pulse_block"] < P or cut.attrs["tiles"] > 1
    ref = whole["image"].values
    assert _db(cut["image"].values - ref, ref) < -50
