"""Turbulence commands: ``salkit screen`` (phase screens) and ``salkit propagate`` (split-step wave
optics against scintillation theory)."""
from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Optional

import typer

from .app import _guard, out
from .options import _check_out_file


@_guard
def screen(n: int = typer.Option(..., "--n", metavar="SAMPLES", help="screen size, samples per side"),
           dx: float = typer.Option(..., "--dx", metavar="METRES", help="sample spacing, m"),
           r0: float = typer.Option(..., "--r0", metavar="METRES", help="Fried parameter r0, m"),
           count: int = typer.Option(1, "--count", metavar="N", help="number of screens"),
           seed: int = typer.Option(0, "--seed", metavar="INT", help="random seed (the same seed gives the same screens)"),
           outer_scale: Optional[float] = typer.Option(None, "--outer-scale", metavar="METRES", help="von Karman outer scale L0, m (default: Kolmogorov, infinite)"),
           inner_scale: Optional[float] = typer.Option(None, "--inner-scale", metavar="METRES", help="inner scale l0, m (default: none)"),
           out: Path = typer.Option(..., "--out", metavar="FILE.nc", help="NetCDF file to write (phase in rad; a PNG of screen 0 beside it)"),
           overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Generate turbulence phase screens (rad) into a NetCDF file, with a picture of the first."""
    from ..atmosphere import phase_screens
    _check_out_file(out, overwrite)
    from ..io.screens import write_screens
    phi = phase_screens(n, dx, r0, count=count, seed=seed, outer_scale=outer_scale, inner_scale=inner_scale)
    step = math.sqrt(6.88 * (dx / r0) ** (5.0 / 3.0))  # rms phase difference of neighbouring samples, rad
    if step > math.pi:
        warnings.warn(f"--dx = {dx:g} m against --r0 = {r0:g} m: neighbouring samples differ by {step:.3g} rad rms "
                      "(Kolmogorov, sqrt(6.88 (dx/r0)^(5/3))); beyond pi a field sampled at this spacing through the "
                      f"screen is aliased: sample at dx below {1.24 * r0:.3g} m (1.24 r0)", UserWarning, stacklevel=2)
    from ..plot import screen_image
    nc = write_screens(phi, dx, out, r0=r0, seed=seed, outer_scale=outer_scale, inner_scale=inner_scale)
    png = screen_image(phi[0], dx, out.with_suffix(".png"), title=f"phase screen 0 (r0 = {r0} m)")
    globals()["out"].print(f"wrote {nc} ({count} screens of {n} x {n}) and {png}")


@_guard
def propagate(wave: str = typer.Option("plane", "--wave", metavar="KIND", help="plane | spherical (a point source)"),
              wavelength: float = typer.Option(..., "--wavelength", metavar="METRES", help="wavelength, m"),
              cn2: float = typer.Option(..., "--cn2", metavar="M^-2/3", help="refractive-index structure constant Cn2, m^(-2/3), uniform on the path"),
              distance: float = typer.Option(..., "--distance", metavar="METRES", help="path length, m"),
              layers: Optional[int] = typer.Option(None, "--layers", metavar="N", help="phase screens (default: as many as keep each weak, at least 10)"),
              count: int = typer.Option(16, "--count", metavar="K", help="realisations"),
              seed: int = typer.Option(0, "--seed", metavar="INT", help="random seed"),
              inner_scale: Optional[float] = typer.Option(None, "--inner-scale", metavar="METRES", help="inner scale l0 of the modified atmospheric spectrum, m (plane waves; default 0: Kolmogorov)"),
              out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder: field.nc and metrics.json"),
              overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new run is complete")):
    """Propagate a wave through turbulence (split-step wave optics): the received field and its
    scintillation against theory."""
    from ..atmosphere.propagation import propagation_result
    from ..metrics.table import warn_undeclared
    from ..errors import ScenarioError
    from ..io import write_dataset
    from ..io.writing import write_json_atomic
    from ..io.runfolder import RunFolder
    for name, v, ok, rule in (("--wavelength", wavelength, 0 < wavelength < 1e-3, "must be in (0, 1 mm)"),
                              ("--cn2", cn2, 0 <= cn2 < 1e-10, "must be in [0, 1e-10) m^(-2/3)"),
                              ("--distance", distance, 0 < distance <= 1e6, "must be in (0, 1000 km]"),
                              ("--count", count, count >= 1, "must be >= 1"),
                              ("--layers", layers, layers is None or layers >= 1, "must be >= 1"),
                              ("--inner-scale", inner_scale, inner_scale is None or 0 < inner_scale < 1.0,
                               "must be in (0, 1 m)"),
                              ("--inner-scale", inner_scale, inner_scale is None or wave == "plane",
                               "is modelled for plane waves only")):
        if not ok:
            raise ScenarioError(name, v, rule)
    ds, m = propagation_result(wave, wavelength, cn2, distance, count, seed=seed, layers=layers,
                               inner_scale=inner_scale)
    warn_undeclared(m, "salkit propagate")
    with RunFolder(out_dir, overwrite=overwrite) as tmp:
        write_dataset(ds, tmp / "field.nc")
        write_json_atomic(tmp / "metrics.json", m)
    out.print(f"Rytov variance {m['rytov_variance']:.4g}: scintillation index {m['scintillation_index']:.4g} "
              f"(Andrews-Phillips {m['scintillation_index_theory']:.4g}); r0 {m['r0_plane_m']:.4g} m plane, "
              f"{m['r0_spherical_m']:.4g} m spherical; {m['realisations']} realisations on {m['grid_n']}^2 at "
              f"{m['grid_dx_m'] * 1e3:.3g} mm, {m['layers']} screens", highlight=False, soft_wrap=True)
    out.print(f"wrote {Path(out_dir) / 'field.nc'} and metrics.json", highlight=False)
