"""Scenario files: YAML in, validated frozen objects out; ``--set`` overrides."""
from __future__ import annotations

import copy
import difflib
import typing
from pathlib import Path
from typing import Any, Iterable, Mapping

import yaml
from pydantic import BaseModel, TypeAdapter, ValidationError

from ..errors import NOT_GIVEN, EnvironmentProblem, ScenarioError, require_scenario_file, shown
from .base import FieldProblem
from .models import AnyScenario, DownlookingScenario, Scenario

_ADAPTER = TypeAdapter(AnyScenario)


#: The experiment union's tags, which pydantic puts in an error's location (not fields).
_EXPERIMENT_TAGS = ("turbulence_pga", "nonlinear_chirp", "spaceborne_geo", "downlooking")


def _model_in(annotation):
    """The pydantic model an annotation holds (through Optional, unions, lists, Annotated), or None."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in typing.get_args(annotation):
        m = _model_in(arg)
        if m is not None:
            return m
    return None


def _models_in(annotation) -> list:
    """Every pydantic model an annotation holds (the members of a union), in order."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    return [m for arg in typing.get_args(annotation) for m in _models_in(arg)]


def fields_at(parts, root=Scenario) -> list[str]:
    """The field names of the section at a location (``["waveform"]``: the waveform's fields), as a
    scenario file spells them; the top level for an empty location. Empty where the location is not
    a section.

    Parameters
    ----------
    parts : sequence of str or int
        The section's keys (list indices are skipped; an experiment kind's tag, as pydantic puts it
        in an error's location, picks that experiment's fields).
    root : pydantic model
        The scenario's model (:class:`~salkit.params.DownlookingScenario` for a down-looking one).

    Returns
    -------
    list of str

    Examples
    --------
    >>> "bandwidth" in fields_at(["waveform"])
    True
    """
    model = root
    if parts and parts[0] == "experiment" and len(parts) > 1:
        kinds = {"downlooking": DownlookingScenario}
        model = kinds.get(str(parts[1]), root)
    members: list = []
    for p in parts:
        if str(p) in _EXPERIMENT_TAGS:  # a union's tag (pydantic's location): the member of that kind
            model = next((m for m in members if m.model_fields.get("kind") is not None
                          and m.model_fields["kind"].default == str(p)), model)
            continue
        if isinstance(p, int) or str(p).isdigit():
            continue
        f = model.model_fields.get(str(p))
        m = _model_in(f.annotation) if f is not None else None
        if m is None:
            return []
        members = _models_in(f.annotation)
        model = m
    names = set(model.model_fields)
    if model is Scenario:
        names |= set(DownlookingScenario.model_fields)
    return sorted(names)


def did_you_mean(name: str, candidates) -> str:
    """`` (did you mean 'x'?)`` for the candidate nearest ``name`` (difflib), or ``""``.

    Parameters
    ----------
    name : str
        What the user wrote.
    candidates : iterable of str
        The valid names.

    Returns
    -------
    str

    Examples
    --------
    >>> did_you_mean("bandwidht", ["bandwidth", "prf"])
    " (did you mean 'bandwidth'?)"
    """
    near = difflib.get_close_matches(str(name), list(candidates), n=1, cutoff=0.6)
    return f" (did you mean '{near[0]}'?)" if near else ""


def unknown_key_error(loc, value=None, valid=None, kind: str = "sal") -> ScenarioError:
    """The error for a key that is not a field: names the key as written, the nearest valid key and the
    section's valid keys.

    Parameters
    ----------
    loc : sequence
        The key's location (``["waveform", "bandwidht"]``).
    value : object, optional
        The value given to it.
    valid : list of str, optional
        The section's field names (default :func:`fields_at` of the location's parent).
    kind : {"sal", "downlooking"}
        The scenario's model (``experiment.kind = downlooking`` has no waveform, platform, receiver
        or processing sections: its experiment block holds the whole system).

    Returns
    -------
    ScenarioError

    Examples
    --------
    >>> str(unknown_key_error(["waveform", "bandwidht"], 3e9)).split(";")[0]
    "waveform.bandwidht = 3000000000.0: 'bandwidht' is not a field of waveform (did you mean 'bandwidth'?)"
    >>> unknown_key_error(["waveform"], {"wavelength": 1.55e-6}, kind="downlooking").constraint.split(" (")[0]
    "'waveform' is not a field of a down-looking scenario"
    """
    parts = [p for p in loc if str(p) not in _EXPERIMENT_TAGS]
    key, section = str(parts[-1]), parts[:-1]
    top_down = kind == "downlooking" and not section
    if valid is None:  # the section's fields, found with the union's tags kept (which experiment)
        valid = fields_at(list(loc)[:-1], DownlookingScenario if kind == "downlooking" else Scenario)
    where = ("a down-looking scenario" if top_down else ".".join(str(p) for p in section) or "the scenario")
    hint = did_you_mean(key, [v for v in valid if v != key])
    if top_down and key in Scenario.model_fields:
        hint = (" (experiment.kind = downlooking: the experiment block holds the whole system, its optics, "
                "scan and track)")
    listed = f"; its fields: {', '.join(valid)}" if valid and len(valid) <= 16 else ""
    return ScenarioError(".".join(str(p) for p in parts), value,
                         f"'{key}' is not a field of {where}{hint}{listed}")


