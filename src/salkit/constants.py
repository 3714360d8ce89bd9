"""Physical constants (SI units)."""
SPEED_OF_LIGHT = 299_792_458.0  #: m/s, exact
PLANCK = 6.626_070_15e-34  #: J s, exact
ELEMENTARY_CHARGE = 1.602_176_634e-19  #: C, exact

#: ``workers`` of every scipy.fft call: all cores.
FFT_WORKERS = -1
