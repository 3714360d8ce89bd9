"""Phase screens: ensemble structure functions against Kolmogorov and von Karman theory, subharmonics, batches."""
import math

import numpy as np
import pytest

from salkit.atmosphere import (combine_r0, cn2_from_r0, max_layer_spacing, phase_screens, r0_from_cn2, r0_path,
                               rytov_variance, structure_function, structure_function_estimate, turbulence_class)
from salkit.atmosphere.turbulence import PSD_CONST, SF_CONST
from salkit.errors import ScenarioError


@pytest.mark.parametrize("n,count", [(64, 4000), (128, 2000)])
def test_kolmogorov_structure_function_within_3_percent(n, count):
    dx, r0 = 0.01, 0.05
    s = phase_screens(n, dx, r0, count=count, seed=0)
    r, d, err = structure_function_estimate(s, dx)
    th = structure_function(r, r0)
    ratio = d[1:] / th[1:]  # from 2 pixels to N/4
    assert np.all(np.abs(ratio - 1) < 0.03), ratio
    assert np.all(err[1:] / th[1:] < 0.015)  # the ensemble is large enough to test 3 %


@pytest.mark.parametrize("L0,l0", [(2.0, None), (0.3, None), (2.0, 0.02)])
def test_von_karman_structure_function_within_2_percent(L0, l0):
    dx, r0, n = 0.01, 0.05, 64
    s = phase_screens(n, dx, r0, count=3000, seed=0, outer_scale=L0, inner_scale=l0)
    r, d, err = structure_function_estimate(s, dx)
    th = structure_function(r, r0, L0, l0)
    assert np.all(np.abs(d[1:] / th[1:] - 1) < 0.02), d[1:] / th[1:]


def test_screens_without_subharmonics_fall_short():
    """The FFT alone misses the low frequencies: about a third of theory at N/4 is lost."""
    s = phase_screens(64, 0.01, 0.05, count=1000, seed=0, levels=0)
    r, d, _ = structure_function_estimate(s, 0.01)
    assert d[-1] / structure_function(r[-1:], 0.05)[0] < 0.8


def test_batches_seeds_dtypes():
    a = phase_screens(32, 0.01, 0.05, count=5, seed=3)
    b = phase_screens(32, 0.01, 0.05, count=5, seed=3)
    c = phase_screens(32, 0.01, 0.05, count=5, seed=4, dtype=np.float32)
    assert a.shape == (5, 32, 32) and np.array_equal(a, b)
    assert c.dtype == np.float32 and not np.allclose(a, c)
    odd = phase_screens(37, 0.02, 0.1, count=2, seed=0)
    assert odd.shape == (2, 37, 37) and np.all(np.isfinite(odd))


def test_amplitude_tables_kept_for_every_plane_of_an_ensemble_within_their_byte_bound(monkeypatch):
    """An ensemble visits its planes (each its own spacing) in turn, realisation after realisation:
    every plane's amplitude table is computed once, not once a screen (a cache of 4 tables visited
    by 17 planes in turn never hit), the screens are the same whether the table was cached or not,
    and the cache keeps to its byte bound, dropping the least recently used."""
    from salkit.atmosphere import screens as scr
    calls = []
    real = scr._spectrum_table
    monkeypatch.setattr(scr, "_spectrum_table", lambda *a: calls.append(a) or real(*a))
    monkeypatch.setattr(scr, "_amplitude_cache", type(scr._amplitude_cache)())
    spacings = [0.001 * (1 + 0.05 * i) for i in range(17)]
    first = [phase_screens(64, dx, 0.05, seed=3) for dx in spacings]
    again = [phase_screens(64, dx, 0.05, seed=3) for dx in spacings]
    assert len(calls) == 17
    assert all(np.array_equal(a, b) for a, b in zip(first, again))
    one = scr._amplitude_cache[next(iter(scr._amplitude_cache))].nbytes
    monkeypatch.setattr(scr, "AMPLITUDE_CACHE_BYTES", 3 * one)
    phase_screens(64, 0.5, 0.05, seed=3)
    assert len(scr._amplitude_cache) == 3 and (64, 0.5, 1.0, None, None) in scr._amplitude_cache
    assert (64, spacings[0], 1.0, None, None) not in scr._amplitude_cache  # the least recently used
    with pytest.raises(ValueError):
        scr._amplitude_cache[(64, 0.5, 1.0, None, None)][0, 0] = 1.0  # read-only
