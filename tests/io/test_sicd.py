"""SICD 1.3.0 export through sarkit: consistent, pixels read back, horizontal looks refused."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.errors import DataFileError
from salkit.focus import range_compress
from salkit.io import check_cphd, read_cphd, read_gotcha, read_phase_data, write_cphd, write_gotcha

from .conftest import _ccorr


@pytest.mark.parametrize("case", ["spot", "ground", "strip", "right"])
def test_sicd_export_is_consistent(tmp_path, case):
    """SICD 1.3.0 from a focused image: sarkit's checker finds 0 errors and 0 warnings, and the
    pixels read back are the image's (rows = range, columns along the grid normal's convention)."""
    from salkit.io import check_sicd, read_sicd, write_sicd
    from salkit.io.sicd import sicd_xml
    from salkit.params import parse_scenario
    from ..conftest import SPOT, STRIP, merge
    d = {"spot": SPOT, "strip": STRIP, "right": merge(SPOT, platform__side="right"),
         "ground": merge(SPOT, processing__grid={"nx": 96, "ny": 64, "dx": 0.015, "dy": 0.02, "plane": "ground"})}[case]
    sc = parse_scenario(d)
    img = focus(simulate(sc), sc.processing)
    img.attrs["origin_llh"] = np.array([35.0, -106.5, 1600.0])
    p = write_sicd(img, tmp_path / "i.nitf")
    assert check_sicd(p) == {"errors": [], "warnings": []}
    pix, tree = read_sicd(p)
    _, info = sicd_xml(img)
    ref = img["image"].values.T
    np.testing.assert_array_equal(pix, ref[:, ::-1] if info["columns_flipped"] else ref)
    assert info["position_fit_residual"] < 1e-6
    assert tree.findtext("{*}Grid/{*}ImagePlane") == ("GROUND" if case == "ground" else "SLANT")
    # sarpy, an independent reader, validates it too (it asks for the imaged area's corners, ACP)
    from sarpy.io.complex.converter import open_complex
    meta = open_complex(str(p)).sicd_meta
    assert meta.is_valid(recursive=True, stack=False)
    assert meta.GeoData.SCP.LLH.Lat == pytest.approx(35.0, abs=1e-3)


def test_sicd_refuses_a_horizontal_look(tmp_path, geo):
    from salkit.io import write_sicd
    img = focus(simulate(geo), geo.processing)
    with pytest.raises(DataFileError, match="above the scene's horizon"):
        write_sicd(img, tmp_path / "g.nitf")
    assert not list(tmp_path.iterdir())
