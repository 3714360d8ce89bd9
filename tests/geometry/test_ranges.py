"""Differential ranges from small quantities against a 50-digit evaluation."""
from decimal import Decimal, getcontext
from fractions import Fraction

import numpy as np

from salkit.geometry.ranges import differential_range, range_offsets


def _exact(x, p, ref):
    getcontext().prec = 50
    return float(sum((Decimal(float(a)) - Decimal(float(b))) ** 2 for a, b in zip(x, p)).sqrt() - Decimal(float(ref)))


def test_range_offsets_exact():
    pos = np.array([[336000.1, -448000.3, 12.7], [3.0, 4.0, 0.0]])
    ref = np.array([560000.2, 5.0])
    D = range_offsets(pos, ref)
    want = [float(sum(Fraction(float(v)) ** 2 for v in p) - Fraction(float(r)) ** 2) for p, r in zip(pos, ref)]
    assert D.tolist() == want


def test_differential_range_at_560_km_to_1e_15_m():
    rng = np.random.default_rng(2)
    pos = np.c_[rng.uniform(-5, 5, 20), -560000.0 + rng.uniform(-1, 1, 20), rng.uniform(-1, 1, 20)]
    ref = np.linalg.norm(pos, axis=1) + rng.uniform(-0.1, 0.1, 20)
    D = range_offsets(pos, ref)
    worst_new, worst_naive = 0.0, 0.0
    for k in range(20):
        x = rng.uniform(-3, 3, 3)
        e = _exact(x, pos[k], ref[k])
        got = differential_range(x[0], x[1], x[2], pos[k, 0], pos[k, 1], pos[k, 2], ref[k], D[k])
        naive = np.linalg.norm(x - pos[k]) - ref[k]
        worst_new = max(worst_new, abs(got - e))
        worst_naive = max(worst_naive, abs(naive - e))
    assert worst_new < 1e-14
    assert worst_naive > 1e-12  # the rounding the module avoids (up to 6e-11 m)
