"""Physical constants: exact SI values."""
from salkit.constants import FFT_WORKERS, SPEED_OF_LIGHT


def test_speed_of_light_is_exact():
    assert SPEED_OF_LIGHT == 299_792_458.0 and isinstance(SPEED_OF_LIGHT, float)


def test_fft_workers_use_every_core():
    assert FFT_WORKERS == -1
