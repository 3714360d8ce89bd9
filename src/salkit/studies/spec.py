"""What a sweep varies: ``FIELD=SPEC`` axes (a list of values, ``lin:START:STOP:N`` or
``log:START:STOP:N``), checked before any work."""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from ..errors import ScenarioError
from ..metrics.table import check_metric
from ..params.scenario import did_you_mean, is_sweep_document

#: Most points an axis may hold (a typo such as lin:0:1:1e6 is refused before any work).
MAX_AXIS_POINTS = 10_000


@dataclass(frozen=True)
class Axis:
    """One varied field: its dotted path (as ``--set`` names it), its values and how they are spaced.

    Parameters
    ----------
    field : str
        Scenario field, e.g. ``waveform.bandwidth``.
    values : tuple
        The values, in the field's SI unit (numbers) or choices (strings).
    scale : {"list", "lin", "log"}
        How the values were given; ``log`` draws its axis logarithmically.
    spec : str
        The SPEC as given.
    """

    field: str
    values: tuple
    scale: str
    spec: str

    @property
    def numeric(self) -> bool:
        """Whether every value is a number (the axis can carry a unit and a theory curve)."""
        return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in self.values)

    def as_dict(self) -> dict:
        """The axis as plain data (for the sweep's attributes and its checkpoint)."""
        return {"field": self.field, "spec": self.spec, "scale": self.scale, "values": list(self.values)}


