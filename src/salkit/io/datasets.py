"""Labelled datasets (xarray) for raw phase histories and focused images; NetCDF4/HDF5 files.

See ``docs/data-format.md`` for the specification. Complex data are stored as the HDF5 compound
type {r, i} (the nc-complex convention), which ``xarray.open_dataset`` reads back as complex
through the h5netcdf engine.
"""
from __future__ import annotations

import json
import os
import tempfile
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import lazy_loader as _lazy
import numpy as np
import yaml
import xarray as xr

from ..errors import DataFileError
from .. import __version__
from ..params.scenario import dump_scenario
from ..errors import EnvironmentProblem
import io
import errno as _errno
from .ingest import normalise_phase_history

_h5netcdf = _lazy.load("h5netcdf", suppress_warning=True)

FORMAT_VERSION = "1.0"


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


def finish_atomic(tmp: str, path: Path) -> None:
    """Give a temporary file ordinary permissions (0666 less the umask), flush it, rename it.

    Parameters
    ----------
    tmp : Path
        The complete temporary file.
    path : Path
        Its final name.
    """
    os.chmod(tmp, 0o666 & ~_umask())
    with open(tmp, "rb") as fh:
        os.fsync(fh.fileno())
    os.replace(tmp, path)
RAW_KINDS = ("raw", "phase_history")


def clean_attrs(attrs: dict) -> dict:
    """Attributes NetCDF can store: None dropped, booleans as 0/1, sequences as float64 arrays.

    Parameters
    ----------
    attrs : dict

    Returns
    -------
    dict
    """
    out = {}
    for k, v in attrs.items():
        if v is None:
            continue
        if isinstance(v, bool):
            v = int(v)
        if isinstance(v, (list, tuple)):
            v = np.asarray(v, dtype=np.float64)
        out[k] = v
    return out


def salkit_version() -> str:
    """The installed salkit version (for file attributes).

    Returns
    -------
    str
    """
    return __version__


def make_raw_dataset(signal: np.ndarray, collection, fast_time: np.ndarray, scenario,
                     signal_units: str = "reflectivity", noise: bool = False) -> xr.Dataset:
    """Build the raw (dechirped fast-time) dataset of a simulated collection.

    Parameters
    ----------
    signal : ndarray (P, N) complex64
        Dechirped samples; ``fast_time`` is relative to the reference delay 2*R_ref/c.
    collection : Collection
    fast_time : ndarray (N,)
        s.
    scenario : Scenario
    signal_units : {"reflectivity", "shot_noise"}
    noise : bool
        Whether noise was added.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind = raw`` (docs/data-format.md).
    """

    w, rx = scenario.waveform, scenario.receiver
    ds = xr.Dataset(
        data_vars={
            "signal": (("slow_time", "fast_time"), signal.astype(np.complex64, copy=False),
                       {"long_name": "dechirped I/Q signal", "units": signal_units}),
            "position": (("slow_time", "xyz"), collection.positions,
                         {"long_name": "antenna phase centre", "units": "m"}),
            "velocity": (("slow_time", "xyz"), collection.velocity, {"units": "m/s"}),
            "reference_range": (("slow_time",), collection.reference_range,
                                {"long_name": "dechirp reference range (one way)", "units": "m"}),
            "boresight": (("slow_time", "xyz"), collection.boresight, {"units": "1"}),
        },
        coords={
            "slow_time": ("slow_time", collection.slow_time, {"units": "s"}),
            "fast_time": ("fast_time", fast_time, {"units": "s",
                                                   "long_name": "time after the reference delay"}),
            "xyz": ("xyz", ["x", "y", "z"]),
        },
        attrs=clean_attrs({
            "salkit_kind": "raw",
            "salkit_format": FORMAT_VERSION,
            "salkit_version": salkit_version(),
            "wavelength": w.wavelength,
            "carrier_frequency": w.carrier_frequency,
            "chirp_rate": w.rate,
            "bandwidth": w.bandwidth,
            "pulse_width": w.pulse_width,
            "prf": w.prf,
            "nonlinearity": list(w.nonlinearity) if w.nonlinearity else None,
            "adc_rate": rx.adc_rate,
            "iq": rx.iq,
            "rvp_removed": 0,
            "mode": scenario.platform.mode,
            "real_aperture": scenario.platform.real_aperture,
            "track": collection.track,
            "center_position": collection.center_position,
            "scene_center": [0.0, 0.0, 0.0],
            "signal_units": signal_units,
            "noise_added": noise,
            "origin_llh": list(scenario.scene.origin) if scenario.scene.origin is not None else None,
            "scenario": dump_scenario(scenario),
        }),
    )
    return ds


