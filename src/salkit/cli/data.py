"""Commands on data files: ``salkit focus`` (raw or phase history into an image and its report),
``salkit export`` (an image as SICD) and ``salkit convert`` (phase histories between formats)."""
from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Optional

import typer

from .app import _Bar, _command_line, _guard, out
from .options import (NO_ORIGIN, _check_dask_options, _check_out_file, _export_sicd, _grid, _origin, _report_check, _summary,
                      apply_memory_limit)


@_guard
def focus(raw: Path = typer.Argument(..., metavar="RAW", help="raw or phase-history file: .nc, .cphd or GOTCHA .mat"),
          out_dir: Path = typer.Option(..., "--out", metavar="DIR", help="output folder (complete or absent after the run)"),
          algorithm: Optional[str] = typer.Option(None, metavar="NAME", help="the image former: {formers}"),
          accuracy: Optional[str] = typer.Option(None, metavar="LEVEL", help="standard | high (for interferometry): what each former promises at each, against the exact matched filter, is in the README's table of formers"),
          range_upsample: Optional[int] = typer.Option(None, "--range-upsample", metavar="N", help="backprojection's range-profile upsampling, 2 to 64 (default the scenario's processing.range_upsample, else the former's own: bp 6, bp_cubic and bp_fitted 16; accuracy high takes at least bp 8, the others 32): bp and bp_fitted are -74 / -88 / -98 / -111 dB against the exact matched filter at 4 / 6 / 8 / 16, bp_cubic -91 dB at 16"),
          window: Optional[str] = typer.Option(None, metavar="NAME", help="amplitude window: none | hamming | taylor"),
          nx: Optional[int] = typer.Option(None, metavar="PIXELS", help="grid size along azimuth, pixels (with --ny, --dx, --dy)"),
          ny: Optional[int] = typer.Option(None, metavar="PIXELS", help="grid size along range, pixels"),
          dx: Optional[float] = typer.Option(None, metavar="METRES", help="pixel spacing along azimuth, m (at most the resolution)"),
          dy: Optional[float] = typer.Option(None, metavar="METRES", help="pixel spacing along range, m (at most the resolution)"),
          plane: Optional[str] = typer.Option(None, metavar="NAME", help="image plane: slant | ground (alone: the default grid in that plane)"),
          autofocus: Optional[str] = typer.Option(None, metavar="NAME", help="none | pga | min-entropy (on the image) | pulse (one phase per pulse)"),
          kernel: Optional[str] = typer.Option(None, metavar="NAME", help="PGA phase-gradient kernel: pd | lumv | ev"),
          sicd: bool = typer.Option(False, "--sicd", help="also write the image as SICD (image.nitf), checked by sarkit; needs a geographic reference (the data's or --origin)"),
          origin: Optional[str] = typer.Option(None, metavar="LAT,LON,HAE", help="where the scene frame's origin lies on the earth (WGS84 deg, deg, m): the image gets its pixels' geodetic positions; default the data's own (scene.origin, a CPHD's reference point)"),
          memory_limit: Optional[str] = typer.Option(None, "--memory-limit", metavar="SIZE", help="memory budget, e.g. 512MiB or 4GiB (default: what is available): a bigger job runs in tiles of the image (bp, ffbp) and, for bp, blocks of pulses read from the .nc as needed"),
          workers: Optional[int] = typer.Option(None, metavar="N", help="form the image's tiles on a local Dask cluster of N worker processes (bp, ffbp; at least two tiles a worker)"),
          scheduler: Optional[str] = typer.Option(None, metavar="ADDRESS", help="form the tiles on an existing Dask cluster, e.g. tcp://host:8786 (each worker reads the .nc itself: a path they can all reach)"),
          overwrite: bool = typer.Option(False, "--overwrite", help="replace a non-empty --out once the new run is complete")):
    """Focus a raw file (.nc, .cphd or GOTCHA .mat) into image.nc, metrics.json, figures and report.html."""
    from ..choices import ACCURACY, AUTOFOCUS_METHODS, PGA_KERNELS, PLANES, WINDOWS, check_choice
    from ..errors import ScenarioError
    from ..report import write_run
    from ..systems.airborne import focus_file
    from ..registry import FORMERS
    if algorithm is not None:
        FORMERS.check(algorithm, "--algorithm")
    for opt, v, allowed in (("--accuracy", accuracy, ACCURACY),
                            ("--window", window, WINDOWS),
                            ("--autofocus", autofocus, AUTOFOCUS_METHODS), ("--kernel", kernel, PGA_KERNELS),
                            ("--plane", plane, PLANES)):
        if v is not None:
            check_choice(opt, v, allowed)
    from ..focus.pipeline import check_upsample
    check_upsample(range_upsample, "--range-upsample")
    from ..io import open_dataset, read_phase_data
    apply_memory_limit(memory_limit)
    if raw.suffix.lower() in (".cphd", ".mat"):
        probe = None
    else:
        probe = open_dataset(raw, lazy=True)  # the signal stays on disk until focusing reads it
    from ..io.runfolder import RunFolder
    grid = _grid(nx, ny, dx, dy, plane or "slant")
    if probe is not None and probe.attrs.get("salkit_kind") == "raw_downlooking":
        from .. import plot
        from ..focus import focus as form_image
        from ..io import write_dataset
        image = form_image(probe, algorithm=algorithm, window_name=window, grid=grid, plane=plane, accuracy=accuracy,
                           upsample=range_upsample)
        with RunFolder(out_dir, overwrite=overwrite) as tmp:
            write_dataset(image, tmp / "image.nc")
            plot.image_db(image, tmp / "image.png", title="DL-SAL eq-19 image")
        globals()["out"].print(f"wrote {Path(out_dir) / 'image.nc'}")
        return
    ds = read_phase_data(raw, lazy=True)  # NetCDF, CPHD: the signal read as focusing needs it
    llh = _origin(origin)
    if llh is not None:
        ds.attrs["origin_llh"] = llh
    if sicd and "origin_llh" not in ds.attrs:  # before any work: SICD places the image on the earth
        raise ScenarioError("--origin", None, NO_ORIGIN)
    if grid is None and plane is not None:
        src = "the scenario stored in the file" if "scenario" in ds.attrs else "the default (256 x 256 at 0.8 of the resolution)"
        out.print(f"--plane {plane} without --nx/--ny/--dx/--dy: grid size and spacing from {src}, "
                  f"in the {plane} plane", highlight=False)
    _check_dask_options(workers, scheduler)
    RunFolder(out_dir, overwrite=overwrite)._check_target()  # before any work
    with RunFolder(out_dir, overwrite=overwrite) as tmp:
        with _dask_or_not(workers, scheduler) as client, _Bar() as bar:
            result = focus_file(ds, algorithm=algorithm, window_name=window, grid=grid, progress=bar,
                                autofocus=autofocus, kernel=kernel, plane=plane, accuracy=accuracy, client=client,
                                upsample=range_upsample,
                                image_file=tmp / "image.nc")  # an image larger than memory goes there tile by tile
        m = write_run(result, tmp, command=_command_line())  # written without the cluster (its file locks)
        if sicd:
            _export_sicd(tmp / "image.nc", tmp / "image.nitf", origin)
    _summary(m, out_dir)


