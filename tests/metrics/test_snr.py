"""SNR estimators over ensembles of speckle: eq 14 for one look, sqrt(K) for K looks."""
import numpy as np
import pytest

from salkit.metrics import split_snr, stack_snr


def _looks(k, rng, n=128):
    # fully developed speckle on a uniform target of mean intensity 1: exponential intensities
    return rng.exponential(1.0, (k, n, n))


@pytest.mark.parametrize("k", [2, 8, 32])
def test_split_snr_grows_as_sqrt_k(k):
    rng = np.random.default_rng(k)
    mask = np.ones((128, 128), bool)
    assert split_snr(_looks(k, rng), mask, 0.0) == pytest.approx(np.sqrt(k), rel=0.05)


def test_stack_snr_of_one_look_is_one():
    rng = np.random.default_rng(0)
    mask = np.ones((128, 128), bool)
    assert stack_snr(_looks(1, rng)[0], np.ones((128, 128)), mask) == pytest.approx(1.0, rel=0.03)
