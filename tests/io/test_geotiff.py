"""The detected image as a Cloud-Optimised GeoTIFF: its map places every corner pixel where the
image's geolocation says (to a micrometre), GDAL reads it as a COG; refused without a geographic
reference or off the ground plane."""
import shutil
import subprocess

import numpy as np
import pytest
import rasterio
from pyproj import Transformer

from salkit import focus, simulate
from salkit.errors import DataFileError
from salkit.io.geotiff import write_geotiff
from salkit.params import parse_scenario

from ..conftest import SPOT, merge


def _image(**changes):
    d = merge(SPOT, processing__grid={"nx": 120, "ny": 96, "dx": 0.012, "dy": 0.02, "plane": "ground"}, **changes)
    sc = parse_scenario(d)
    return focus(simulate(sc), sc.processing, scenario=sc)


@pytest.mark.parametrize("origin", [[48.8583, 2.2945, 35.0], [-33.86, 151.21, 40.0], [69.65, 18.96, 0.0]])
def test_corners_land_where_the_geolocation_says(tmp_path, origin):
    img = _image(scene__origin=origin)
    info = write_geotiff(img, tmp_path / "i.tif")
    assert info["misfit_pixels"] < 1e-3
    with rasterio.open(tmp_path / "i.tif") as src:
        assert src.tags(ns="IMAGE_STRUCTURE")["LAYOUT"] == "COG" and src.shape == (120, 96)
        np.testing.assert_allclose(src.read(1), np.abs(img["image"].values), rtol=1e-6)
        back = Transformer.from_crs(src.crs, "EPSG:4326", always_xy=True)
        nx, ny = src.shape
        for k, (r, c) in enumerate([(0, 0), (0, ny - 1), (nx - 1, 0), (nx - 1, ny - 1)]):
            lon, lat = back.transform(*(src.transform @ (c + 0.5, r + 0.5)))
            assert abs(lat - img.attrs["corner_latitude"][k]) * 111e3 < 1e-6
            assert abs(lon - img.attrs["corner_longitude"][k]) * 111e3 * np.cos(np.radians(lat)) < 1e-6
    if shutil.which("gdalinfo"):  # GDAL's own tool, where Debian's gdal-bin is installed
        r = subprocess.run(["gdalinfo", "-json", str(tmp_path / "i.tif")], capture_output=True, text=True, check=True)
        assert '"LAYOUT":"COG"' in r.stdout.replace(" ", "") and "cornerCoordinates" in r.stdout


def test_refused_without_a_reference_or_off_the_ground(tmp_path):
    with pytest.raises(DataFileError, match="--origin"):
        write_geotiff(_image(), tmp_path / "a.tif")
    sc = parse_scenario(merge(SPOT, scene__origin=[10.0, 10.0, 0.0]))
    slant = focus(simulate(sc), sc.processing, scenario=sc)
    with pytest.raises(DataFileError, match="--plane ground"):
        write_geotiff(slant, tmp_path / "b.tif")
    assert not list(tmp_path.iterdir())


def test_export_places_an_image_formed_without_origin_when_given_one(tmp_path):
    """``salkit export image.nc x.tif --origin ...`` geolocates an image formed without a reference
    (through ``geolocate_image``), the same as forming it with that origin."""
    from typer.testing import CliRunner

    from salkit.cli.main import app
    from salkit.io import write_dataset
    img = _image()
    write_dataset(img, tmp_path / "image.nc")
    r = CliRunner().invoke(app, ["export", str(tmp_path / "image.nc"), str(tmp_path / "x.tif")])
    assert r.exit_code == 2 and "--origin" in r.output and not (tmp_path / "x.tif").exists()
    r = CliRunner().invoke(app, ["export", str(tmp_path / "image.nc"), str(tmp_path / "x.tif"),
                                 "--origin", "45.0,7.0,100"])
    assert r.exit_code == 0, r.output
    ref = _image(scene__origin=[45.0, 7.0, 100.0])
    with rasterio.open(tmp_path / "x.tif") as src:
        back = Transformer.from_crs(src.crs, "EPSG:4326", always_xy=True)
        lon, lat = back.transform(*(src.transform @ (0.5, 0.5)))
    assert abs(lat - ref.attrs["corner_latitude"][0]) * 111e3 < 1e-6
    assert abs(lon - ref.attrs["corner_longitude"][0]) * 111e3 < 1e-6
