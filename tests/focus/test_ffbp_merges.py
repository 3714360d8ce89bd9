"""FFBP's merge kernels: merging by two or by four gives the image direct backprojection gives,
and the last step's point-by-point path equals its separable row pass."""
import numpy as np

from salkit import focus, simulate
from salkit.focus import phase_history
from salkit.focus.ffbp import ffbp
from salkit.focus.formers import ImageGrid
from salkit.simulate.testbeds import wide_angle

from .test_ffbp import CASES, _error_db, _images


def test_merging_by_two_and_by_four_agree_with_the_direct_sum():
    tb = wide_angle(4.0, 0.5, "ground")
    pts, amp = tb.point_targets(64, count=3)
    ph = phase_history(tb.dataset(pts, amp))
    ig = ImageGrid.of(ph, tb.grid(64))
    P, M = ph.data.shape
    direct = focus(tb.dataset(pts, amp), grid=tb.grid(64), algorithm="exact", window_name="none")["image"].values
    for factor in (2, 4):
        img, info = ffbp(ph.data, ph.freq, ph.positions, ph.reference_range, ig, np.ones(P), np.ones(M), factor=factor)
        img = img / (P * M)
        err = 10 * np.log10(np.sum(np.abs(img - direct) ** 2) / np.sum(np.abs(direct) ** 2))
        assert err < -50, (factor, err)


def test_final_step_point_by_point_agrees(monkeypatch):
    """Where image rows do not cross the sub-apertures' range bins in order, the last step
    interpolates point by point (48 taps): the same image as the separable row pass."""
    import salkit.focus.ffbp as ffbp_module
    sc, a, b = _images(CASES["5km"])
    monkeypatch.setattr(ffbp_module, "_rows_in_order", lambda *args: False)
    c = focus(simulate(sc), sc.processing, algorithm="ffbp")
    assert _error_db(a, c) < -40
    assert _error_db(b, c) < -40


