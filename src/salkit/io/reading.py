"""Reading salkit datasets: opened eagerly or lazily, checked (kind, variables, finite values,
checksums) with errors that name the file and the variable, read a block at a time
(:func:`blocks`, :func:`lazy_reads`), and described (:func:`describe`).
"""
from __future__ import annotations

import math
from contextlib import contextmanager
from pathlib import Path

import lazy_loader as _lazy
import numpy as np
import yaml
import xarray as xr

from ..errors import DataFileError, shown
from .datasets import RAW_KINDS
from .ingest import normalise_phase_history

_h5netcdf = _lazy.load("h5netcdf", suppress_warning=True)



@contextmanager
def lazy_reads(name: str = "signal", source=None):
    """Reads of a lazily opened file (:func:`open_dataset` ``lazy=True``) inside the block: a chunk
    that fails its checksum or cannot be decoded raises :class:`DataFileError` naming the file and
    the variable, as an eager open would.

    Parameters
    ----------
    name : str
        The variable being read.
    source : path, optional
        The file (a dataset's or a lazily read variable's ``encoding["source"]``).
    """
    try:
        yield
    except OSError as e:  # h5py reports a failed filter (fletcher32) or a bad read as OSError
        where = f"{source}: " if source else ""
        raise DataFileError(f"{where}variable '{name}' fails its checksum (fletcher32) or cannot be decoded: the "
                            f"file is corrupted ({e})") from None