@contextmanager
def _dask_or_not(workers: Optional[int], scheduler: Optional[str]):
    """A Dask client when ``--workers`` or ``--scheduler`` asks for one, else None."""
    if workers is None and scheduler is None:
        yield None
        return
    from ..resources import dask_client
    with dask_client(scheduler, workers) as client:
        yield client


@_guard
def export(image: Path = typer.Argument(..., metavar="IMAGE.nc", help="salkit image file (image.nc of a run)"),
           dst: Path = typer.Argument(..., metavar="DST.nitf", help="SICD file to write (.nitf or .ntf)"),
           origin: Optional[str] = typer.Option(None, metavar="LAT,LON,HAE", help="scene centre as LAT,LON,HAE (deg, deg, m); default "
                                                "the image's origin_llh (SICD needs one)"),
           overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Export a focused image as SICD 1.3.0 (.nitf: the complex image, metadata from the image and its
    collection) or as a Cloud-Optimised GeoTIFF (.tif: the detected image of a ground-plane image on
    its map); both need a geographic reference (the image's or --origin)."""
    from ..errors import ScenarioError
    _check_out_file(dst, overwrite, "dst")
    suf = dst.suffix.lower()
    if suf not in (".nitf", ".ntf", ".tif", ".tiff"):
        raise ScenarioError("dst", str(dst), "SICD files end in .nitf or .ntf, GeoTIFFs in .tif or .tiff")
    if suf in (".tif", ".tiff"):
        _export_geotiff(image, dst, origin)
        return
    _export_sicd(image, dst, origin)


def _export_geotiff(src: Path, dst: Path, origin: Optional[str]) -> None:
    """The detected image as a COG; an --origin given here places it (and wins over the image's)."""
    from ..errors import ScenarioError
    from ..geometry.geodesy import geolocate_image
    from ..io import read_image
    from ..io.geotiff import write_geotiff
    img = read_image(src)
    llh = _origin(origin)
    if llh is None and "origin_llh" not in img.attrs:
        raise ScenarioError("--origin", None, NO_ORIGIN)
    if llh is not None:
        img.attrs.update(geolocate_image(img, llh))
    info = write_geotiff(img, dst)
    out.print(f"wrote {dst} (Cloud-Optimised GeoTIFF of |image|; corners within {info['misfit_pixels']:.2g} pixel "
              "of the affine map)", highlight=False)


@_guard
def convert(src: Path = typer.Argument(..., metavar="SRC", help="input: .nc (raw or phase history), .cphd or .mat (GOTCHA)"),
            dst: Path = typer.Argument(..., metavar="DST", help="output: .nc (phase history), .cphd or .mat"),
            origin: Optional[str] = typer.Option(None, metavar="LAT,LON,HAE", help="scene centre for CPHD as LAT,LON,HAE (deg, deg, m); "
                                                 "default the file's origin_llh (a CPHD needs one)"),
            check: bool = typer.Option(True, help="run sarkit's consistency checker on a written CPHD"),
            overwrite: bool = typer.Option(False, "--overwrite", help="replace an existing file")):
    """Convert phase histories between salkit NetCDF, CPHD and the GOTCHA .mat layout."""
    _check_out_file(dst, overwrite, "dst")
    from ..errors import ScenarioError
    from ..focus import range_compress
    from ..io import PHASE_SUFFIXES, check_cphd, read_phase_data, write_cphd, write_dataset, write_gotcha
    suf = dst.suffix.lower()
    if suf not in PHASE_SUFFIXES:
        raise ScenarioError("dst", str(dst), f"suffix must be one of {', '.join(PHASE_SUFFIXES)}")
    llh = _origin(origin)
    ds = read_phase_data(src)
    ph = range_compress(ds) if ds.attrs.get("salkit_kind") == "raw" else ds
    if suf == ".cphd":
        if llh is None and "origin_llh" not in ph.attrs:  # CPHD places the collection on the earth
            raise ScenarioError("--origin", None, NO_ORIGIN)
        write_cphd(ph, dst, origin=llh)
        if check:
            _report_check(check_cphd(dst))
            out.print("sarkit CPHD consistency check: 0 errors", highlight=False)
    elif suf == ".mat":
        write_gotcha(ph, dst)
    else:
        write_dataset(ph, dst)
    out.print(f"wrote {dst} ({ph.sizes['slow_time']} pulses x {ph.sizes['frequency']} frequencies)")
