import numpy as np
import pytest

from salkit.errors import SamplingError, ScenarioError
from salkit.geometry import build_collection, check_sampling, resolution_theory, truth_positions
from salkit.geometry.sampling import delay_spread, n_fast_samples
from salkit.params import parse_scenario

from ..conftest import SPOT, STRIP, merge


def test_all_samples_inside_gate(spot):
    n = n_fast_samples(spot)
    d0, d1 = delay_spread(spot)
    gate = spot.waveform.pulse_width - 2 * max(abs(d0), abs(d1))
    assert (n // 2) / spot.receiver.adc_rate < gate / 2
    assert (n - n // 2 - 1) / spot.receiver.adc_rate < gate / 2


def test_prf_alias_detected_with_numbers():
    pts = [{"x": -0.5, "y": 0.0}, {"x": 0.5, "y": 0.0}]  # 1 m of scene in azimuth: ~5.2 kHz
    sc = parse_scenario(merge(SPOT, waveform__prf=1000.0, scene={"points": pts}))
    with pytest.raises(SamplingError) as ei:
        check_sampling(sc)
    assert ei.value.field == "waveform.prf"
    assert "Doppler bandwidth" in str(ei.value) and "Hz" in str(ei.value)


def test_stripmap_prf_against_beam():
    sc = parse_scenario(merge(STRIP, waveform__prf=1000.0))  # 4.88 v / D = 1627 Hz
    with pytest.raises(SamplingError, match="waveform.prf"):
        check_sampling(sc)


def test_adc_alias_detected():
    sc = parse_scenario(merge(SPOT, scene={"points": [{"x": 0, "y": 1.0}]}, receiver={"adc_rate": 2e6}))
    with pytest.raises(SamplingError) as ei:
        check_sampling(sc)
    assert ei.value.field == "receiver.adc_rate"
    assert "beat bandwidth" in str(ei.value)


def test_grid_coarser_than_resolution():
    sc = parse_scenario(merge(SPOT, processing={"algorithm": "bp", "grid": {"nx": 64, "ny": 64, "dx": 0.05, "dy": 0.01}}))
    with pytest.raises(SamplingError, match="processing.grid.dx"):
        check_sampling(sc)


def test_algorithm_mode_mismatch():
    sc = parse_scenario(merge(SPOT, processing={"algorithm": "omegak", "grid": SPOT["processing"]["grid"]}))
    with pytest.raises(ScenarioError, match="omegak forms stripmap collections on a straight track"):
        check_sampling(sc)
    sc = parse_scenario(merge(STRIP, processing={"algorithm": "pfa", "grid": STRIP["processing"]["grid"]}))
    with pytest.raises(ScenarioError, match="pfa forms spotlight collections; this one is stripmap: use bp"):
        check_sampling(sc)


def test_single_point_cannot_alias_but_grid_replicas_warn():
    sc = parse_scenario(merge(SPOT, waveform__prf=1000.0))
    with pytest.warns(UserWarning, match="unambiguous azimuth extent"):
        rep = check_sampling(sc)
    assert rep.doppler_bandwidth == pytest.approx(0.0, abs=1e-6)


def test_ffbp_on_stripmap_refused_before_work():
    from salkit.geometry import build_collection, check_sampling
    sc = parse_scenario(merge(STRIP, processing__algorithm="ffbp"))
    with pytest.raises(ScenarioError, match="ffbp"):
        check_sampling(sc, build_collection(sc))


def test_the_probe_points_hold_every_object_turned():
    from salkit.geometry.sampling import scene_probe_points
    sc = parse_scenario(merge(SPOT, scene={"objects": [{"shape": "box", "size": [4.0, 1.0, 1.0], "position": [1, 2, 0.5],
                                                        "attitude_deg": [90.0, 0.0, 0.0]}]}))
    pts = scene_probe_points(sc)
    assert np.ptp(pts[:, 1]) == pytest.approx(4.4) and np.ptp(pts[:, 0]) == pytest.approx(1.1)  # yawed 90 deg
    assert pts[:, 2].max() == pytest.approx(0.5 + 0.55)


def test_an_unreadable_mesh_is_refused_before_any_work(tmp_path):
    from salkit.geometry.sampling import scene_probe_points
    (tmp_path / "bad.stl").write_text("not a mesh")
    sc = parse_scenario(merge(SPOT, scene={"objects": [{"mesh": str(tmp_path / "bad.stl")}]}))
    with pytest.raises(ScenarioError, match="scene.objects.mesh"):
        scene_probe_points(sc)