def blocks(values, target_bytes: int = 4 << 20, multiple: int = 1):
    """``(row, column, block)`` of a 2-D array, read a block at a time in row-major order: an array in
    memory is sliced into blocks of whole rows; a variable of a lazily opened file
    (:func:`open_dataset` ``lazy=True``) is read in blocks of whole chunks (each chunk read and
    checksummed once; a chunk row wider than ``target_bytes`` is cut into groups of chunk columns),
    and a chunk that fails its checksum raises :class:`DataFileError` naming the variable.

    Parameters
    ----------
    values : array-like (n, m)
        ndarray or ``xarray.DataArray``.
    target_bytes : int
        About this many bytes a block (at least one chunk, and ``multiple`` rows and columns).
    multiple : int
        Blocks start at multiples of this many rows and columns.

    Yields
    ------
    (int, int, ndarray)
        First row and column of the block, and the block, in memory.

    Examples
    --------
    >>> [(a, b, x.shape) for a, b, x in blocks(np.zeros((5, 3)), target_bytes=48)]
    [(0, 0, (2, 3)), (2, 0, (2, 3)), (4, 0, (1, 3))]
    """
    n, m = values.shape
    item = max(int(getattr(values.dtype, "itemsize", 8)), 1)
    enc = getattr(values, "encoding", {}) or {}
    chunks = enc.get("chunksizes") or enc.get("chunks")
    if chunks and len(chunks) == 2:
        cr, cc = (int(c) for c in chunks)
        per = max(1, target_bytes // (cr * cc * item))  # chunks a block
        cols = min(m, cc * max(1, min(per, -(-m // cc))))
        rows = cr * max(1, per // max(1, -(-cols // cc)))
    else:
        cols = m
        rows = max(1, target_bytes // (m * item))
    rows = -(-rows // multiple) * multiple
    cols = m if cols >= m else -(-cols // multiple) * multiple
    name = getattr(values, "name", None) or "image"
    for a in range(0, n, rows):
        for b in range(0, m, cols):
            with lazy_reads(str(name), enc.get("source")):
                blk = np.asarray(values[a:a + rows, b:b + cols])
            yield a, b, blk


def scenario_hint(path: str | Path) -> str:
    """``"; it is a scenario file: ..."`` where ``path`` looks like a salkit scenario (a YAML mapping
    with scenario sections), else ``""``: for the error of a command given a scenario where data are
    expected.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    str
    """
    p = Path(path)
    try:
        with open(p, "rb") as fh:
            head = fh.read(65536)
        doc = yaml.safe_load(head.decode("utf-8"))
    except Exception:  # noqa: BLE001 - binary or not YAML: not a scenario
        return ""
    sections = {"waveform", "platform", "scene", "receiver", "processing", "experiment", "sweep", "vary"}
    if not isinstance(doc, dict) or not sections & set(doc):
        return ""
    if "sweep" in doc or "vary" in doc:
        return f"; it is a sweep file: run it with `salkit sweep {p} --out DIR`"
    return (f"; it is a scenario file, not data: `salkit run {p} --out DIR` simulates and focuses it, "
            f"`salkit simulate {p} --out raw.nc` writes its raw data")


def input_file(path: str | Path) -> Path:
    """``path`` as an existing regular file to read, or a :class:`DataFileError` that says what it
    is instead (missing, a directory, a device or pipe).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    Path

    Raises
    ------
    DataFileError
    """
    p = Path(path)
    if p.is_dir():
        raise DataFileError(f"{p}: is a directory, not a file")
    if not p.exists():
        raise DataFileError(f"{p}: file does not exist")
    if not p.is_file():
        raise DataFileError(f"{p}: is not a regular file")
    return p


def open_dataset(path: str | Path, lazy: bool = False) -> xr.Dataset:
    """Open a salkit NetCDF file fully into memory (or lazily), with clear errors for bad files.

    Parameters
    ----------
    path : path
    lazy : bool
        Leave the data variables on disk, read when indexed (a block of pulses at a time by
        :class:`salkit.focus.tiles.DatasetPulses`); the file stays open while the dataset lives.
        Coordinates and the small per-pulse geometry are read now.

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    DataFileError
        For a missing, unreadable or corrupt file (a corrupt variable is named; lazily, a corrupt
        block is found when it is read).
    """
    p = input_file(path)
    try:
        if lazy:
            ds = xr.open_dataset(p, engine="h5netcdf", cache=False)  # what is read is not kept
            small = [n for n, v in ds.data_vars.items() if n not in ("signal", "image") and v.nbytes <= 64 * 2 ** 20]
            ds = ds.assign({n: ds[n].load() for n in small})
            for n in ds.data_vars:  # a lazily read variable names its file in any error
                if n not in small:
                    ds[n].encoding["source"] = str(p)
            return ds
        with xr.open_dataset(p, engine="h5netcdf") as ds:
            ds = ds.load()
    except Exception as err:  # noqa: BLE001 - truncated/corrupt files raise many types
        bad = _corrupt_variable(p)
        if bad is not None:
            raise DataFileError(f"{p}: variable '{bad}' fails its checksum (fletcher32) or cannot be decoded: "
                                "the file is corrupted") from None
        hint = scenario_hint(p)
        if hint:
            raise DataFileError(f"{p}: is not a NetCDF4/HDF5 data file{hint}") from None
        raise DataFileError(f"{p}: cannot be read as NetCDF4/HDF5 (truncated or corrupt?): "
                            f"{type(err).__name__}: {err}") from None
    return ds


def _corrupt_variable(p: Path) -> str | None:
    """Name of the first HDF5 dataset in ``p`` that cannot be read (checksum failure), if any."""
    try:
        import h5py
        with h5py.File(p, "r") as f:
            names = []
            f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
            for n in names:
                try:
                    f[n][()]
                except Exception:  # noqa: BLE001
                    return n
    except Exception:  # noqa: BLE001 - not even HDF5
        return None
    return None


def _require(ds: xr.Dataset, p, names, kind):
    for n in names:
        if n not in ds.variables:
            raise DataFileError(f"{p}: {kind} file lacks the variable '{n}'")


def _finite(ds: xr.Dataset, p, names):
    for n in names:
        v = ds[n].values
        bad = ~np.isfinite(v)
        if np.any(bad):
            idx = np.argwhere(bad)[0]
            raise DataFileError(f"{p}: variable '{n}' holds {int(bad.sum())} non-finite value(s) "
                                f"(NaN or inf), first at index {tuple(int(i) for i in idx)}")


#: A raw file's numeric attributes and what each must be, where present: (name, test, constraint).
#: The first four are required (:func:`read_raw`).
RAW_NUMBERS = (("wavelength", lambda v: v > 0, "> 0 (m)"),
               ("chirp_rate", lambda v: v != 0, "non-zero (Hz/s; its sign is the chirp's direction)"),
               ("adc_rate", lambda v: v > 0, "> 0 (Hz)"),
               ("prf", lambda v: v > 0, "> 0 (Hz)"),
               ("bandwidth", lambda v: v > 0, "> 0 (Hz)"),
               ("pulse_width", lambda v: v > 0, "> 0 (s)"),
               ("real_aperture", lambda v: v >= 0, ">= 0 (m)"),
               ("reference_delay", lambda v: True, "(s)"))


def _numeric_attrs(ds: xr.Dataset, p) -> None:
    """Refuse a raw file whose numeric attributes are not finite numbers within their bounds
    (:data:`RAW_NUMBERS`), naming the attribute, the value and the constraint."""
    for name, ok, constraint in RAW_NUMBERS:
        if name not in ds.attrs:
            continue
        raw = ds.attrs[name]
        try:
            v = float(np.asarray(raw).item())
        except (TypeError, ValueError):
            raise DataFileError(f"{p}: attribute {name} = {raw!r}: must be a finite number {constraint}") from None
        if not (math.isfinite(v) and ok(v)):
            raise DataFileError(f"{p}: attribute {name} = {v!r}: must be a finite number {constraint}")


def require_dataset(value, who: str, name: str = "raw") -> None:
    """Refuse what is not a dataset where a function takes one (a path, an array).

    Parameters
    ----------
    value : object
        What the caller gave.
    who : str
        The function, for the message.
    name : str
        The argument's name.

    Raises
    ------
    DataFileError
        Naming the function, the argument and the way to a dataset.
    """
    if not isinstance(value, xr.Dataset):
        raise DataFileError(f"{who}: {name} = {shown(value)!r}: must be an xarray.Dataset (salkit.simulate's "
                            "output, or a file opened with salkit.io.open_dataset)")


def read_raw(path: str | Path, lazy: bool = False) -> xr.Dataset:
    """Read and validate a raw phase-history file (kinds ``raw`` or ``phase_history``).

    Parameters
    ----------
    path : path
    lazy : bool
        Leave the signal on disk (:func:`open_dataset`); its values are checked block by block as
        focusing reads them (:class:`salkit.focus.tiles.DatasetPulses`).

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    DataFileError
    """
    ds = open_dataset(path, lazy=lazy)
    kind = ds.attrs.get("salkit_kind")
    if kind not in RAW_KINDS:
        raise DataFileError(f"{path}: attribute salkit_kind = {kind!r}; expected one of {RAW_KINDS}")
    if kind == "raw":
        _require(ds, path, ["signal", "position", "reference_range", "fast_time"], "raw")
        for a in ("wavelength", "chirp_rate", "adc_rate", "prf"):
            if a not in ds.attrs:
                raise DataFileError(f"{path}: raw file lacks the attribute '{a}'")
        _numeric_attrs(ds, path)
    else:
        _require(ds, path, ["signal", "position", "reference_range", "frequency"], "phase_history")
        ds = normalise_phase_history(ds, str(path))
    if ds["signal"].dtype.kind != "c":
        raise DataFileError(f"{path}: variable 'signal' must be complex, got {ds['signal'].dtype}")
    _finite(ds, path, ["position", "reference_range"] + ([] if lazy else ["signal"]))
    return ds


def read_image(path: str | Path) -> xr.Dataset:
    """Read and validate a focused-image file.

    Parameters
    ----------
    path : path

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    DataFileError
    """
    ds = open_dataset(path)
    if ds.attrs.get("salkit_kind") != "image" and "image" not in ds:
        raise DataFileError(f"{path}: not a salkit image file (no 'image' variable)")
    _require(ds, path, ["image", "azimuth", "range"], "image")
    if ds["image"].dims != ("azimuth", "range"):
        raise DataFileError(f"{path}: 'image' has dims {ds['image'].dims}; expected ('azimuth', 'range')")
    _finite(ds, path, ["image"])
    return ds


def describe(path: str | Path) -> dict:
    """Summary of a salkit file (kind, shapes, key attributes).

    Parameters
    ----------
    path : path

    Returns
    -------
    dict

    Notes
    -----
    The file is opened lazily: no array larger than 64 MiB is read (an image bigger than memory
    is described without loading it).
    """
    ds = open_dataset(path, lazy=True)
    try:
        info = {"file": str(path), "kind": ds.attrs.get("salkit_kind", "unknown"),
                "variables": {k: {"dims": list(v.dims), "dtype": str(v.dtype), "shape": list(v.shape)}
                              for k, v in ds.data_vars.items()}}
        for k, v in ds.attrs.items():
            if k == "scenario":
                continue
            info[k] = v.tolist() if isinstance(v, np.ndarray) else v
        if "image" in ds and ds["image"].encoding.get("chunksizes"):  # None: stored contiguous
            info["image_chunks"] = list(ds["image"].encoding["chunksizes"])
    finally:
        ds.close()
    return info
