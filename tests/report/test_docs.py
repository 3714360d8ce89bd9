"""The README's generated blocks: markers found, replaced, and refused when missing."""
import json

import pytest

from salkit.errors import DataFileError
from salkit.report.docs import blocks, fill, read_blocks, spotlight_caption


def test_fill_replaces_only_the_named_blocks():
    text = "x\n<!-- generated:a -->\nold a\n<!-- /generated:a -->\n<!-- generated:b -->\nold b\n<!-- /generated:b -->\n"
    out = fill(text, {"a": "new a\n"})
    assert read_blocks(out) == {"a": "new a\n", "b": "old b\n"}
    with pytest.raises(DataFileError, match="generated block"):
        fill(text, {"c": "?"})


def test_caption_quotes_the_metrics_rounded():
    m = {"irw_range_m": 0.017971, "irw_range_theory_m": 0.0178, "pslr_range_db": -13.2561,
         "irw_azimuth_m": 0.01775, "irw_azimuth_theory_m": 0.017663, "pslr_azimuth_db": -13.27}
    c = spotlight_caption(m)
    assert "IRW 1.797 cm vs 1.780 cm" in c and "PSLR -13.26 dB" in c and "1.775 cm vs 1.766 cm" in c


def test_blocks_from_a_results_folder(tmp_path):
    sp = {"irw_range_m": 0.018, "irw_range_theory_m": 0.018, "pslr_range_db": -13.26, "irw_azimuth_m": 0.018,
          "irw_azimuth_theory_m": 0.018, "pslr_azimuth_db": -13.26}
    dl = {"terrain_look_angle_deg": 45.0, "terrain_phase_per_height_rad_per_m": -0.002,
          "terrain_phase_per_height_model_rad_per_m": 49.4, "terrain_height_recovered_rms_m": 0.0057,
          "terrain_height_rms_m": 0.243}
    for name, m in (("spotlight_points", sp), ("downlooking_3d", dl)):
        (tmp_path / name).mkdir()
        (tmp_path / name / "metrics.json").write_text(json.dumps(m))
        (tmp_path / name / "image.nc").write_bytes(b"")
    b = blocks(tmp_path)
    assert set(b) == {"spotlight_caption", "downlooking_caption", "files", "formers"}
    assert "| `spotlight_points` | `image.nc` |" in b["files"]