def _number(text: str, what: str, item: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise ScenarioError("--vary", item, f"{what} {text!r} is not a number") from None
    if not math.isfinite(v):
        raise ScenarioError("--vary", item, f"{what} {text!r} must be finite")
    return v


def _scalar(text: str):
    """A list entry: an int or a float as Python reads them (``7.5e9`` too, which YAML 1.1 keeps as
    a string), else a YAML scalar (``true``, ``null``, a word)."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError:
        return text


def parse_vary(item: str) -> Axis:
    """Parse ``FIELD=SPEC``: ``v1,v2,...`` (YAML scalars), ``lin:START:STOP:N`` (N evenly spaced
    values, both ends included) or ``log:START:STOP:N`` (N values evenly spaced in log, START and
    STOP > 0).

    Parameters
    ----------
    item : str

    Returns
    -------
    Axis

    Raises
    ------
    ScenarioError
        Naming ``--vary``, the text and what is wrong: no ``=``, an empty field or list, N not a
        positive integer, a non-number, a log sweep through zero or negative values.

    Examples
    --------
    >>> parse_vary("waveform.bandwidth=lin:1e9:3e9:3").values
    (1000000000.0, 2000000000.0, 3000000000.0)
    >>> parse_vary("atmosphere.cn2=log:1e-15:1e-13:3").values
    (1e-15, 1e-14, 1e-13)
    >>> parse_vary("processing.algorithm=bp,pfa").values
    ('bp', 'pfa')
    """
    if "=" not in item:
        raise ScenarioError("--vary", item, "must have the form FIELD=SPEC (SPEC: v1,v2,... | lin:START:STOP:N | "
                            "log:START:STOP:N)")
    field, spec = (s.strip() for s in item.split("=", 1))
    if not field or any(not k for k in field.split(".")):
        raise ScenarioError("--vary", item, "the field path is empty or has an empty part")
    kind = spec.split(":", 1)[0]
    if kind in ("lin", "log"):
        parts = spec.split(":")
        if len(parts) != 4:
            raise ScenarioError("--vary", item, f"{kind} needs {kind}:START:STOP:N")
        start = _number(parts[1], "START", item)
        stop = _number(parts[2], "STOP", item)
        try:
            n = int(parts[3])
        except ValueError:
            n = 0
        if n <= 0 or str(n) != parts[3].strip():
            raise ScenarioError("--vary", item, f"N = {parts[3]!r} must be a positive integer")
        if n > MAX_AXIS_POINTS:
            raise ScenarioError("--vary", item, f"N = {n} exceeds {MAX_AXIS_POINTS} points on one axis")
        if kind == "log":
            if start <= 0 or stop <= 0:
                raise ScenarioError("--vary", item, "a log sweep needs START and STOP > 0 (it cannot pass through "
                                    "zero or negative values)")
            vals = np.geomspace(start, stop, n) if n > 1 else np.array([start])
        else:
            vals = np.linspace(start, stop, n) if n > 1 else np.array([start])
        # 12 significant digits: log:0.3:30:5 gives 3.0, not 2.9999999999999996
        return Axis(field, tuple(float(f"{v:.12g}") for v in vals), kind, spec)
    texts = [t.strip() for t in spec.split(",")]
    if not spec.strip() or any(not t for t in texts):
        raise ScenarioError("--vary", item, "the list of values is empty or has an empty entry")
    vals = []
    for t in texts:
        v = _scalar(t)
        if isinstance(v, float) and not math.isfinite(v):
            raise ScenarioError("--vary", item, f"value {t!r} must be finite")
        elif not isinstance(v, (int, float, str, bool)):
            raise ScenarioError("--vary", item, f"value {t!r} must be a number or a word")
        vals.append(v)
    if len(set(map(repr, vals))) != len(vals):
        raise ScenarioError("--vary", item, "repeats a value")
    return Axis(field, tuple(vals), "list", spec)


@dataclass(frozen=True)
class SweepFile:
    """A shipped or written sweep: the base scenario file and what varies.

    Parameters
    ----------
    scenario : Path
        The base scenario (relative paths are taken from the sweep file's folder).
    vary : tuple of str
        ``FIELD=SPEC`` items.
    zipped : bool
    realisations : int
    metrics : tuple of str
    sets : tuple of str
        ``--set`` overrides of the base scenario.
    description : str
    name : str
        The study's name (a sweep file's stem; empty for a sweep given by options): the report's title.
    """

    scenario: Path
    vary: tuple
    zipped: bool = False
    realisations: int = 1
    metrics: tuple = ()
    sets: tuple = ()
    description: str = ""
    name: str = ""


#: The keys a sweep file may hold.
SWEEP_KEYS = ("sweep", "scenario", "vary", "zip", "realisations", "metrics", "set", "description")


def is_sweep_file(path) -> bool:
    """Whether a YAML file is a sweep definition (its top level names ``sweep: 1``), not a scenario.

    Parameters
    ----------
    path : path

    Returns
    -------
    bool
    """
    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError):
        return False
    return is_sweep_document(data)


def read_sweep_file(path) -> SweepFile:
    """Read a sweep definition::

        sweep: 1
        description: range IRW against bandwidth
        scenario: ../spotlight_points.yaml
        vary: {waveform.bandwidth: "lin:1e9:7.5e9:7"}
        realisations: 1
        metrics: [irw_range_m]

    Parameters
    ----------
    path : path

    Returns
    -------
    SweepFile

    Raises
    ------
    ScenarioError
        Naming the key, the value and the constraint.
    """
    p = Path(path)
    data = yaml.safe_load(p.read_text(encoding="utf-8"))
    unknown = sorted(set(data) - set(SWEEP_KEYS))
    if unknown:
        raise ScenarioError(f"{p.name}: {unknown[0]}", data[unknown[0]],
                            f"is not a sweep key{did_you_mean(unknown[0], SWEEP_KEYS)}; the keys: {', '.join(SWEEP_KEYS)}")
    if data.get("sweep") != 1:
        raise ScenarioError(f"{p.name}: sweep", data.get("sweep"), "must be 1 (the sweep file format)")
    if not isinstance(data.get("scenario"), str):
        raise ScenarioError(f"{p.name}: scenario", data.get("scenario"), "must name the base scenario file")
    vary = data["vary"]
    if not isinstance(vary, dict) or not vary:
        raise ScenarioError(f"{p.name}: vary", vary, "must map fields to SPECs")
    items = tuple(f"{k}={v if isinstance(v, str) else ','.join(map(str, v))}" for k, v in vary.items())
    for m in data.get("metrics") or ():  # each a metric salkit measures (the table of metrics)
        check_metric(m, f"{p.name}: metrics")
    base = Path(data["scenario"])
    return SweepFile(base if base.is_absolute() else p.parent / base, items, bool(data.get("zip", False)),
                     int(data.get("realisations", 1)), tuple(data.get("metrics") or ()),
                     tuple(data.get("set") or ()), str(data.get("description", "")))


def resolve_request(scenario, vary=(), sets=(), zipped: bool = False, realisations: int | None = None,
                    metrics=()) -> SweepFile:
    """What to sweep, from a scenario file and options or a sweep file and options: the options'
    ``--vary`` replaces the file's for the same field, their ``--set`` come after the file's, their
    metrics (if any) replace the file's.

    Parameters
    ----------
    scenario : path
        A scenario file or a sweep file (:func:`is_sweep_file`).
    vary, sets : sequence of str
        ``FIELD=SPEC`` and ``KEY=VALUE`` items.
    zipped : bool
    realisations : int, optional
    metrics : sequence of str

    Returns
    -------
    SweepFile

    Raises
    ------
    ScenarioError
        When nothing varies, a metric is not in the table of metrics (with the nearest name), or a
        sweep file's base scenario does not exist.
    """
    for m in metrics:
        check_metric(m, "--metric")
    path = Path(scenario)
    if path.suffix.lower() in (".yaml", ".yml") and path.is_file() and is_sweep_file(path):
        sf = read_sweep_file(path)
        if not sf.scenario.exists():  # say where a relative path was looked for
            raise ScenarioError(f"{path.name}: scenario", str(sf.scenario), "file does not exist (a relative path is "
                                f"read from the sweep file's folder, {path.parent.resolve()})")
        mine = {v.split("=", 1)[0].strip() for v in vary}
        sf = SweepFile(sf.scenario, tuple(v for v in sf.vary if v.split("=", 1)[0] not in mine) + tuple(vary),
                       sf.zipped or zipped, realisations or sf.realisations, tuple(metrics) or sf.metrics,
                       sf.sets + tuple(sets), sf.description, path.stem)
    else:
        sf = SweepFile(path, tuple(vary), zipped, realisations or 1, tuple(metrics), tuple(sets))
    if not sf.vary:
        raise ScenarioError("--vary", None, "a sweep needs at least one --vary FIELD=SPEC (or a sweep file)")
    return sf