#: Further bad values a scenario error names after its first problem (the rest are counted), and
#: missing fields it names.
LISTED_PROBLEMS = 5
LISTED_MISSING = 8


def _short(value):
    """A value as an error message shows it: a large section by its type alone."""
    if isinstance(value, (dict, list)) and len(repr(value)) > 120:
        return f"<{type(value).__name__}>"
    return value


def _problem(e: dict) -> tuple[str, ScenarioError]:
    """One pydantic error as (its type: "extra", "missing" or "value", the ScenarioError that names
    its field, value and constraint)."""
    parts = list(e["loc"])
    kind = "sal"
    if parts and parts[0] in ("sal", "downlooking"):  # the union's tag, not a field
        kind = parts.pop(0)
    if e["type"] == "extra_forbidden":
        return "extra", unknown_key_error(parts, _short(e.get("input")), kind=kind)
    if e["type"] == "union_tag_invalid" and parts == ["experiment"]:  # a kind that does not exist
        tag = (e.get("ctx") or {}).get("tag")
        return "extra", ScenarioError("experiment.kind", tag, "is not an experiment kind"
                                      f"{did_you_mean(tag, _EXPERIMENT_TAGS)}; the kinds: {', '.join(_EXPERIMENT_TAGS)} "
                                      "(none: a SAL scenario)")
    parts = [p for i, p in enumerate(parts) if not (i and parts[i - 1] == "experiment" and p in _EXPERIMENT_TAGS)]
    problem = (e.get("ctx") or {}).get("error")
    if isinstance(problem, FieldProblem):  # a check across fields that names the field it refuses
        parts += problem.field.split(".")
    loc = ".".join(str(p) for p in parts) or "scenario"
    if e["type"] == "missing":
        msg = "is required" + (" (only experiment.kind = downlooking works without the waveform, platform, "
                               "receiver and processing sections)" if len(parts) == 1 and kind == "sal" else "")
        return "missing", ScenarioError(loc, NOT_GIVEN, msg)
    msg = problem.constraint if isinstance(problem, FieldProblem) else e["msg"]
    if msg.startswith("Value error, "):
        msg = msg[len("Value error, "):]
    value = problem.value if isinstance(problem, FieldProblem) else e.get("input")
    return "value", ScenarioError(loc, _short(value), msg)


def _format_validation(err: ValidationError) -> ScenarioError:
    """The first problem of a scenario as a ScenarioError (an unknown key first: a typo explains the
    "required" errors beside it), its constraint followed by the others: the bad values and unknown
    keys each with its own message, the missing fields by name."""
    problems = [_problem(e) for e in err.errors()]
    problems.sort(key=lambda p: p[0] != "extra")  # stable: pydantic's order otherwise
    first, rest = problems[0][1], problems[1:]
    others = [f"{e.field}: {e.constraint.split('; its fields')[0]}" if k == "extra" else str(e)
              for k, e in rest if k != "missing"]
    missing = [e.field for k, e in rest if k == "missing"]
    notes = others[:LISTED_PROBLEMS]
    if len(others) > LISTED_PROBLEMS:
        notes.append(f"{len(others) - LISTED_PROBLEMS} more")
    if missing:
        names = ", ".join(missing[:LISTED_MISSING]) + (f" and {len(missing) - LISTED_MISSING} more"
                                                       if len(missing) > LISTED_MISSING else "")
        notes.append(f"missing: {names}")
    msg = first.constraint + (f" (and {len(rest)} more problem{'s' if len(rest) > 1 else ''}: "
                              f"{'; '.join(notes)})" if rest else "")
    return ScenarioError(first.field, first.value, msg)


