"""Commands that look at things: ``salkit info`` (a file or a scenario as typed JSON with units),
``salkit verify`` (a run folder against its manifest) and ``salkit examples``."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

from .app import _guard, out
from .options import _examples_dir, _preflight
from ..units import FLAGS

#: Attributes stored as 0/1 (NetCDF has no booleans) that mean yes/no.
FLAG_KEYS = FLAGS


def _typed(d):
    """JSON-ready values: NumPy scalars and arrays as numbers and lists, flags as booleans."""
    import numpy as np
    if isinstance(d, dict):
        return {k: (_flag(v) if k in FLAG_KEYS else _typed(v)) for k, v in d.items()}
    if isinstance(d, (list, tuple)):
        return [_typed(v) for v in d]
    if isinstance(d, np.ndarray):
        return d.tolist()
    if isinstance(d, np.generic):
        return d.item()
    return d


def _flag(v):
    """A 0/1 flag (NetCDF stores no booleans; some files hold it as the text "0" or "1") as a boolean."""
    import numpy as np
    if isinstance(v, (bool, np.bool_, int, np.integer)):
        return bool(v)
    if isinstance(v, str) and v.strip().lower() in ("0", "1", "true", "false"):
        return v.strip().lower() in ("1", "true")
    return v


def _eng(v: float, unit: str, digits: int = 4) -> str:
    """``v`` in ``unit`` with an SI prefix (1.55e-06 m -> '1.55 um')."""
    import math
    if v == 0 or not math.isfinite(v):
        return f"{v:g} {unit}"
    for f, p in ((1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k"), (1, ""), (1e-2, "c") if unit == "m" else (1, ""),
                 (1e-3, "m"), (1e-6, "u"), (1e-9, "n")):
        if abs(v) >= f * (1 - 1e-9):
            return f"{v / f:.{digits}g} {p}{unit}"
    return f"{v:.{digits}g} {unit}"


def _scan(ds) -> dict:
    """Read every variable of a lazily opened file a block at a time: each chunk's checksum is
    verified as it is read (a corrupt chunk raises, naming the file and the variable); the brightest
    sample of the image or signal is found on the way."""
    import numpy as np

    from ..io.reading import lazy_reads
    from ..metrics.image import brightest_pixel
    from ..resources import size_text
    found = {}
    for name, v in ds.data_vars.items():
        if v.ndim == 2 and v.dtype.kind == "c":  # read a chunk at a time, each chunk's checksum verified
            at = brightest_pixel(v)
            with lazy_reads(name, ds.encoding.get("source")):
                best = float(np.abs(np.asarray(v[at[0], at[1]].values)))
            found[name] = {"peak": best, "at": at, "size": size_text(v.nbytes)}
        else:
            with lazy_reads(name, ds.encoding.get("source")):
                np.asarray(v.values)
    return found


def _summary_lines(d: dict, ds, found: dict) -> list[str]:
    """A short human description of a data file (:func:`info`)."""
    import numpy as np
    kind = d.get("kind", "unknown")
    if "salkit_version" in d or "salkit_format" in d:
        lines = [f"{d['file']}: salkit {kind} file (format {d.get('salkit_format', '?')}, written by salkit "
                 f"{d.get('salkit_version', '?')})"]
    else:  # an outside file salkit reads by its variables (docs/data-format.md)
        lines = [f"{d['file']}: {kind if kind != 'unknown' else 'a'} file not written by salkit (no salkit_format "
                 "attribute)"]
    for name, v in ds.data_vars.items():
        if name in found:
            ch = f", chunks {' x '.join(map(str, d['image_chunks']))}" if name == "image" and "image_chunks" in d else ""
            lines.append(f"  {name}: {' x '.join(f'{n} {dim}' for n, dim in zip(v.shape, v.dims))} {v.dtype} "
                         f"({found[name]['size']}{ch})")
    for dim in ("azimuth", "range"):
        if dim in ds.coords and ds.sizes[dim] > 1:
            c = np.asarray(ds[dim].values, np.float64)
            lines.append(f"  {dim}: {c[0]:.4g} .. {c[-1]:.4g} m, pixel {_eng(float(c[1] - c[0]), 'm')}")
    if "slow_time" in ds.coords and ds.sizes["slow_time"] > 1:
        t = np.asarray(ds["slow_time"].values, np.float64)
        lines.append(f"  slow time: {ds.sizes['slow_time']} pulses over {_eng(float(t[-1] - t[0]), 's')}"
                     + (f", PRF {_eng(float(d['prf']), 'Hz')}" if "prf" in d else ""))
    if "fast_time" in ds.coords and ds.sizes["fast_time"] > 1:
        lines.append(f"  fast time: {ds.sizes['fast_time']} samples"
                     + (f" at {_eng(float(d['adc_rate']), 'Hz')}" if "adc_rate" in d else ""))
    waves = []
    if "wavelength" in d:
        waves.append(f"wavelength {_eng(float(d['wavelength']), 'm')}")
    if "frequency_min" in d and "frequency_max" in d:
        waves.append(f"frequencies {_eng(float(d['frequency_min']), 'Hz', 7)} .. {_eng(float(d['frequency_max']), 'Hz', 7)}")
    if "bandwidth" in d:
        waves.append(f"bandwidth {_eng(float(d['bandwidth']), 'Hz')}")
    if waves:
        lines.append("  " + ", ".join(waves))
    how = [f"{k} {d[k]}" for k in ("algorithm", "accuracy", "window", "plane", "mode") if k in d]
    if how:
        lines.append("  " + ", ".join(how))
    if "resolution_range" in d:
        lines.append(f"  resolution: range {_eng(float(d['resolution_range']), 'm')}, azimuth "
                     f"{_eng(float(d.get('resolution_azimuth', float('nan'))), 'm')}")
    for name, f in found.items():
        i, j = f["at"]
        where = []
        for dim, idx in zip(ds[name].dims, (i, j)):
            if dim in ds.coords:
                unit = "m" if dim in ("azimuth", "range") else "s"
                where.append(f"{dim} {_eng(float(ds[dim].values[idx]), unit)}")
            else:
                where.append(f"{dim} {idx}")
        lines.append(f"  brightest {name} sample: |{name}| {f['peak']:.4g} at pixel ({i}, {j}): {', '.join(where)}")
    lines.append("  checksums: " + _checksum_line(ds))
    return lines


def _unchecked(ds) -> list[str]:
    """The numeric variables of ``ds`` stored without a checksum (HDF5's fletcher32 filter)."""
    return [str(k) for k, v in ds.variables.items() if v.dtype.kind in "biufc" and v.encoding.get("fletcher32") is False]


def _checksum_line(ds) -> str:
    """What :func:`info` can say of the file's checksums, after reading every chunk."""
    none = _unchecked(ds)
    if not none:
        return "verified (fletcher32 on every variable; every chunk read)"
    if len(none) == sum(v.dtype.kind in "biufc" for v in ds.variables.values()):
        return "none in this file (no fletcher32 filter): every chunk read, nothing to verify it against"
    return f"verified where stored (every chunk read); none on {', '.join(none)}"


def _with_units(d: dict) -> dict:
    """``d`` with a ``units`` map: every key whose unit is known (:func:`salkit.units.unit_of`)."""
    from ..units import unit_of
    def numeric(v):
        return (isinstance(v, (int, float)) and not isinstance(v, bool)) or (
            isinstance(v, list) and bool(v) and all(numeric(x) for x in v))
    units = {k: unit_of(k) for k, v in d.items() if numeric(v) and unit_of(k)}
    return {**d, "units": units}


def _sweep_info(path: Path, as_json: bool) -> None:
    """`salkit info` of a sweep file: its base scenario, axes, points, realisations and metrics, every
    point checked as `salkit sweep` checks them before any work."""
    from ..studies.spec import resolve_request
    from ..systems.study import prepare
    import os
    request = resolve_request(path)
    sc, plan, invalid = prepare(request)
    base = os.path.normpath(request.scenario)
    d = {"name": request.name or path.stem, "kind": "sweep", "description": request.description,
         "scenario": base, "sets": list(request.sets), "axes": plan.definition()["axes"],
         "zip": plan.zipped, "points": plan.n_points, "realisations": plan.realisations,
         "runs": (plan.n_points - len(invalid)) * plan.realisations,
         "metrics": list(plan.metrics) or "every numeric metric", "invalid_points": {str(i): why for i, why in invalid.items()}}
    if as_json:
        out.print_json(json.dumps(d))
        return
    lines = [f"{path}: sweep file '{d['name']}' over {base} ({sc.kind})"]
    if d["description"]:
        lines.append(f"  {d['description']}")
    for a in d["axes"]:
        vals = a["values"]
        shown = ", ".join(f"{v:.4g}" if isinstance(v, float) else str(v) for v in vals[:6]) + (", ..." if len(vals) > 6 else "")
        lines.append(f"  {a['field']}: {len(vals)} values ({a['scale']}): {shown}")
    lines.append(f"  {d['points']} points{' (zipped)' if d['zip'] else ''} x {d['realisations']} realisation"
                 f"{'s' if d['realisations'] != 1 else ''}: {d['runs']} runs; metrics: "
                 f"{', '.join(d['metrics']) if isinstance(d['metrics'], list) else d['metrics']}")
    for i, why in invalid.items():
        lines.append(f"  invalid point {i} ({', '.join(plan.overrides(i))}): {why}")
    for line in lines:
        out.print(line, highlight=False, soft_wrap=True)


@_guard
def info(path: Path = typer.Argument(..., metavar="PATH", help="a salkit NetCDF file, a scenario YAML or a sweep file"),
         as_json: bool = typer.Option(False, "--json", help="everything as JSON, for machines")):
    """Describe a data file (kind, sizes, grid, frequencies, brightest sample; every chunk read and its
    checksum verified: a corrupt file exits 2), a scenario with its derived quantities, or a sweep file
    (its axes, points and runs, every point checked). ``--json``:
    the same as JSON, numbers typed, flags as true/false, a "units" map for every quantity with a unit."""
    yaml_file = path.suffix.lower() in (".yaml", ".yml")
    if yaml_file:
        from ..studies.spec import is_sweep_file
        if is_sweep_file(path):
            return _sweep_info(path, as_json)
    if yaml_file:
        from ..geometry import build_collection, check_sampling, resolution_theory
        from ..params import load_scenario
        sc = load_scenario(path)
        if sc.is_downlooking:
            from ..geometry.downlooking import design
            dd = design(sc.experiment)
            d = {"name": sc.name, "kind": "downlooking", **dd.as_dict(), "warnings": list(dd.warnings)}
        else:
            _preflight(sc)
            col = build_collection(sc)
            res = resolution_theory(sc, col)
            kind = sc.experiment.kind if sc.experiment is not None else "sal"
            d = {"name": sc.name, "kind": kind, "pulses": col.n_pulses, "slant_range_m": sc.platform.slant_range,
                 "resolution_range_m": res["range"], "resolution_azimuth_m": res["azimuth"],
                 "aperture_length_m": res["aperture_length"]}
            if sc.experiment is None:  # an experiment checks the sampling of what it images itself
                d.update({f"sampling_{k}": v for k, v in check_sampling(sc, col).as_dict().items()})
            else:
                d["sampling"] = f"checked by the {kind} experiment for what it images"
    else:
        from ..io import describe, open_dataset
        d = describe(path)
        ds = open_dataset(path, lazy=True)
        try:
            found = _scan(ds)
            lines = _summary_lines(d, ds, found)
            missing = _unchecked(ds)
        finally:
            ds.close()
        d["checksums_verified"] = not missing  # every chunk was read: a failed checksum would have raised
        if missing:
            d["checksums_missing"] = missing
        for name, f in found.items():
            d[f"brightest_{name}_index"] = list(f["at"])
            d[f"brightest_{name}_magnitude"] = f["peak"]
        if not as_json:
            for line in lines:
                out.print(line, highlight=False, soft_wrap=True)
            return
    if not as_json and path.suffix.lower() in (".yaml", ".yml"):
        from ..units import unit_of
        typed = _typed(d)
        for k, v in typed.items():
            if isinstance(v, float):
                v = f"{v:.6g}"
            elif isinstance(v, list):
                v = ", ".join(map(str, v))
            unit = unit_of(k) if not isinstance(typed[k], (bool, str)) else ""
            out.print(f"  {k:<30} {v} {unit}".rstrip(), highlight=False, soft_wrap=True)
        return
    out.print_json(json.dumps(_with_units(_typed(d))))


@_guard
def verify(folder: Path = typer.Argument(..., metavar="DIR", help="an output folder of salkit run / focus")):
    """Check every file of an output folder against its manifest.json (size and SHA-256)."""
    from ..errors import DataFileError
    from ..io.runfolder import verify as verify_folder
    r = verify_folder(folder)
    for x in r["extra"]:
        out.print(f"[yellow]not in the manifest:[/] {x}", highlight=False)
    if not r["ok"]:
        raise DataFileError(f"{folder}: " + "; ".join(r["problems"]))
    out.print(f"{folder}: {r['files']} files match manifest.json", highlight=False)


@_guard
def examples(copy_to: Optional[Path] = typer.Option(None, "--copy", metavar="DIR", help="copy the examples into this folder"),
             overwrite: bool = typer.Option(False, "--overwrite", help="replace files that differ from the shipped ones")):
    """List the shipped example scenarios and sweep files (and optionally copy them all, sweeps/ too,
    so that every command the README runs works from the copy)."""
    import yaml
    d = _examples_dir()
    files = sorted(d.glob("*.yaml")) + sorted((d / "sweeps").glob("*.yaml"))
    for f in files:
        try:
            desc = (yaml.safe_load(f.read_text()) or {}).get("description", "")
        except yaml.YAMLError:
            desc = "(unreadable)"
        out.print(f"[bold]{f.relative_to(d).as_posix()}[/]  {' '.join(str(desc).split())}", highlight=False)
    if copy_to is not None:
        from ..io.writing import write_text_atomic
        if copy_to.exists() and not copy_to.is_dir():
            from ..errors import ScenarioError
            raise ScenarioError("--copy", str(copy_to), "names an existing file; give a folder")
        copied, kept = 0, []
        for f in files:
            dst = copy_to / f.relative_to(d)
            text = f.read_text()
            if dst.exists() and dst.read_text() != text and not overwrite:
                kept.append(f.relative_to(d).as_posix())
                continue
            write_text_atomic(dst, text)
            copied += 1
        out.print(f"copied {copied} examples to {copy_to}")
        if kept:
            out.print(f"[yellow]kept[/] {len(kept)} edited file(s) ({', '.join(kept)}); --overwrite replaces them",
                      highlight=False)
