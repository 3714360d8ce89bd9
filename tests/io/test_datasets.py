"""Building salkit datasets: a raw file focuses to the same image as the data in memory; a
phase history from outside, in the documented form, focuses without a scenario."""

import numpy as np
import pytest
import xarray as xr

from salkit import focus, simulate
from salkit.io import read_raw, write_dataset


def test_focus_from_file_is_identical(files, spot):
    rp, ip, raw, img = files
    again = focus(read_raw(rp), spot.processing)
    np.testing.assert_array_equal(again["image"].values, img["image"].values)


def test_outside_phase_history_focuses(tmp_path, spot):
    """A frequency-domain phase history with per-pulse positions (the GOTCHA-like form of
    docs/data-format.md) focuses with salkit focus, without any scenario."""
    from salkit.focus import range_compress
    ph = range_compress(simulate(spot))
    outside = xr.Dataset(
        {"signal": (("slow_time", "frequency"), ph["signal"].values),
         "position": (("slow_time", "xyz"), ph["position"].values),
         "reference_range": (("slow_time",), ph["reference_range"].values)},
        coords={"frequency": ph["frequency"].values, "slow_time": ph["slow_time"].values, "xyz": ["x", "y", "z"]},
        attrs={"salkit_kind": "phase_history"})
    p = write_dataset(outside, tmp_path / "outside.nc")
    img = focus(read_raw(p), algorithm="bp")
    a = np.abs(img["image"].values)
    i, j = np.unravel_index(np.argmax(a), a.shape)
    assert abs(img["azimuth"].values[i]) < 0.01 and abs(img["range"].values[j]) < 0.01
    assert a.max() == pytest.approx(1.0, rel=0.02)
