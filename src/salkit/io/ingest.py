"""Outside phase histories read as they come: near-uniform float32 frequency axes, other sign
conventions, transposed arrays, float32 geometry, missing pulse times.

Every rule here either accepts an input whose meaning is unambiguous and records what it did in
the dataset's attributes, or refuses it with a :class:`~salkit.errors.DataFileError` that names
the field, the value found and the constraint.
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from ..errors import DataFileError

#: Largest accepted deviation of a frequency sample from the least-squares line through the axis,
#: as a fraction of one frequency step (float32 inputs: at least their own rounding). A float32 axis of a uniform 1.47 MHz grid at 10 GHz is off
#: by up to 514 Hz (3.5e-4 of a step), which this accepts; anything larger is not a rounding error.
FREQUENCY_FIT_TOLERANCE = 1e-3


def regularise_axis(values, name: str = "frequency", tol: float = FREQUENCY_FIT_TOLERANCE):
    """Replace a nearly uniform axis by its least-squares straight line.

    Parameters
    ----------
    values : array_like (M,)
        Axis samples (any float dtype; float32 accepted), e.g. Hz.
    name : str
        Name used in error messages.
    tol : float
        Largest accepted |residual| of the line fit, in units of one step (dimensionless). For a
        float32 (or float16) axis the limit is at least half a unit in the last place of that type
        at the axis' largest value (x 1.05), the rounding the file itself carries: an optical
        frequency axis (193 THz, 37.5 MHz steps) in float32 is quantised to 16.8 MHz.

    Returns
    -------
    axis : ndarray (M,) float64
        The fitted uniform axis, same units as ``values``.
    residual : float
        Largest |residual| of the fit, in units of one step.
    residual_abs : float
        Largest |residual| of the fit, in the units of ``values``.

    Raises
    ------
    DataFileError
        Fewer than two samples, non-finite values, a non-monotonic axis (the first offending index
        and values named) or a residual above ``tol`` steps.

    Examples
    --------
    >>> import numpy as np
    >>> f = (9.3e9 + 1.47e6 * np.arange(512)).astype(np.float32)
    >>> axis, res, res_hz = regularise_axis(f)
    >>> bool(res < 1e-3), round(float(axis[1] - axis[0]) / 1.47e6, 6)  # float32 rounding gone, step kept
    (True, 1.0)
    """
    raw = np.asarray(values)
    v = raw.astype(np.float64).ravel()
    if v.size < 2:
        raise DataFileError(f"'{name}' has {v.size} sample(s); at least 2 are needed")
    if not np.all(np.isfinite(v)):
        i = int(np.flatnonzero(~np.isfinite(v))[0])
        raise DataFileError(f"'{name}' holds a non-finite value at index {i}")
    d = np.diff(v)
    sgn = np.sign(np.median(d))
    bad = np.flatnonzero(np.sign(d) != sgn) if sgn != 0 else np.array([0])
    if bad.size:
        i = int(bad[0])
        raise DataFileError(f"'{name}' must be strictly monotonic: sample {i} = {v[i]!r} and sample "
                            f"{i + 1} = {v[i + 1]!r} ({bad.size} such step(s))")
    n = np.arange(v.size, dtype=np.float64) - (v.size - 1) / 2.0
    slope = float(np.dot(n, v - v.mean()) / np.dot(n, n))
    fit = v.mean() + slope * n
    res_abs = float(np.max(np.abs(v - fit)))
    res = res_abs / abs(slope)
    limit = tol * abs(slope)
    why = f"{tol:g} of a step"
    if raw.dtype.kind == "f" and raw.dtype.itemsize < 8:
        # the file's own rounding: half a unit in the last place at the largest value
        half_ulp = 0.5 * float(np.spacing(np.abs(raw).max().astype(raw.dtype)))
        if 1.05 * half_ulp > limit:
            limit, why = 1.05 * half_ulp, f"half a {raw.dtype} unit in the last place ({half_ulp:.6g})"
    if res_abs > limit:
        raise DataFileError(f"'{name}' is not uniformly spaced: the largest deviation from a straight "
                            f"line is {res_abs:.6g} ({res:.3g} of the {abs(slope):.6g} step); at most "
                            f"{why} is accepted as rounding")
    return fit, res, res_abs


def normalise_phase_history(ds: xr.Dataset, source: str = "dataset") -> xr.Dataset:
    """Bring an outside phase-history dataset into salkit's form (docs/data-format.md).

    Accepted without loss of meaning, and recorded in the attributes:

    * ``signal`` with dims (frequency, slow_time): transposed;
    * complex128 or float32 geometry: cast to complex64 / float64;
    * a frequency axis within :data:`FREQUENCY_FIT_TOLERANCE` of a line: replaced by the line
      (``frequency_fit_residual_steps``, ``frequency_fit_residual``, Hz);
    * ``phase_sign = +1`` (data written as exp(+j 4 pi f dR / c)): conjugated to salkit's
      exp(-j ...), ``phase_sign`` then set to -1 and ``phase_sign_converted = 1``;
    * no ``slow_time`` coordinate: the pulse index is used (``slow_time_units = "pulse"``).

    Parameters
    ----------
    ds : xarray.Dataset
        ``salkit_kind = "phase_history"`` dataset.
    source : str
        File name or description, for error messages.

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    DataFileError
        Wrong shapes, missing fields, a real-valued signal, a bad frequency axis or an unknown
        ``phase_sign``.
    """
    for n in ("signal", "position", "reference_range"):
        if n not in ds.variables:
            raise DataFileError(f"{source}: phase_history lacks the variable '{n}'")
    sig = ds["signal"]
    if sig.ndim != 2:
        raise DataFileError(f"{source}: 'signal' has {sig.ndim} dimension(s) {sig.dims}; expected 2 "
                            "(slow_time, frequency)")
    if set(sig.dims) != {"slow_time", "frequency"}:
        raise DataFileError(f"{source}: 'signal' has dims {sig.dims}; expected ('slow_time', 'frequency')")
    out = ds.copy()
    attrs = dict(ds.attrs)
    if sig.dims == ("frequency", "slow_time"):
        out["signal"] = sig.transpose("slow_time", "frequency")
        attrs["signal_transposed"] = 1
    if not np.iscomplexobj(sig.values):
        raise DataFileError(f"{source}: 'signal' must be complex (I/Q phase history), got {sig.dtype}")
    P, M = out["signal"].shape
    if "frequency" not in out.variables:
        raise DataFileError(f"{source}: phase_history lacks the coordinate 'frequency' (Hz)")
    pos = np.asarray(out["position"].values)
    ref = np.asarray(out["reference_range"].values)
    if pos.shape != (P, 3):
        raise DataFileError(f"{source}: 'position' has shape {pos.shape}; expected ({P}, 3) for "
                            f"{P} pulses (x, y, z in m)")
    if ref.shape != (P,):
        raise DataFileError(f"{source}: 'reference_range' has shape {ref.shape}; expected ({P},)")
    if P < 2 or M < 2:
        raise DataFileError(f"{source}: 'signal' has shape {(P, M)}; at least 2 pulses and 2 "
                            "frequency samples are needed")
    f_in = out["frequency"].values
    fit, res, res_abs = regularise_axis(f_in, "frequency")
    attrs["frequency_fit_residual_steps"] = res
    attrs["frequency_fit_residual"] = res_abs
    attrs["frequency_input_dtype"] = str(np.asarray(f_in).dtype)
    sign = int(attrs.get("phase_sign", -1))
    if sign not in (-1, 1):
        raise DataFileError(f"{source}: attribute phase_sign = {attrs.get('phase_sign')!r}; must be -1 "
                            "(exp(-j 4 pi f dR/c), salkit's) or +1 (conjugated on reading)")
    data = np.asarray(out["signal"].values).astype(np.complex64, copy=False)
    if sign == 1:
        data = np.conj(data)
        attrs["phase_sign"] = -1
        attrs["phase_sign_converted"] = 1
    if pos.dtype != np.float64 or ref.dtype != np.float64:
        attrs["geometry_input_dtype"] = str(pos.dtype if pos.dtype != np.float64 else ref.dtype)
    coords = {"frequency": ("frequency", fit, {"units": "Hz"}), "xyz": ("xyz", ["x", "y", "z"])}
    if "slow_time" in out.coords:
        st = np.asarray(out["slow_time"].values, dtype=np.float64)
    else:
        st = np.arange(P, dtype=np.float64)
        attrs["slow_time_units"] = "pulse"
    coords["slow_time"] = ("slow_time", st, {"units": "s" if "slow_time_units" not in attrs else "1"})
    new = xr.Dataset(
        {"signal": (("slow_time", "frequency"), data),
         "position": (("slow_time", "xyz"), pos.astype(np.float64)),
         "reference_range": (("slow_time",), ref.astype(np.float64))},
        coords=coords, attrs=attrs)
    for name, var in out.data_vars.items():  # keep anything else the file carries
        if name not in new.variables and "frequency" not in var.dims:
            new[name] = var
    return new


__all__ = ["FREQUENCY_FIT_TOLERANCE", "normalise_phase_history", "regularise_axis"]
