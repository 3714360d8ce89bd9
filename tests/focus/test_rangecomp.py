"""Range compression: real sampling, intra-pulse motion, float64 ranges at long range."""
import numpy as np
import pytest

from salkit import focus, measure, simulate
from salkit.params import parse_scenario

from ..conftest import GEO, SPOT, merge

C = 299792458.0


def test_real_sampling_focuses_like_iq():
    """Real (single-channel) sampling with the scene beyond the reference range."""
    base = merge(SPOT, scene={"points": [{"x": 0.05, "y": 0.6, "phase": 0.3}]})
    iq = parse_scenario(merge(base, receiver={"adc_rate": 20e6, "reference_range": 4999.0}))
    re = parse_scenario(merge(base, receiver={"adc_rate": 40e6, "reference_range": 4999.0, "iq": False}))
    m_iq = measure(focus(simulate(iq), iq.processing), reflectivity_phase=0.3)
    m_re = measure(focus(simulate(re), re.processing), reflectivity_phase=0.3)
    for m in (m_iq, m_re):
        assert m["irw_range_m"] == pytest.approx(m["irw_range_theory_m"], rel=0.03)
        assert abs(m["peak_offset_range_m"]) < 0.1 * m["resolution_range_theory_m"]
        assert abs(m["peak_phase_error_rad"]) < 0.05
    assert m_re["peak_amplitude"] == pytest.approx(m_iq["peak_amplitude"], rel=0.02)


def test_real_sampling_needs_one_sided_scene():
    from salkit.errors import SamplingError
    sc = parse_scenario(merge(SPOT, receiver={"adc_rate": 40e6, "iq": False},
                              scene={"points": [{"x": 0, "y": -0.5}, {"x": 0, "y": 0.5}]}))
    with pytest.raises(SamplingError, match="one side of the reference"):
        simulate(sc)


def test_intra_pulse_motion_is_small_and_focused():
    """Motion during a 10 us pulse at 20 m/s moves the antenna 0.2 mm: the stop-and-go image and
    the intra-pulse image agree to well inside a resolution cell."""
    sc = parse_scenario(SPOT)
    sc2 = parse_scenario(merge(SPOT, platform__intra_pulse_motion=True))
    a = measure(focus(simulate(sc), sc.processing))
    b = measure(focus(simulate(sc2), sc2.processing))
    assert abs(a["peak_azimuth_m"] - b["peak_azimuth_m"]) < 0.02 * a["resolution_azimuth_theory_m"]
    assert b["irw_azimuth_m"] == pytest.approx(b["irw_azimuth_theory_m"], rel=0.03)
    raw_a, raw_b = simulate(sc)["signal"].values, simulate(sc2)["signal"].values
    assert not np.allclose(raw_a, raw_b)  # the motion is modelled


def test_float32_ranges_cannot_focus_at_200km(geo):
    """Why salkit keeps geometry in float64: backprojection with positions, pixels and ranges in
    float32 (as public GPU backprojectors hold them; 1.6 cm steps at 200 km) loses an off-centre
    target at 200 km, while the float64 sum at the same pixel is coherent."""
    from salkit.focus import phase_history
    sc = parse_scenario(merge(GEO, scene={"points": [{"x": 0.37, "y": 0.29}]}))
    ph = phase_history(simulate(sc))
    X = np.array([0.37, 0.29, 0.0])
    k = 4 * np.pi * ph.freq[ph.freq.size // 2] / C
    M = ph.data.shape[1]
    fc = ph.freq[M // 2]
    dR_true = np.linalg.norm(X - ph.positions, axis=1) - ph.reference_range
    # each pulse's range profile evaluated at the target's true range (exact, float64) ...
    prof = np.sum(ph.data * np.exp(4j * np.pi * (ph.freq[None, :] - fc) * dR_true[:, None] / C), axis=1)

    def value(dtype):  # ... so only the carrier phase depends on the arithmetic under test
        d = np.linalg.norm(X.astype(dtype) - ph.positions.astype(dtype), axis=1).astype(dtype) \
            - ph.reference_range.astype(dtype)
        return np.abs(np.sum(prof * np.exp(1j * k * d.astype(np.float64)))) / (len(prof) * M)
    v64 = value(np.float64)
    v32 = value(np.float32)
    assert v64 > 0.85  # coherent (two-way beam gain 0.88 at 0.47 m off the beam centre)
    assert v32 < 0.3 * v64


def test_image_file_scene(tmp_path):
    img = np.zeros((40, 60))
    img[10:30, 20:40] = 1.0
    np.save(tmp_path / "scene.npy", img)
    sc = parse_scenario(merge(SPOT, scene={"extended": {"kind": "image", "file": str(tmp_path / "scene.npy"),
                                                        "extent": [0.6, 0.4], "spacing": 0.01, "speckle": False}}))
    ds = focus(simulate(sc), sc.processing)
    im = np.abs(ds["image"].values)
    A, R = np.meshgrid(ds["azimuth"].values, ds["range"].values, indexing="ij")
    # the bright square spans +-0.1 m on the ground: +-0.1 m in azimuth, +-0.08 m in slant range
    inside = im[(np.abs(A) < 0.06) & (np.abs(R) < 0.05)].mean()
    outside = im[(np.abs(A) > 0.3) | (np.abs(R) > 0.3)].mean()
    assert inside > 20 * outside
    assert inside == pytest.approx(1.0, rel=0.15)  # unit reflectivity cells image to ~1


def test_a_path_where_the_dataset_belongs_is_refused_naming_it():
    """range_compress("raw.nc") raised AttributeError ('str' object has no attribute 'attrs')."""
    from salkit.errors import DataFileError
    from salkit.focus import range_compress
    with pytest.raises(DataFileError, match=r"range_compress: raw = 'raw.nc': must be an xarray.Dataset"):
        range_compress("raw.nc")
