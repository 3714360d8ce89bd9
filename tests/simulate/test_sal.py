"""The sal simulator in blocks and on Dask: the same numbers as simulate_sal, whether the history is
made at once, written a block of pulses at a time, or its blocks' echoes are computed on Dask
workers while the receiver's noise is drawn in pulse order here (a speckled scene with photon noise;
a laser of finite linewidth with a reference channel recording each pulse)."""
import numpy as np
import pytest

from salkit import simulate
from salkit.io import open_dataset
from salkit.params import parse_scenario
from salkit.resources import dask_client
from salkit.simulate.echoes import scene_memory, signal_shape
from salkit.simulate.sal import simulate_to_file

from ..conftest import SPOT, merge

SPECKLE = {"extended": {"pattern": "uniform", "extent": [0.6, 0.6], "spacing": 0.01, "speckle": True},
           "points": [{"x": 0.1, "y": -0.1}]}


LONG = {"platform": {**SPOT["platform"], "aperture_length": 0.8},  # 1000 pulses
        "processing": {**SPOT["processing"], "grid": {"nx": 64, "ny": 64, "dx": 0.004, "dy": 0.004}}}


def _cases():
    noisy = parse_scenario(merge(SPOT, scene=SPECKLE, receiver={**SPOT["receiver"], "noise": {
        "enabled": True, "signal_photons": 50.0}}, **LONG))
    laser = parse_scenario(merge(SPOT, waveform={**SPOT["waveform"], "linewidth": 2e6},
                                 receiver={**SPOT["receiver"], "lo_delay": 3.33e-5,
                                           "reference_channel": {"d_r": 3.0, "d_rlo": 0.0}}, **LONG))
    return {"noise": noisy, "linewidth": laser}


@pytest.mark.parametrize("case", ["noise", "linewidth"])
def test_blocks_and_dask_workers_give_the_same_history(case, tmp_path):
    sc = _cases()[case]
    whole = simulate(sc)
    P, N = whole["signal"].shape
    assert P > 512  # more than one block of noise draws
    block = 3 * 8.0 * signal_shape(sc)[1] * 512 * 2 + 100.0  # blocks of 512 pulses in half of what the scene leaves
    here = open_dataset(simulate_to_file(sc, tmp_path / "here.nc", memory_limit=scene_memory(sc)[0] + block))
    with dask_client(workers=2) as client:  # three blocks in flight share it
        there = open_dataset(simulate_to_file(sc, tmp_path / "there.nc", memory_limit=scene_memory(sc)[0] + 3 * block,
                                              client=client))
    ref = whole["signal"].values
    scale = np.abs(ref).max()
    for got in (here, there):
        assert got["signal"].encoding["chunksizes"][0] <= 512
        np.testing.assert_allclose(got["signal"].values, ref, rtol=0, atol=1e-6 * scale)
        if "reference_signal" in whole:
            np.testing.assert_allclose(got["reference_signal"].values, whole["reference_signal"].values, rtol=0,
                                       atol=1e-6)
