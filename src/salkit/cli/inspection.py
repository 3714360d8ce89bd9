"""Commands that look at things: ``salkit info`` (a file or a scenario as typed JSON with units),
``salkit verify`` (a run folder against its manifest) and ``salkit examples``."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

from .app import _guard, out
from .options import _examples_dir, _preflight

#: Attributes stored as 0/1 (NetCDF has no booleans) that mean yes/no.
FLAG_KEYS = frozenset({"iq", "wavelength_derived", "design_wavelength_derived", "speckle", "beam_weighting",
                       "rvp_removed", "noise_added"})


def _typed(d):
    """JSON-ready values: NumPy scalars and arrays as numbers and lists, flags as booleans."""
    import numpy as np
    if isinstance(d, dict):
        return {k: (bool(v) if k in FLAG_KEYS and isinstance(v, (int, np.integer, bool, np.bool_)) else _typed(v))
                for k, v in d.items()}
    if isinstance(d, (list, tuple)):
        return [_typed(v) for v in d]
    if isinstance(d, np.ndarray):
        return d.tolist()
    if isinstance(d, np.generic):
        return d.item()
    return d


def _with_units(d: dict) -> dict:
    """``d`` with a ``units`` map: every key whose unit is known (:func:`salkit.units.unit_of`)."""
    from ..units import unit_of
    def numeric(v):
        return (isinstance(v, (int, float)) and not isinstance(v, bool)) or (
            isinstance(v, list) and bool(v) and all(numeric(x) for x in v))
    units = {k: unit_of(k) for k, v in d.items() if numeric(v) and unit_of(k)}
    return {**d, "units": units}


@_guard
def info(path: Path = typer.Argument(..., metavar="PATH", help="a salkit NetCDF file, or a scenario YAML")):
    """Describe a data file or a scenario (with its derived quantities) as JSON: numbers typed,
    flags as true/false, a "units" map for every quantity with a unit."""
    if path.suffix.lower() in (".yaml", ".yml"):
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
        from ..io import describe
        d = describe(path)
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
    """List the shipped example scenarios (and optionally copy them)."""
    import yaml
    d = _examples_dir()
    files = sorted(d.glob("*.yaml"))
    for f in files:
        try:
            desc = (yaml.safe_load(f.read_text()) or {}).get("description", "")
        except yaml.YAMLError:
            desc = "(unreadable)"
        out.print(f"[bold]{f.name}[/]  {desc}", highlight=False)
    if copy_to is not None:
        from ..io.datasets import write_text_atomic
        if copy_to.exists() and not copy_to.is_dir():
            from ..errors import ScenarioError
            raise ScenarioError("--copy", str(copy_to), "names an existing file; give a folder")
        copied, kept = 0, []
        for f in files:
            dst = copy_to / f.name
            text = f.read_text()
            if dst.exists() and dst.read_text() != text and not overwrite:
                kept.append(f.name)
                continue
            write_text_atomic(dst, text)
            copied += 1
        out.print(f"copied {copied} examples to {copy_to}")
        if kept:
            out.print(f"[yellow]kept[/] {len(kept)} edited file(s) ({', '.join(kept)}); --overwrite replaces them",
                      highlight=False)
