"""Writing salkit datasets and text: atomically (a temporary name renamed, nothing half-written),
chunked and tile by tile (:class:`ChunkedFileWriter`, :class:`ImageFileWriter`), large variables
streamed a block at a time (:func:`write_dataset`).
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
import xarray as xr

from ..errors import EnvironmentProblem
import io
import errno as _errno
from .datasets import clean_attrs

_h5netcdf = _lazy.load("h5netcdf", suppress_warning=True)


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
