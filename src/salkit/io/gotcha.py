"""AFRL GOTCHA-style MATLAB phase histories (``.mat``) as salkit phase-history datasets.

The published layout: a struct ``data`` with ``fp`` (frequency x pulse, complex, deramped to the
scene centre), ``freq`` (Hz), ``x``, ``y``, ``z`` (antenna positions per pulse, m, scene-centred),
``r0`` (range to the scene centre per pulse, m), ``th`` and ``phi`` (azimuth and elevation, deg)
and an optional ``af`` struct (``r_correct``, m, and ``ph_correct``, rad, per pulse). The AFRL
sample code focuses by multiplying with exp(+j 4 pi f dR / c), so ``fp`` follows salkit's
exp(-j 4 pi f dR / c) and is not conjugated. The ``af`` corrections are applied as the layout's
sample code does (r0 + r_correct; fp x exp(j ph_correct)) unless ``apply_af=False``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import DataFileError
import lazy_loader as _lazy
from .ingest import normalise_phase_history
from .reading import input_file
from .writing import atomic_path
_scipy_io = _lazy.load("scipy.io", suppress_warning=True)

#: Accepted spellings of each field (first found wins), lower case.
FIELDS = {"fp": ("fp", "phdata", "phase_history"), "freq": ("freq", "f", "frequency"),
          "x": ("x", "antx"), "y": ("y", "anty"), "z": ("z", "antz"), "r0": ("r0", "r_0", "range0")}


def _field(obj, names):
    keys = {k.lower(): k for k in (obj._fieldnames if hasattr(obj, "_fieldnames") else obj.keys())}
    for n in names:
        if n in keys:
            return getattr(obj, keys[n]) if hasattr(obj, "_fieldnames") else obj[keys[n]]
    return None


def read_gotcha(path: str | Path, apply_af: bool = True) -> xr.Dataset:
    """Read a GOTCHA-style ``.mat`` phase history.

    Parameters
    ----------
    path : str or Path
        MATLAB v5/v7 file with a struct ``data`` (or the fields at top level).
    apply_af : bool
        Apply the ``af`` range and phase corrections when present.

    Returns
    -------
    xarray.Dataset
        ``salkit_kind = "phase_history"``; no pulse times in the layout, so ``slow_time`` is the
        pulse index (``slow_time_units = "pulse"``).

    Raises
    ------
    DataFileError
        Unreadable file (v7.3 HDF5 included), missing fields, wrong shapes.
    """

    p = input_file(path)
    try:
        m = _scipy_io.loadmat(p, squeeze_me=True, struct_as_record=False)
    except NotImplementedError:
        raise DataFileError(f"{p}: MATLAB v7.3 (HDF5) file; save it with -v7 or convert with h5py") from None
    except Exception as e:  # noqa: BLE001 - scipy raises many kinds for bad files
        raise DataFileError(f"{p}: cannot be read as a MATLAB file: {type(e).__name__}: {e}") from None
    d = m.get("data", None)
    if d is None:
        d = {k: v for k, v in m.items() if not k.startswith("__")}
    got = {k: _field(d, names) for k, names in FIELDS.items()}
    missing = [k for k, v in got.items() if v is None]
    if missing:
        raise DataFileError(f"{p}: GOTCHA layout lacks the field(s) {missing} (expected a struct 'data' with "
                            "fp [freq x pulse], freq, x, y, z, r0)")
    fp = np.asarray(got["fp"])
    freq = np.asarray(got["freq"], dtype=np.float64).ravel()
    if fp.ndim != 2:
        raise DataFileError(f"{p}: 'fp' has shape {fp.shape}; expected (frequency, pulse)")
    if fp.shape[0] != freq.size and fp.shape[1] == freq.size:
        raise DataFileError(f"{p}: 'fp' has shape {fp.shape} with {freq.size} frequencies on its second axis; "
                            "the layout is [freq x pulse]: transpose it")
    if fp.shape[0] != freq.size:
        raise DataFileError(f"{p}: 'fp' has {fp.shape[0]} rows but 'freq' has {freq.size} values")
    P = fp.shape[1]
    pos = np.stack([np.asarray(got[k], np.float64).ravel() for k in ("x", "y", "z")], axis=1)
    r0 = np.asarray(got["r0"], np.float64).ravel()
    if pos.shape != (P, 3) or r0.shape != (P,):
        raise DataFileError(f"{p}: x, y, z and r0 must hold one value per pulse ({P}); got "
                            f"{pos.shape[0]} positions and {r0.size} ranges")
    sig = fp.T.astype(np.complex64)
    attrs = {"salkit_kind": "phase_history", "salkit_format": "1.0", "mode": "spotlight",
             "source_format": "GOTCHA .mat", "source_file": p.name, "af_applied": 0}
    af = _field(d, ("af",))
    if af is not None and apply_af:
        rc = _field(af, ("r_correct",))
        pc = _field(af, ("ph_correct",))
        if rc is not None:
            r0 = r0 + np.broadcast_to(np.asarray(rc, np.float64).ravel(), (P,))
        if pc is not None:
            sig = sig * np.exp(1j * np.broadcast_to(np.asarray(pc, np.float64).ravel(), (P,)))[:, None].astype(np.complex64)
        attrs["af_applied"] = 1
    ds = xr.Dataset(
        {"signal": (("slow_time", "frequency"), sig),
         "position": (("slow_time", "xyz"), pos),
         "reference_range": (("slow_time",), r0)},
        coords={"frequency": ("frequency", freq), "xyz": ("xyz", ["x", "y", "z"])},
        attrs=attrs)
    for k in ("th", "phi"):
        v = _field(d, (k,))
        if v is not None and np.asarray(v).size == P:
            ds[k] = (("slow_time",), np.asarray(v, np.float64).ravel(), {"units": "deg"})
    return normalise_phase_history(ds, str(p))


def write_gotcha(ph: xr.Dataset, path: str | Path) -> Path:
    """Write a phase-history dataset in the GOTCHA ``.mat`` layout (fp [freq x pulse], freq, x, y,
    z, r0, th, phi, af with zero corrections).

    Parameters
    ----------
    ph : xarray.Dataset
        ``salkit_kind = "phase_history"``.
    path : str or Path

    Returns
    -------
    Path
    """

    pos = np.asarray(ph["position"].values, np.float64)
    P = pos.shape[0]
    th = np.degrees(np.arctan2(pos[:, 1], pos[:, 0]))
    phi = np.degrees(np.arctan2(pos[:, 2], np.hypot(pos[:, 0], pos[:, 1])))
    data = {"fp": np.asarray(ph["signal"].values).T.astype(np.complex64), "freq": np.asarray(ph["frequency"].values,
            np.float64), "x": pos[:, 0], "y": pos[:, 1], "z": pos[:, 2],
            "r0": np.asarray(ph["reference_range"].values, np.float64), "th": th, "phi": phi,
            "af": {"r_correct": np.zeros(P), "ph_correct": np.zeros(P)}}
    with atomic_path(path, suffix=".mat") as tmp:
        _scipy_io.savemat(tmp, {"data": data}, do_compression=False)
    return Path(path)


__all__ = ["FIELDS", "read_gotcha", "write_gotcha"]
