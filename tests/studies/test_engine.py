"""Running a sweep: the same numbers in this
process and on Dask workers, one of them killed mid-point; a checkpointed sweep interrupted and resumed equals the uninterrupted
one and reruns nothing; invalid points recorded; the dataset written and described."""
import numpy as np
import pytest

from salkit.errors import ScenarioError
from salkit.io import describe, open_dataset, write_dataset
from salkit.params import parse_scenario
from salkit.studies.engine import execute, plan_of
from salkit.studies.plan import check_points
from salkit.systems.preflight import preflight
from salkit.systems.study import run_point

from ..conftest import SPOT, merge

C = 299792458.0
NOISY = merge(SPOT, receiver__noise={"enabled": True, "signal_photons": 20.0})


def _numbers(ds):
    return {k: v.values for k, v in ds.data_vars.items() if k != "run_seconds"}


def test_interrupted_then_resumed_equals_uninterrupted(tmp_path):
    sc = parse_scenario(NOISY)
    plan = plan_of(sc, {"waveform.bandwidth": "5e9,7.5e9"}, realisations=2, metrics=["peak_amplitude"])
    whole = execute(plan, {}, run_point)
    seen = []

    def stop_after_two(done, total):
        seen.append(done)
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        execute(plan, {}, run_point, checkpoint=tmp_path / "ck", progress=stop_after_two)
    assert len(list((tmp_path / "ck").glob("p*_r*.json"))) == 2
    resumed_from = []
    again = execute(plan, {}, run_point, checkpoint=tmp_path / "ck", progress=lambda d, n: resumed_from.append(d))
    assert resumed_from[0] == 2 and resumed_from[-1] == 4  # only the two missing runs ran
    for k, v in _numbers(whole).items():
        np.testing.assert_array_equal(v, _numbers(again)[k], err_msg=k)
    other = plan_of(sc, {"waveform.bandwidth": "5e9,6e9"}, realisations=2, metrics=["peak_amplitude"])
    with pytest.raises(Exception, match="belongs to another sweep"):
        execute(other, {}, run_point, checkpoint=tmp_path / "ck")


def test_invalid_points_recorded_all_invalid_refused(tmp_path):
    sc = parse_scenario(SPOT)
    plan = plan_of(sc, {"waveform.prf": "25000,50"}, metrics=["irw_range_m"])
    bad = check_points(plan, preflight)
    ds = execute(plan, bad, run_point)
    assert ds["status"].values[0] == "ok" and ds["status"].values[1].startswith("invalid: ")
    assert np.isnan(ds["irw_range_m"].values[1]).all() and np.isfinite(ds["irw_range_m"].values[0]).all()
    allbad = plan_of(sc, {"waveform.prf": "50,60"})
    with pytest.raises(ScenarioError, match="none can run"):
        execute(allbad, check_points(allbad, preflight), run_point)
    p = write_dataset(ds, tmp_path / "sweep.nc")
    back = open_dataset(p)
    np.testing.assert_array_equal(back["irw_range_m"].values, ds["irw_range_m"].values)
    assert list(back["status"].values) == list(ds["status"].values)
    info = describe(p)
    assert info["kind"] == "sweep" and info["variables"]["irw_range_m"]["dims"] == ["waveform.prf", "realisation"]


def dies_once(data, metrics=(), keep_images=False):
    """Kills its Dask worker process the first time any worker runs it (a marker file records it)."""
    import os
    from pathlib import Path

    from salkit.systems.study import run_point
    marker = Path(os.environ["SALKIT_TEST_DIE_MARKER"])
    if not marker.exists():
        marker.write_text("died")
        os._exit(1)
    return run_point(data, metrics, keep_images)


def test_same_numbers_on_dask_even_when_a_worker_dies_mid_point(tmp_path):
    """Two Dask workers, one killed by its first run: the point is run again elsewhere, and every
    number equals the in-process sweep's; realisations differ from each other and repeat exactly."""
    dd = pytest.importorskip("dask.distributed")
    sc = parse_scenario(NOISY)
    plan = plan_of(sc, {"processing.window": "none,hamming"}, realisations=2,
                   metrics=["peak_amplitude", "irw_azimuth_m"])
    here = execute(plan, {}, run_point)
    marker = tmp_path / "died"
    with dd.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                         env={"SALKIT_TEST_DIE_MARKER": str(marker)}) as cl, dd.Client(cl) as client:
        there = execute(plan, {}, dies_once, client=client)
    assert marker.read_text() == "died"  # a worker did die, mid-point
    assert (there["status"].values == "ok").all()
    for k, v in _numbers(here).items():
        np.testing.assert_array_equal(v, _numbers(there)[k], err_msg=k)
    pk = here["peak_amplitude"].values
    assert pk[0, 0] != pk[0, 1]  # the realisations differ ...
    assert np.array_equal(execute(plan, {}, run_point)["peak_amplitude"].values, pk)  # ... and repeat exactly


def _half_measured(data, metrics, keep_images):
    """A runner whose second bandwidth cannot measure its IRW (as a run says when it cannot)."""
    bw = data["waveform"]["bandwidth"]
    if bw > 6e9:
        return {"status": "ok", "metrics": {"irw_range_m": float("nan")}, "seconds": 0.0,
                "unmeasured": {"irw_range_m": "the response's half-power points fall outside the cells analysed"}}
    return {"status": "ok", "metrics": {"irw_range_m": C / (2 * bw) * 0.886}, "seconds": 0.0}


def test_a_metric_a_point_cannot_measure_is_recorded_with_its_reason():
    """A NaN in sweep.nc comes with why: ``unmeasured`` per point (it used to be a bare NaN)."""
    sc = parse_scenario(SPOT)
    plan = plan_of(sc, {"waveform.bandwidth": "5e9,7.5e9"}, metrics=["irw_range_m"])
    ds = execute(plan, {}, _half_measured)
    assert list(ds["unmeasured"].values) == ["", "irw_range_m: the response's half-power points fall outside the "
                                                 "cells analysed"]
    from salkit.studies.engine import assemble
    rec = {"status": "ok", "metrics": {}, "unmeasured": {"irw_range_m": "why", "pslr_range_db": "why", "x_m": "other"}}
    grouped = assemble(plan, {}, {(0, 0): rec, (1, 0): rec})["unmeasured"].values[0]
    assert grouped == "irw_range_m, pslr_range_db: why; x_m: other"  # one reason, said once
    assert np.isnan(ds["irw_range_m"].values[1, 0]) and list(ds["status"].values) == ["ok", "ok"]


def test_a_run_asked_for_a_figure_it_does_not_measure_says_so():
    sc = parse_scenario(SPOT)
    plan = plan_of(sc, {"waveform.bandwidth": "7.5e9"}, metrics=["irw_range_m", "fringe_period_m"])
    ds = execute(plan, {}, run_point)
    assert "fringe_period_m: this run measures no such figure" in str(ds["unmeasured"].values[0])


def test_one_axis_as_a_string_is_one_axis_not_its_characters():
    """sweep(sc, vary="waveform.bandwidth=5e9,6e9") was read character by character ("--vary = 'w'")."""
    sc = parse_scenario(SPOT)
    one = plan_of(sc, "waveform.bandwidth=5e9,6e9")
    assert one.shape == (2,) and one == plan_of(sc, ["waveform.bandwidth=5e9,6e9"]) \
        == plan_of(sc, {"waveform.bandwidth": "5e9,6e9"})