def require_scenario(value, name: str = "scenario") -> None:
    """Refuse what is not a parsed scenario where a function takes one: a path, a mapping, None.

    Parameters
    ----------
    value : object
        What the caller gave.
    name : str
        The argument's name, for the message.

    Raises
    ------
    ScenarioError
        Naming the argument, the value and what it must be (a path: read it with
        :func:`load_scenario`; a mapping: :func:`parse_scenario`).

    Examples
    --------
    >>> require_scenario("examples/spotlight_points.yaml")
    Traceback (most recent call last):
    ...
    salkit.errors.ScenarioError: scenario = 'examples/spotlight_points.yaml': must be a Scenario or DownlookingScenario; read a file with salkit.load_scenario(path)
    """
    if isinstance(value, (Scenario, DownlookingScenario)):
        return
    if isinstance(value, (str, Path)):
        hint = "; read a file with salkit.load_scenario(path)"
    elif isinstance(value, Mapping):
        hint = "; parse a mapping with salkit.params.parse_scenario(data)"
    else:
        hint = ""
    raise ScenarioError(name, str(value) if isinstance(value, Path) else shown(value),
                        f"must be a Scenario or DownlookingScenario{hint}")


def parse_scenario(data: Mapping[str, Any]) -> Scenario | DownlookingScenario:
    """Validate a scenario mapping into the model its ``experiment.kind`` names.

    Parameters
    ----------
    data : mapping
        The parsed YAML document.

    Returns
    -------
    Scenario or DownlookingScenario

    Raises
    ------
    ScenarioError
        Naming the field, the value and the constraint.
    """
    if not isinstance(data, Mapping):
        raise ScenarioError("scenario", type(data).__name__, "the document must be a mapping")
    try:
        return _ADAPTER.validate_python(dict(data))
    except ValidationError as err:
        raise _format_validation(err) from None


def apply_overrides(data: Mapping[str, Any], overrides: Iterable[str]) -> dict:
    """Apply ``key.path=value`` overrides (values parsed as YAML) to a scenario mapping.

    List elements are addressed by index: ``scene.points.0.x=0.3``.

    Parameters
    ----------
    data : mapping
    overrides : iterable of str

    Returns
    -------
    dict

    Raises
    ------
    ScenarioError
        For a malformed override or a path that does not exist.

    Examples
    --------
    >>> apply_overrides({"a": {"b": 1}}, ["a.b=2", "a.c=[1, 2]"])
    {'a': {'b': 2, 'c': [1, 2]}}
    """
    out = copy.deepcopy(dict(data))
    for item in overrides:
        if "=" not in item:
            raise ScenarioError("--set", item, "must have the form key.path=value")
        path, text = item.split("=", 1)
        keys = [k for k in path.strip().split(".") if k]
        if not keys:
            raise ScenarioError("--set", item, "the key path is empty")
        try:
            value = yaml.safe_load(text)
        except yaml.YAMLError:
            value = text
        node: Any = out
        for i, key in enumerate(keys[:-1]):
            if isinstance(node, list):
                try:
                    node = node[int(key)]
                except (ValueError, IndexError):
                    raise ScenarioError(".".join(keys[:i + 1]), key, "is not a valid list index") from None
            elif isinstance(node, dict):
                if node.get(key) is None:
                    node[key] = {}
                node = node[key]
            else:
                raise ScenarioError(".".join(keys[:i]), node, "is a value, not a section")
        last = keys[-1]
        if isinstance(node, list):
            try:
                node[int(last)] = value
            except (ValueError, IndexError):
                raise ScenarioError(path, last, "is not a valid list index") from None
        elif isinstance(node, dict):
            node[last] = value
        else:
            raise ScenarioError(".".join(keys[:-1]), node, "is a value, not a section")
    return out


