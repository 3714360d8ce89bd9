"""``salkit focus`` on bad files: exit 2, one line, the file named."""


import pytest

from .conftest import salkit


def test_bad_files_exit_2(tmp_path, scen):
    raw = tmp_path / "raw.nc"
    salkit("simulate", scen, "--out", raw)
    t = tmp_path / "t.nc"
    t.write_bytes(raw.read_bytes()[:2000])
    import numpy as np
    from salkit.io import read_raw, write_dataset
    bad = read_raw(raw)
    bad["signal"].values[0, 0] = np.nan
    nan_file = write_dataset(bad, tmp_path / "nan.nc")
    r = salkit("focus", nan_file, "--out", tmp_path / "y")
    assert r.returncode == 2 and "non-finite" in r.stderr and "Traceback" not in r.stderr
    for args in (["focus", t, "--out", tmp_path / "x"], ["focus", tmp_path / "none.nc", "--out", tmp_path / "x"],
                 ["focus", raw, "--algorithm", "magic", "--out", tmp_path / "x"], ["run", tmp_path / "no.yaml", "--out", tmp_path / "x"]):
        r = salkit(*args)
        assert r.returncode == 2, args
        assert "Traceback" not in r.stderr


def test_focus_under_a_memory_limit_runs_in_tiles(tmp_path, scen):
    """--memory-limit: the job too big for it runs in tiles and pulse blocks read from the file (a
    note says how), the image equal to the untiled one, also with the tiles on 2 Dask workers; a
    limit one tile cannot fit: exit 2, the memory and the budget named, no folder."""
    import numpy as np
    from salkit.io import open_dataset
    raw = tmp_path / "raw.nc"
    salkit("simulate", scen, "--out", raw)
    r = salkit("focus", raw, "--out", tmp_path / "whole", "--algorithm", "bp")
    assert r.returncode == 0, r.stderr
    # 3 MiB: under the 3.6 MiB the job needs whole, over the 2.45 MiB of one tile and pulse block (one
    # kernel call's 6x range profiles, 0.6 MiB, are in every tile's need)
    r = salkit("focus", raw, "--out", tmp_path / "tiled", "--algorithm", "bp", "--memory-limit", "3MiB")
    assert r.returncode == 0, r.stderr
    assert "note: focusing bp in" in r.stderr and "tiles" in r.stderr
    a, b = open_dataset(tmp_path / "whole" / "image.nc"), open_dataset(tmp_path / "tiled" / "image.nc")
    assert b.attrs["pulse_block"] < a.sizes["pulse"] and b.attrs["tiles"] >= 1
    np.testing.assert_array_equal(a["image"].values, b["image"].values)
    r = salkit("focus", raw, "--out", tmp_path / "no", "--algorithm", "bp", "--memory-limit", "64KiB")
    assert r.returncode == 2 and "one tile of" in r.stderr and "available (the budget)" in r.stderr
    assert not (tmp_path / "no").exists() and "Traceback" not in r.stderr
    r = salkit("focus", raw, "--out", tmp_path / "no", "--memory-limit", "lots")
    assert r.returncode == 2 and "--memory-limit" in r.stderr
    # the tiles on a local Dask cluster: each worker reads its pulse blocks from the file; the same image
    # (5 MiB: two tiles at once with pulse blocks need 4.2 MiB, with all the pulses 6.7 MiB)
    r = salkit("focus", raw, "--out", tmp_path / "dask", "--algorithm", "bp", "--memory-limit", "5MiB",
               "--workers", "2")
    assert r.returncode == 0, r.stderr
    c = open_dataset(tmp_path / "dask" / "image.nc")
    assert c.attrs["tiles"] >= 4 and c.attrs["pulse_block"] < a.sizes["pulse"]
    np.testing.assert_array_equal(a["image"].values, c["image"].values)
    for args, needle in ((["--workers", "0"], "--workers"), (["--scheduler", "foo"], "tcp://HOST:PORT")):
        r = salkit("focus", raw, "--out", tmp_path / "no", *args)
        assert r.returncode == 2 and needle in r.stderr and not (tmp_path / "no").exists()


