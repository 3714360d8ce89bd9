"""``salkit focus`` on bad files: exit 2, one line, the file named."""


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