def read_yaml(path: str | Path) -> dict:
    """Read a YAML mapping from ``path`` with clear errors.

    Parameters
    ----------
    path : path

    Returns
    -------
    dict

    Raises
    ------
    ScenarioError
        For a missing file, a folder, non-UTF-8 text, invalid YAML or a non-mapping.
    """
    require_scenario_file(path)
    p = Path(path)
    try:
        data = yaml.safe_load(p.read_text(encoding="utf-8"))
    except UnicodeDecodeError as err:
        raise ScenarioError("scenario", str(p), f"is not UTF-8 text (byte {err.start}: {err.reason}); "
                            "a scenario is a YAML file") from None
    except yaml.YAMLError as err:
        raise ScenarioError("scenario", str(p), f"is not valid YAML ({err})") from None
    except OSError as err:
        raise EnvironmentProblem(f"cannot read {p}: {err.strerror or err}") from None
    if not isinstance(data, dict):
        raise ScenarioError("scenario", str(p), "must hold a YAML mapping")
    return data


def stored_scenario(attrs: Mapping[str, Any]) -> Scenario | DownlookingScenario | None:
    """The scenario a dataset carries in its ``scenario`` attribute (YAML), or None when it has
    none or one this version cannot read (outside data may carry anything).

    Parameters
    ----------
    attrs : mapping
        A dataset's attributes.

    Returns
    -------
    Scenario, DownlookingScenario or None
    """
    text = attrs.get("scenario")
    if not isinstance(text, str):
        return None
    try:
        data = yaml.load(text, Loader=_LOADER)
        return parse_scenario(data) if isinstance(data, Mapping) else None
    except (yaml.YAMLError, ScenarioError):
        return None


_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def is_sweep_document(data) -> bool:
    """Whether a parsed YAML document is a sweep definition (``sweep`` and ``vary`` at its top
    level, :mod:`salkit.studies.spec`), not a scenario.

    Parameters
    ----------
    data : object
        The parsed document.

    Returns
    -------
    bool

    Examples
    --------
    >>> is_sweep_document({"sweep": 1, "scenario": "base.yaml", "vary": {"seed": "1,2"}}), is_sweep_document({"name": "x"})
    (True, False)
    """
    return isinstance(data, Mapping) and "sweep" in data and "vary" in data


def load_scenario(path: str | Path, overrides: Iterable[str] = ()) -> Scenario | DownlookingScenario:
    """Load, override and validate a scenario file.

    Parameters
    ----------
    path : str or Path
        YAML scenario file.
    overrides : iterable of str, or str
        ``key.path=value`` strings, applied before validation (one string: one override).

    Returns
    -------
    Scenario or DownlookingScenario

    Examples
    --------
    >>> sc = load_scenario("examples/spotlight_points.yaml", ["waveform.bandwidth=2e9"])  # doctest: +SKIP
    """
    raw = read_yaml(path)
    if is_sweep_document(raw):  # a study, not one scenario
        raise ScenarioError("scenario", str(path), "is a sweep file (sweep, scenario, vary), not a scenario: run it "
                            "with salkit sweep (salkit.systems.study.prepare from Python), or give its base scenario, "
                            f"{raw.get('scenario')!r}")
    data = apply_overrides(raw, [overrides] if isinstance(overrides, str) else overrides)
    return parse_scenario(data)


def dump_scenario(scenario: Scenario | DownlookingScenario) -> str:
    """The resolved scenario as YAML text (all defaults filled in).

    Parameters
    ----------
    scenario : Scenario or DownlookingScenario

    Returns
    -------
    str
    """
    data = scenario.model_dump(mode="json")
    return yaml.dump(data, Dumper=getattr(yaml, "CSafeDumper", yaml.SafeDumper), sort_keys=False)


def examples_dir() -> Path:
    """The folder of the shipped example scenarios (installed with the package, or the
    repository's ``examples/`` in a source checkout).

    Returns
    -------
    Path
    """
    here = Path(__file__).resolve()
    for cand in (here.parents[1] / "examples", here.parents[3] / "examples"):
        if cand.is_dir():
            return cand
    return here.parents[1] / "examples"


def example_path(name: str) -> Path:
    """The path of a shipped example scenario.

    Parameters
    ----------
    name : str
        File name with or without ``.yaml`` (``salkit examples`` lists them).

    Returns
    -------
    Path

    Raises
    ------
    ScenarioError
        When there is no such example.

    Examples
    --------
    >>> example_path("spotlight_points").name
    'spotlight_points.yaml'
    """
    p = examples_dir() / (name if name.endswith(".yaml") else f"{name}.yaml")
    if not p.is_file():
        known = ", ".join(sorted(f.stem for f in examples_dir().glob("*.yaml")))
        raise ScenarioError("example", name, f"no such shipped example; known: {known}")
    return p