def test_focus_an_image_larger_than_its_budget_into_a_chunked_file(tmp_path, scen):
    """An image that cannot be held within --memory-limit is formed tile by tile into the run's
    image.nc (chunked), equal to the image formed in memory; measured on the window around its
    brightest pixel, drawn from every k-th pixel; info and verify read the folder; autofocus,
    which needs the whole image, is refused (exit 2, no folder)."""
    import json

    import numpy as np
    from salkit.io import describe, open_dataset
    raw = tmp_path / "raw.nc"
    salkit("simulate", scen, "--out", raw)
    grid = ["--nx", "512", "--ny", "512", "--dx", "0.015", "--dy", "0.015", "--algorithm", "bp"]
    assert salkit("focus", raw, "--out", tmp_path / "mem", *grid).returncode == 0
    # 3 MiB: the 512^2 image is not held (held, tiles of 64 x 128 would need 3.45 MiB), tiles of
    # 128 x 256 written (2.7 MiB)
    r = salkit("focus", raw, "--out", tmp_path / "big", *grid, "--memory-limit", "3MiB")
    assert r.returncode == 0, r.stderr
    a, b = open_dataset(tmp_path / "mem" / "image.nc"), open_dataset(tmp_path / "big" / "image.nc", lazy=True)
    assert b["image"].encoding["chunksizes"] == (min(b.attrs["tile_nx"], 1024), min(b.attrs["tile_ny"], 1024))
    assert b.attrs["tiles"] > 1
    np.testing.assert_array_equal(a["image"].values, b["image"].values)
    m = json.loads((tmp_path / "big" / "metrics.json").read_text())
    ma = json.loads((tmp_path / "mem" / "metrics.json").read_text())
    assert m["image_out_of_core"] == 1
    for k in ("irw_range_m", "irw_azimuth_m", "peak_amplitude", "peak_range_m", "entropy", "contrast"):
        assert m[k] == pytest.approx(ma[k], rel=1e-6, abs=1e-9), k
    for k in ("pslr_range_db", "pslr_azimuth_db", "islr_range_db", "islr_azimuth_db", "peak_phase_rad"):
        assert m[k] == pytest.approx(ma[k], abs=1e-6), k  # the same window, the whole image's entropy
    assert (tmp_path / "big" / "image.png").is_file() and (tmp_path / "big" / "report.html").is_file()
    assert describe(tmp_path / "big" / "image.nc")["image_chunks"] == list(b["image"].encoding["chunksizes"])
    assert salkit("verify", tmp_path / "big").returncode == 0
    r = salkit("focus", raw, "--out", tmp_path / "af", *grid, "--memory-limit", "3MiB", "--autofocus", "pga")
    assert r.returncode == 2 and "--autofocus" in r.stderr and not (tmp_path / "af").exists()


def test_focus_range_upsample(tmp_path, scen):
    """--range-upsample sets backprojection's profile upsampling (the image records it); outside
    2..64 or not an integer: exit 2 naming the option, no folder."""
    from salkit.io import open_dataset
    raw = tmp_path / "raw.nc"
    salkit("simulate", scen, "--out", raw)
    r = salkit("focus", raw, "--out", tmp_path / "f6", "--algorithm", "bp_fitted", "--range-upsample", "6")
    assert r.returncode == 0, r.stderr
    assert open_dataset(tmp_path / "f6" / "image.nc").attrs["range_upsample"] == 6
    for bad in ("1", "100", "six"):
        r = salkit("focus", raw, "--out", tmp_path / "no", "--range-upsample", bad)
        assert r.returncode == 2 and "--range-upsample" in r.stderr and "Traceback" not in r.stderr, r.stderr
        assert not (tmp_path / "no").exists()
