"""Units of metric names and their display."""
import math

import pytest

from salkit.units import display, round_sig, unit_of


@pytest.mark.parametrize("name, unit", [("irw_range_m", "m"), ("pslr_azimuth_db", "dB"), ("run_s", "s"),
                                        ("relative_speed_m_s", "m/s"), ("sampling_prf", "Hz"),
                                        ("sampling_gate", "s"), ("xi_per_m", "Hz/m"), ("stack_count", ""),
                                        ("peak_phase_error_rad", "rad"), ("terrain_look_angle_deg", "deg")])
def test_unit_of(name, unit):
    assert unit_of(name) == unit


@pytest.mark.parametrize("value, scale, unit", [(1.797e-2, 1e-2, "cm"), (3.2e-4, 1e-6, "um"), (5000.0, 1e3, "km"),
                                                (1.5, 1.0, "m"), (4.5e-3, 1e-3, "mm"), (2e-9, 1e-9, "nm")])
def test_lengths_are_shown_in_a_unit_that_keeps_them_readable(value, scale, unit):
    text, u = display("x_m", value)
    assert u == unit
    assert float(text) == pytest.approx(value / scale, rel=1e-3)


def test_round_sig_keeps_four_significant_digits():
    for x in (0.0123456, 123.456, 98765.4321, -13.2649, 2.5e-7, 3.0e12):
        assert float(round_sig(x)) == pytest.approx(x, rel=5e-4)
    assert round_sig(float("nan")) == "nan" and not math.isfinite(float(round_sig(math.inf)))


def test_flags_and_counts_are_not_rounded():
    assert display("speckle", True) == ("yes", "")
    assert display("stack_count", 11288) == ("11288", "")
