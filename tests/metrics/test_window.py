"""An image larger than memory measured from its file: the window around the brightest pixel and the
whole image's moments give the in-memory figures."""
import numpy as np
import pytest
import xarray as xr

from salkit.io.reading import open_dataset
from salkit.io.writing import ImageFileWriter
from salkit.metrics import brightest_window, measure


def _image(n=600, d=0.0025, rho=0.02):
    x = (np.arange(n) - n // 2) * d
    X, Y = np.meshgrid(x, x, indexing="ij")
    rng = np.random.default_rng(3)
    img = (np.sinc((X - 0.11) / rho) * np.sinc((Y + 0.07) / rho) * np.exp(2j * np.pi * 0.3 * X / d)
           + 0.002 * (rng.standard_normal(X.shape) + 1j * rng.standard_normal(X.shape))).astype(np.complex64)
    attrs = {"resolution_azimuth": rho, "resolution_range": rho, "salkit_kind": "image"}
    return xr.Dataset({"image": (("azimuth", "range"), img)}, coords={"azimuth": x, "range": x}, attrs=attrs)


def test_window_of_a_chunked_file_measures_as_the_whole_image(tmp_path):
    ds = _image()
    path = tmp_path / "img.nc"
    with ImageFileWriter(path, ds.drop_vars("image"), (128, 128)) as w:
        for a in range(0, 600, 128):
            for b in range(0, 600, 128):
                w.write(a, b, ds["image"].values[a:a + 128, b:b + 128])
        w.close()
    lazy = open_dataset(path, lazy=True)
    win, mom = brightest_window(lazy, rows=37)  # blocks that cut chunks: read as whole chunks anyway
    assert win.sizes["azimuth"] < 600 and win.sizes["range"] < 600  # the analysis' window (+-15 cells)
    a, b = measure(ds), measure(win, moments=mom)
    for k in ("irw_range_m", "irw_azimuth_m", "peak_azimuth_m", "peak_range_m", "peak_amplitude", "entropy",
              "contrast"):
        assert b[k] == pytest.approx(a[k], rel=1e-9, abs=1e-12), k
    for k in ("pslr_range_db", "pslr_azimuth_db", "islr_range_db", "islr_azimuth_db"):
        assert b[k] == pytest.approx(a[k], abs=1e-9), k
    assert a["peak_azimuth_m"] == pytest.approx(0.11, abs=0.02 / 50)