def make_image_dataset(image: np.ndarray, az: np.ndarray, rg: np.ndarray, plane, attrs: dict,
                       truth: np.ndarray | None = None) -> xr.Dataset:
    """Build a focused-image dataset.

    Parameters
    ----------
    image : ndarray (n_az, n_rg) complex
    az, rg : ndarray
        Azimuth and range coordinates of the pixels in the image plane, m, from the scene centre.
    plane : ImagePlane
        Origin and unit axes of the image plane in the scene frame.
    attrs : dict
        Parameters to carry (algorithm, window, wavelength, resolutions, scenario...).
    truth : ndarray (T, 2), optional
        Expected azimuth/range positions of point targets, m.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind = image`` (docs/data-format.md).
    """
    data = {"image": (("azimuth", "range"), image.astype(np.complex64, copy=False),
                      {"long_name": "focused complex image", "units": "1"})}
    if truth is not None and len(truth):
        data["target_azimuth"] = (("target",), truth[:, 0], {"units": "m"})
        data["target_range"] = (("target",), truth[:, 1], {"units": "m"})
    a = dict(attrs)
    a.update({"salkit_kind": "image", "salkit_format": FORMAT_VERSION, "salkit_version": salkit_version(),
              "plane_origin": plane.origin - (plane.origin @ plane.azimuth) * plane.azimuth
              - (plane.origin @ plane.range) * plane.range,
              "azimuth_axis": plane.azimuth, "range_axis": plane.range})
    return xr.Dataset(
        data_vars=data,
        coords={"azimuth": ("azimuth", np.asarray(az, np.float64), {"units": "m"}),
                "range": ("range", np.asarray(rg, np.float64), {"units": "m"})},
        attrs=clean_attrs(a),
    )


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


