"""OpenMP's waiting policy for salkit's kernels, set before numba starts its threads.

numba runs salkit's parallel kernels on OpenMP (libgomp) threads, which by default keep spinning
for a while after each parallel region before they sleep. salkit's kernels alternate with
``scipy.fft``'s own threads: FFBP's leaves at 4096^2 are 32 parallel sums, each followed by a
two-thread FFT; direct backprojection's profiles are transformed between its kernel's blocks.
The spinning threads then hold the cores the FFT needs. ``OMP_WAIT_POLICY=passive`` puts them to
sleep at once (waking them costs microseconds a region). On the development VM (2-core Zen 4) FFBP
of the synthetic 1.55 um collection at 4096^2 took 1.64 to 1.77 s with the default policy and
1.53 s with this one, its fused leaves 0.80 s against 0.69 to 0.72 s; the arc's FFBP and direct
backprojection's kernel were unchanged (their range profiles 0.023 -> 0.018 s).

Importing salkit sets it where the environment does not already name a policy (a value the user
set is kept), and it takes effect where no OpenMP runtime has started in the process yet: libgomp
reads its environment once, when it is loaded (numba loads it at its first parallel kernel).
"""
from __future__ import annotations

import os

#: The policy salkit asks for (``OMP_WAIT_POLICY``), unless the environment names one.
WAIT_POLICY = "passive"

os.environ.setdefault("OMP_WAIT_POLICY", WAIT_POLICY)

__all__ = ["WAIT_POLICY"]
