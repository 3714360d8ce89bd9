"""``salkit propagate``: the field and its scintillation against theory; ``salkit screen``'s sampling."""
import json


from .conftest import salkit


def test_propagate_writes_the_field_and_its_scintillation(tmp_path):
    import xarray as xr
    r = salkit("propagate", "--wavelength", "1.55e-6", "--cn2", "1e-14", "--distance", "1000", "--count", "4",
               "--out", tmp_path / "p")
    assert r.returncode == 0, r.stderr
    m = json.loads((tmp_path / "p" / "metrics.json").read_text())
    for k in ("rytov_variance", "scintillation_index", "scintillation_index_theory", "r0_spherical_m"):
        assert k in m
    ds = xr.open_dataset(tmp_path / "p" / "field.nc")
    assert ds["field"].dims == ("realisation", "y", "x") and ds["x"].attrs["units"] == "m"
    r = salkit("propagate", "--wave", "conical", "--wavelength", "1.55e-6", "--cn2", "1e-14", "--distance", "1000",
               "--out", tmp_path / "s")
    assert r.returncode == 2 and "--wave" in r.stderr and not (tmp_path / "s").exists()
    r = salkit("propagate", "--wavelength", "2e-6", "--cn2", "1e-13", "--distance", "50000", "--out", tmp_path / "b")
    assert r.returncode == 2 and "more than" in r.stderr and not (tmp_path / "b").exists()


def test_a_screen_sampled_coarser_than_its_r0_is_warned_with_the_numbers(tmp_path):
    """--dx 0.01 with --r0 0.001: neighbouring samples differ by 17.9 rad rms, so a field through the
    screen at that spacing aliases; it was written without a word. Below 1.24 r0 nothing is said."""
    r = salkit("screen", "--n", "32", "--dx", "0.01", "--r0", "0.001", "--out", tmp_path / "a.nc")
    assert r.returncode == 0 and (tmp_path / "a.nc").is_file()
    assert "warning: --dx = 0.01 m against --r0 = 0.001 m: neighbouring samples differ by 17.9 rad rms" in r.stderr
    assert "below 0.00124 m (1.24 r0)" in r.stderr
    r = salkit("screen", "--n", "32", "--dx", "0.012", "--r0", "0.01", "--out", tmp_path / "b.nc")
    assert r.returncode == 0 and "warning" not in r.stderr