class ChunkedFileWriter:
    """One large variable written block by block into a chunked NetCDF4/HDF5 file, never whole in
    memory (an image tile by tile, a raw signal a block of pulses at a time).

    The dataset's other variables, coordinates and attributes (``template``) are written first to a
    temporary name beside ``path``; the variable ``name`` (``dims``, complex64) is created with
    ``chunks`` and a fletcher32 checksum, filled by :meth:`write`, and the file renamed onto
    ``path`` by :meth:`close`; :meth:`discard` (or leaving a ``with`` block by an exception)
    removes it, so nothing half-written is left. The result reads like any salkit file
    (:func:`open_dataset`, lazily with ``lazy=True``).

    Parameters
    ----------
    path : path
    template : xarray.Dataset
        The dataset without ``name``, its dimensions holding ``dims`` (their sizes are the
        variable's).
    name : str
    dims : (str, str)
    chunks : (int, int)
        Chunk shape (a tile, a block of pulses).
    attrs : dict, optional
        Attributes of the variable.
    """

    def __init__(self, path, template: xr.Dataset, name: str, dims, chunks, attrs: dict | None = None):
        self.path = Path(path)
        self.tmp = self.path.with_name(f".{self.path.name}.tmp-{os.getpid()}")
        self.file = None
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                template.to_netcdf(self.tmp, engine="h5netcdf", invalid_netcdf=True,
                                   encoding=_checksum_encoding(template))
            self.file = _h5netcdf.File(self.tmp, "a", invalid_netcdf=True)
            shape = tuple(template.sizes[d] for d in dims)
            ch = tuple(max(1, min(int(c), n)) for c, n in zip(chunks, shape))
            self.vars = {}
            self.create(name, dims, ch, attrs)
            self.var = self.vars[name]
        except OSError as e:
            self.discard()
            raise EnvironmentProblem(f"cannot write {self.path}: {_os_reason(e)}") from None

    def create(self, name: str, dims, chunks, attrs: dict | None = None) -> None:
        """Create one more chunked complex64 variable on existing dimensions, filled by :meth:`write`."""
        shape = tuple(self.file.dimensions[d].size for d in dims)
        ch = tuple(max(1, min(int(c), n)) for c, n in zip(chunks, shape))
        var = self.file.create_variable(name, tuple(dims), dtype=np.complex64, chunks=ch, fletcher32=True)
        for k, v in (attrs or {}).items():
            var.attrs[k] = v
        self.vars[name] = var

    def write(self, i0: int, j0: int, block: np.ndarray, name: str | None = None) -> None:
        """Store a block at offsets (``i0``, ``j0``) of the variable (default the first one)."""
        var = self.var if name is None else self.vars[name]
        try:
            var[i0:i0 + block.shape[0], j0:j0 + block.shape[1]] = np.asarray(block, np.complex64)
        except OSError as e:
            self.discard()
            raise EnvironmentProblem(f"cannot write {self.path}: {_os_reason(e)}") from None

    def add(self, name: str, dims, values: np.ndarray, attrs: dict | None = None) -> None:
        """Add a small variable on existing dimensions (known only once the blocks are written)."""
        v = self.file.create_variable(name, tuple(dims), data=np.asarray(values), fletcher32=True)
        for k, a in (attrs or {}).items():
            v.attrs[k] = a

    def close(self, attrs: dict | None = None) -> Path:
        """Add ``attrs`` to the file's attributes, close it and rename it onto ``path``."""
        try:
            for k, v in clean_attrs(attrs or {}).items():
                self.file.attrs[k] = v
            self.file.close()
            self.file = None
            os.chmod(self.tmp, 0o644)
            os.replace(self.tmp, self.path)
        except OSError as e:
            self.discard()
            raise EnvironmentProblem(f"cannot write {self.path}: {_os_reason(e)}") from None
        return self.path

    def discard(self) -> None:
        """Close and remove the temporary file."""
        if self.file is not None:
            try:
                self.file.close()
            except Exception:  # noqa: BLE001 - already broken: only removal matters
                pass
            self.file = None
        try:
            os.unlink(self.tmp)
        except OSError:
            pass

    def __enter__(self):
        return self

    def __exit__(self, kind, value, tb) -> None:
        if kind is not None:
            self.discard()


#: Largest chunk side of an image written tile by tile, pixels (8 MiB of complex64).
IMAGE_CHUNK = 1024


class ImageFileWriter(ChunkedFileWriter):
    """An image written tile by tile (:class:`ChunkedFileWriter` of ``image`` (azimuth, range)).

    Parameters
    ----------
    path : path
    template : xarray.Dataset
        The image dataset without ``image``.
    chunks : (int, int)
        A tile, pixels: the chunks are the tile, or :data:`IMAGE_CHUNK` a side if smaller.
    """

    def __init__(self, path, template: xr.Dataset, chunks):
        ch = tuple(min(int(c), IMAGE_CHUNK) for c in chunks)  # a window reads little more than itself
        super().__init__(path, template, "image", ("azimuth", "range"), ch,
                         {"long_name": "focused complex image", "units": "1"})


