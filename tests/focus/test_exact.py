"""The truth former: the closed-form matched filter of one pulse, unit response, the CLI's
``--algorithm exact`` and its refusal above the time limit."""
import numpy as np
import pytest

from salkit.constants import SPEED_OF_LIGHT as C
from salkit.errors import ScenarioError
from salkit.focus.exact import estimated_seconds, exact_image
from salkit.io import write_dataset
from salkit.simulate.analytic import analytic_phase_history
from salkit.simulate.testbeds import wide_angle

from ..cli.test_main import salkit


def test_one_pulse_is_the_dirichlet_kernel():
    """One pulse, M frequencies: sum_m exp(j 4 pi f_m d / c) in closed form along the line of
    sight, to 1e-10 over 64 offsets spanning 20 range cells (any interpolation would be far off)."""
    p = np.array([[0.0, -7000.0, 7300.0]])
    ref = np.linalg.norm(p, axis=1)
    f = 9.29e9 + 1.47e6 * np.arange(424)
    s = analytic_phase_history(p, ref, f, np.zeros((1, 3)))
    los = -p[0] / ref[0]
    d = np.linspace(-2.4, 2.4, 64)
    pts = d[:, None] * los[None, :]
    img = exact_image(s, f, p, ref, pts, los, np.array([0.0]))[:, 0]
    x = 2 * np.pi * 2 * 1.47e6 * d / C  # phase step between frequencies at offset d (sign: + for farther)
    M = f.size
    with np.errstate(invalid="ignore", divide="ignore"):
        dirichlet = np.where(np.abs(np.sin(x / 2)) < 1e-15, 1.0, np.sin(M * x / 2) / (M * np.sin(x / 2)))
    # the pixel at d is farther by d: the filter's phase at the band's mean frequency
    expected = dirichlet * np.exp(1j * 4 * np.pi * f.mean() * d / C)
    assert np.max(np.abs(img - expected)) < 1e-10


def test_unit_scatterer_anywhere_gives_one_at_its_pixel():
    tb = wide_angle(4.0, climb=0.5, plane="ground")
    pl = tb.image_plane()
    x = pl.points(np.array([3.7]), np.array([-11.3]))
    s = analytic_phase_history(tb.positions, np.linalg.norm(tb.positions, axis=1), tb.frequency, x,
                               np.array([0.5 * np.exp(0.3j)]))
    img = exact_image(s, tb.frequency, tb.positions, np.linalg.norm(tb.positions, axis=1), x,
                      pl.range, np.array([0.0]))
    assert abs(img[0, 0] - 0.5 * np.exp(0.3j)) < 1e-9


def test_estimate_scales_with_the_work():
    assert estimated_seconds(10, 10, 100, cores=1) * 2 == pytest.approx(estimated_seconds(20, 10, 100, cores=1))
    assert estimated_seconds(10, 10, 100, cores=2) == pytest.approx(estimated_seconds(10, 10, 100, cores=1) / 2)


@pytest.fixture
def ph_file(tmp_path):
    tb = wide_angle(4.0, climb=0.5, plane="ground")
    pts, amp = tb.point_targets(32, count=2)
    return write_dataset(tb.dataset(pts, amp), tmp_path / "ph.nc")


def test_cli_exact_matches_bp(tmp_path, ph_file):
    import xarray as xr
    for alg in ("exact", "bp"):
        r = salkit("focus", ph_file, "--algorithm", alg, "--nx", 32, "--ny", 32, "--dx", 0.2, "--dy", 0.2,
                   "--plane", "ground", "--out", tmp_path / alg)
        assert r.returncode == 0, r.stderr
    a = xr.open_dataset(tmp_path / "exact" / "image.nc")["image"].values
    b = xr.open_dataset(tmp_path / "bp" / "image.nc")["image"].values
    assert 10 * np.log10(np.sum(np.abs(a - b) ** 2) / np.sum(np.abs(a) ** 2)) < -60


def test_cli_exact_refused_above_the_time_limit(tmp_path, ph_file, monkeypatch):
    monkeypatch.setenv("SALKIT_EXACT_MAX_SECONDS", "0.0001")
    r = salkit("focus", ph_file, "--algorithm", "exact", "--nx", 32, "--ny", 32, "--dx", 0.2, "--dy", 0.2,
               "--out", tmp_path / "o")
    assert r.returncode == 2
    assert "processing.algorithm" in r.stderr and "limit" in r.stderr and "SALKIT_EXACT_MAX_SECONDS" in r.stderr
    assert not (tmp_path / "o").exists()


def test_exact_former_refuses_stripmap():
    from salkit.focus.exact import form_exact
    from salkit.focus.phasehistory import PhaseHistory

    class _G:
        shape = (4, 4)
    ph = PhaseHistory(np.zeros((2, 2), np.complex64), np.array([1.0, 2.0]), np.zeros((2, 3)), np.ones(2),
                      np.array([1.0, 0, 0]), np.array([0, -1.0, 1.0]), "stripmap", 0.1, {})
    with pytest.raises(ScenarioError, match="stripmap"):
        form_exact(ph, _G(), None)
