"""salkit benchmarks: throughput figures and ratios against the public alternative, same machine,
same run. ``make bench`` runs them all, ``make bench NAME=ffbp`` one (or
``.venv/bin/python benchmarks/run_all.py [NAME ...]``). One benchmark a file (``benchmarks/<name>.py``),
run by :mod:`runner`, which writes ``benchmarks/last_run.json``.

- backprojection: salkit (numba) vs a straightforward NumPy backprojection (loop over pulses,
  vectorised over pixels), on the same phase history and grid; images compared.
- PFA: time as a multiple of one complex FFT of the output size (scipy.fft, same workers).
- simulation: scatterer-samples per second of the dechirped-echo simulator.
- spaceborne: GEO sub-images per second in-process and through Dask with 1 and 2 workers
  (64 sub-images, cluster start included).
- chirp: milliseconds per pulse of 1e5 samples for each nonlinear-chirp correction.
- pga: PGA seconds per iteration at 256 x 256 and 2048 x 2048 (LUMV and eigenvector kernels).
- screens: phase screens per second at N = 256, 1024, 4096 against aotools' ft_sh_phase_screen
  (install with ``pip install -e .[bench]``), and both generators' ensemble structure function
  against Kolmogorov theory from 2 pixels to N/4.

- downlooking: seed 000 design example, a 2.4 m x 2.4 m scene imaged on >= 256 x 256 pixels:
  raw-data simulation (factored BLAS path and the numba field kernel against a vectorised NumPy
  evaluation of the same fields) and image formation (FFT processor against a direct
  time-domain along-track matched filter), with the images compared.

- startup: ``import salkit`` and ``salkit --help`` in fresh interpreters against
  ``import numpy, xarray``.
- outside: a 500-pulse collection converted to CPHD (sarkit check included) and the GOTCHA .mat
  layout and back, focused; per-pulse sharpness autofocus per sweep against PGA per iteration at
  1024 x 1024.

- ffbp: fast factorised backprojection against direct backprojection at 512^2, 1024^2 and 4096^2
  pixels (as many pulses), direct BP timed on a block of rows and scaled, both the best of the
  same number of runs; ffbp_knobs: the accuracy-speed curve over the polar-grid oversampling and
  the leaf size at 1024^2; ffbp_arcs: arcs of 60 degrees to a full circle against the exact
  matched filter, formed in parts and (to 170 degrees) as one tree, direct BP's time beside.
- accuracy (benchmarks/accuracy.py): every former (bp, bp at 32x, ffbp, ffbp high, pfa) on the
  test geometries against the exact float64 matched filter: error energy, bright-pixel phase
  error, time; the wide-angle arc from 101^2 to 2001^2 pixels.
- propagation: split-step wave-optics propagation per realisation (10 screens) at N = 256, 512,
  1024 against the same propagation written plainly with np.fft; fields compared.
- sweep: a 24-point design study in this process and on 1 and 2 Dask workers: speed-up and the
  engine's per-point overhead.
- scaling: time and peak memory of each stage (simulate, phase history, BP, FFBP, PFA, PGA) at
  N = 256, 512, 1024 (N x N pixels, N pulses), and the fitted exponent of time ~ N^a.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from runner import main  # noqa: E402

if __name__ == "__main__":
    main(sys.argv[1:])