@contextmanager
def atomic_path(path: str | Path, suffix: str = ".tmp"):
    """Yield a temporary path beside ``path``; on success give it ordinary permissions, flush it
    and rename it onto ``path``; on any failure remove it, so nothing is left half-written.

    Parameters
    ----------
    path : path
        The final name.
    suffix : str
        Suffix of the temporary name.

    Yields
    ------
    Path
        The temporary path to write.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        finish_atomic(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _checksum_encoding(ds: xr.Dataset) -> dict:
    """fletcher32 on every array variable (numbers and complex; not strings or scalars)."""
    enc = {}
    for name, v in ds.variables.items():
        if v.ndim >= 1 and v.dtype.kind in "biufc" and v.size > 0:
            enc[name] = {"fletcher32": True}
    return enc


STREAMED_VARIABLE_BYTES = 16 << 20  # a complex 2-D variable larger than this is written a block at a time


def _write_streamed(ds: xr.Dataset, template: xr.Dataset, big: list, path) -> Path:
    """Write ``ds`` with its large complex variables ``big`` streamed a block of about 4 MiB at a time
    into chunked variables (:class:`ChunkedFileWriter`), so that writing adds no copy of them."""
    first, rest = big[0], big[1:]
    v = ds[first]
    rows = max(1, (4 << 20) // (8 * v.shape[1]))
    with ChunkedFileWriter(path, template, first, v.dims, (rows, v.shape[1]), attrs=dict(v.attrs)) as w:
        for name in [first, *rest]:
            var = ds[name]
            if name != first:
                w.create(name, var.dims, (rows, var.shape[1]), attrs=dict(var.attrs))
            for a in range(0, var.shape[0], rows):
                w.write(a, 0, np.asarray(var.values[a:a + rows]), name=name)
        w.close()
    return Path(path)


def write_dataset(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` to NetCDF4/HDF5 atomically (temporary file in the same folder, then rename),
    with a fletcher32 checksum on every array variable, so that corruption is detected on reading.

    Parameters
    ----------
    ds : xarray.Dataset
    path : str or Path

    Returns
    -------
    Path

    Raises
    ------
    EnvironmentProblem
        The file cannot be written (permissions, a full disk); nothing is left behind.
    """
    big = [n for n, v in ds.data_vars.items()
           if v.ndim == 2 and v.dtype == np.complex64 and v.nbytes > STREAMED_VARIABLE_BYTES]
    template = ds.drop_vars(big)
    if big and all(d in template.sizes for n in big for d in ds[n].dims):
        return _write_streamed(ds, template, big, path)
    # HDF5 is written in memory, then copied with plain file I/O: a full disk then fails in
    # Python's write (a clean OSError), never inside HDF5, whose failed flush at exit crashes the
    # interpreter. A large complex array is streamed into the file instead (_write_streamed), so that
    # writing holds no copy of it.
    buf = io.BytesIO()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds.to_netcdf(buf, engine="h5netcdf", invalid_netcdf=True, encoding=_checksum_encoding(ds))
    try:
        with atomic_path(path) as tmp:
            with open(tmp, "wb") as fh:
                fh.write(buf.getbuffer())
    except OSError as e:
        raise EnvironmentProblem(f"cannot write {path}: {_os_reason(e)}") from None
    return Path(path)


def _os_reason(e: BaseException) -> str:
    for x in (e, getattr(e, "__cause__", None), getattr(e, "__context__", None)):
        if isinstance(x, OSError) and x.errno:
            if x.errno == _errno.ENOSPC:
                return "no space left on the device"
            return os.strerror(x.errno)
    return str(e) or type(e).__name__


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write a text file atomically (EnvironmentProblem when the disk or permissions stop it).

    Parameters
    ----------
    path : path
    text : str

    Returns
    -------
    Path
    """
    try:
        with atomic_path(path) as tmp:
            with open(tmp, "w") as fh:
                fh.write(text)
    except OSError as e:
        raise EnvironmentProblem(f"cannot write {path}: {_os_reason(e)}") from None
    return Path(path)


def write_json_atomic(path: str | Path, obj: Any) -> Path:
    """Write JSON atomically (NaN written as null).

    Parameters
    ----------
    path : path
    obj : object
        JSON-serialisable (numpy numbers and arrays allowed).

    Returns
    -------
    Path
    """
    def clean(v):
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [clean(x) for x in v]
        if isinstance(v, (np.floating, float)):
            v = float(v)
            return v if np.isfinite(v) else None
        if isinstance(v, np.integer):
            return int(v)
        return v
    return write_text_atomic(path, json.dumps(clean(obj), indent=2, allow_nan=False) + "\n")


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
        if "image" in ds and "chunksizes" in ds["image"].encoding:
            info["image_chunks"] = list(ds["image"].encoding["chunksizes"])
    finally:
        ds.close()
    return info
