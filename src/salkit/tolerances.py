"""Acceptance tolerances against theory, named once: the tests assert them and the reports colour
their comparison rows with them.

Each is the largest departure a correct implementation shows on the shipped cases, with the
reason for its size.
"""

#: |IRW / theory - 1| for a point target (3 %: the measured -3 dB width on an 8x upsampled cut
#: against the window's continuous IRW factor).
IRW_RATIO = 0.03
#: |PSLR - theory|, dB (sampled sidelobe peaks on a finite aperture).
PSLR_DB = 0.3
#: |ISLR - theory|, dB (the integration window's edges).
ISLR_DB = 1.0
#: |peak position - truth| in resolution cells.
PEAK_OFFSET_CELLS = 0.1
#: |peak phase - reflectivity phase|, rad.
PEAK_PHASE_RAD = 0.05
#: |CNR of the brightest target / theory - 1| for one realisation of photon noise.
CNR_RATIO = 0.15
#: |speckle image SNR / theory - 1|.
SNR_RATIO = 0.1
#: A chirp correction succeeds when the range IRW is within this fraction of the ideal chirp's.
CHIRP_IRW_OF_IDEAL = 0.05
#: Largest ratio of grid spacing to resolution accepted (1 % for rounding in the scenario).
GRID_SPACING_OF_RESOLUTION = 1.01
#: A mainlobe width (IRW) means something only while the highest sidelobe stays this far below the
#: peak, dB; above it (turbulence that breaks the peak up) reports show the peak ratio and entropy.
IRW_MEANINGFUL_PSLR_DB = -6.0
#: |measured fringe period / eq 25 - 1| on a uniform scene (the period is fitted over a finite swath).
FRINGE_PERIOD_RATIO = 0.01
#: Default range-profile upsampling of backprojection's formers that declare none of their own
#: (``bp_cubic``, ``bp_fitted``; linear interpolation through the library): linear -64 to -69 dB
#: image error against the exact matched filter, Keys cubic -89 to -95 dB, the fitted taps -110 to
#: -113.5 dB (docs/performance.md, "Accuracy against the exact truth").
BP_UPSAMPLE = 16
#: Upsampling of every backprojection former at ``accuracy: high`` (at least), unless it declares its own.
HIGH_ACCURACY_UPSAMPLE = 32
#: The default former ``bp``'s upsampling (its four taps fitted to the profile's band): -87 to -89 dB
#: at 6x, and at ``accuracy: high`` 8x, -97 to -99 dB, at the speed of 4x (the kernel's time hardly
#: depends on the upsampling; the bytes it reads do: 6x fitted reads 0.37 of 16x linear's).
BP_DEFAULT_UPSAMPLE = 6
BP_DEFAULT_HIGH_UPSAMPLE = 8
