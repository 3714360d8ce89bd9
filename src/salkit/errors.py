"""Errors that the command line turns into a clear message and exit status 2."""
from __future__ import annotations

from pathlib import Path


class SalkitError(Exception):
    """Base class of every error salkit reports to a user without a traceback."""

    exit_code = 2


class _NotGiven:
    """The value of a field the scenario does not give (:data:`NOT_GIVEN`)."""

    def __repr__(self) -> str:
        return "NOT_GIVEN"


#: A :class:`ScenarioError`'s value for a field that is missing: the message names the field alone
#: (``waveform.wavelength: is required``), not a value the user did not write.
NOT_GIVEN = _NotGiven()


def shown(value, limit: int = 80):
    """A value as a one-line error message shows it: an array by its type and shape, anything else
    itself where its repr fits ``limit`` characters, else by its type (and length).

    Parameters
    ----------
    value : object
        What the caller gave.
    limit : int
        Longest repr shown as it is, characters.

    Returns
    -------
    object
        ``value`` itself, or a short ``"<...>"`` description of it.

    Examples
    --------
    >>> shown("raw.nc"), shown(list(range(100)))
    ('raw.nc', '<list of 100 items>')
    """
    shape = getattr(value, "shape", None)
    if shape is not None and hasattr(value, "dtype"):  # an array's repr spans lines
        return f"<{type(value).__name__} of shape {tuple(shape)}>"
    if len(repr(value)) <= limit:
        return value
    try:
        return f"<{type(value).__name__} of {len(value)} items>"
    except TypeError:
        return f"<{type(value).__name__}>"


class ScenarioError(SalkitError):
    """A scenario field has a bad value.

    Parameters
    ----------
    field : str
        Dotted path of the field, for example ``waveform.bandwidth``.
    value : object
        The offending value (:data:`NOT_GIVEN` for a missing field).
    constraint : str
        What the value must satisfy.

    Examples
    --------
    >>> str(ScenarioError("waveform.bandwidth", -1.0, "must be greater than 0"))
    'waveform.bandwidth = -1.0: must be greater than 0'
    >>> str(ScenarioError("waveform.wavelength", NOT_GIVEN, "is required"))
    'waveform.wavelength: is required'
    """

    def __init__(self, field: str, value: object, constraint: str):
        self.field, self.value, self.constraint = field, value, constraint
        super().__init__(f"{field}: {constraint}" if value is NOT_GIVEN else f"{field} = {value!r}: {constraint}")


class SamplingError(ScenarioError):
    """Sampling that would alias (PRF, ADC rate, image grid), reported with the numbers."""


class DataFileError(SalkitError):
    """A data file is missing, truncated, of the wrong kind or holds invalid values."""


class EnvironmentProblem(SalkitError):
    """The environment, not the input, stops the work: permissions, a full disk, a busy folder,
    a scheduler that cannot be reached. Exit status 1."""

    exit_code = 1


class ResourceError(SalkitError):
    """A job too big for the machine, refused before any work (exit status 2, with the numbers)."""


def require_scenario_file(path) -> None:
    """Refuse a scenario path that is a folder or names no file (the checks that need nothing
    loaded: the command line makes them before the library loads, and the reader of the file).

    Parameters
    ----------
    path : str or path-like

    Raises
    ------
    ScenarioError
        For a folder or a missing file.
    """
    p = Path(path)
    if p.is_dir():
        raise ScenarioError("scenario", str(p), "is a folder, not a YAML file")
    if not p.is_file():
        raise ScenarioError("scenario", str(p), "file does not exist")
