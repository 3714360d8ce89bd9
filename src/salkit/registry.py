"""Registries: what the house declares once and every layer reads (image formers, metrics, scene
object kinds, materials).

A :class:`Registry` maps a name to a declaration, a frozen dataclass whose fields are everything
the rest of salkit needs to know about the thing (a former's collection modes, tiling and memory
estimate; a metric's unit and theory partner). Declarations are checked when they are made: a
property the declaration class does not have, or one it needs and is not given, is an error naming
it, never a silent default. Lookups of unknown names raise :class:`~salkit.errors.ScenarioError`
naming the field, the value, the nearest name and the valid ones (exit status 2 at the command
line).

A registry may be read by a layer below the one that fills it (the scenario models check
``processing.algorithm`` against the formers that :mod:`salkit.focus` declares): it names its
*providers*, the modules whose import declares the built-in entries, and imports them on the first
lookup, as a plug-in system loads its entry points. A test, a notebook or a user package adds its
own entries with the same call the built-in ones use.
"""
from __future__ import annotations

import dataclasses
import difflib
import importlib
import threading
from typing import Generic, Iterator, TypeVar

from .errors import ScenarioError

T = TypeVar("T")


def nearest(name: str, candidates) -> str | None:
    """The candidate nearest ``name`` (difflib, cutoff 0.6), or None.

    Parameters
    ----------
    name : str
    candidates : iterable of str

    Returns
    -------
    str or None

    Examples
    --------
    >>> nearest("fbp", ["bp", "ffbp", "pfa"])
    'ffbp'
    """
    near = difflib.get_close_matches(str(name), [str(c) for c in candidates], n=1, cutoff=0.6)
    return near[0] if near else None


def declare(cls: type[T], what: str, **properties) -> T:
    """Build the declaration ``cls(**properties)``, refusing unknown and missing properties by name.

    Parameters
    ----------
    cls : dataclass type
        The declaration class (every field without a default must be given).
    what : str
        What is being declared, for the message (``"image former 'bp'"``).
    **properties
        The declaration's fields.

    Returns
    -------
    cls instance

    Raises
    ------
    TypeError
        For a property ``cls`` does not have (with the nearest one) or a required one not given.
    """
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = [k for k in properties if k not in fields]
    if unknown:
        hint = nearest(unknown[0], fields)
        raise TypeError(f"{what}: {unknown[0]!r} is not a property of {cls.__name__}"
                        + (f" (did you mean {hint!r}?)" if hint else "") + f"; the properties: {', '.join(fields)}")
    missing = [k for k, f in fields.items() if k not in properties and f.default is dataclasses.MISSING
               and f.default_factory is dataclasses.MISSING]
    if missing:
        raise TypeError(f"{what}: undeclared {', '.join(missing)} (every {cls.__name__} declares "
                        f"{', '.join(k for k in fields if k in missing or k in properties)})")
    return cls(**properties)


class Registry(Generic[T]):
    """Name -> declaration, filled by the modules that declare, read by any layer.

    Parameters
    ----------
    kind : str
        What the entries are, for messages (``"image former"``).
    field : str
        The scenario field or option that names an entry, for messages (``"processing.algorithm"``).
    providers : tuple of str
        Modules whose import declares the built-in entries (imported on the first lookup).
    """

    def __init__(self, kind: str, field: str, providers: tuple[str, ...] = ()):
        self.kind, self.field, self.providers = kind, field, tuple(providers)
        self._entries: dict[str, T] = {}
        self._loaded = not providers
        self._lock = threading.RLock()

    def _load(self) -> None:
        if self._loaded:
            return
        with self._lock:
            if not self._loaded:
                self._loaded = True
                for module in self.providers:
                    importlib.import_module(module)

    def add(self, name: str, declaration: T) -> T:
        """Register ``declaration`` under ``name``.

        Parameters
        ----------
        name : str
        declaration : object

        Returns
        -------
        object
            ``declaration``.

        Raises
        ------
        ValueError
            For a name already taken or not a plain identifier.
        """
        if not isinstance(name, str) or not name.replace("-", "_").isidentifier():
            raise ValueError(f"{self.kind} name {name!r} must be an identifier (letters, digits, _ or -)")
        with self._lock:
            if name in self._entries:
                raise ValueError(f"{self.kind} {name!r} is already declared")
            self._entries[name] = declaration
        return declaration

    def declare(self, cls: type, name: str, **properties):
        """Build the declaration ``cls(name=name, **properties)`` (:func:`declare`: unknown and
        missing properties refused by name) and register it under ``name``.

        Parameters
        ----------
        cls : dataclass type
        name : str
        **properties

        Returns
        -------
        object
            The declaration.
        """
        return self.add(name, declare(cls, f"{self.kind} {name!r}", name=name, **properties))

    def require(self, name):
        """``name`` if declared, else a ``ValueError`` with the constraint (for the scenario models'
        validators, which report it with the field).

        Parameters
        ----------
        name : object

        Returns
        -------
        object
            ``name``.

        Raises
        ------
        ValueError
        """
        if name not in self:
            raise ValueError(str(self.unknown(name).constraint))
        return name

    def remove(self, name: str) -> None:
        """Take ``name`` out (a test's own entry, when it is done).

        Parameters
        ----------
        name : str
        """
        with self._lock:
            self._entries.pop(name, None)

    def get(self, name: str, field: str | None = None) -> T:
        """The declaration of ``name``.

        Parameters
        ----------
        name : str
        field : str, optional
            The field or option that named it (default the registry's), for the message.

        Returns
        -------
        object

        Raises
        ------
        ScenarioError
            For an unknown name: the field, the value, the nearest name and the valid names.
        """
        self._load()
        try:
            return self._entries[name]
        except (KeyError, TypeError):
            raise self.unknown(name, field) from None

    def unknown(self, name, field: str | None = None) -> ScenarioError:
        """The error for a name that is not declared.

        Parameters
        ----------
        name : object
        field : str, optional

        Returns
        -------
        ScenarioError
        """
        self._load()
        hint = nearest(str(name), self._entries)
        return ScenarioError(field or self.field, name, f"is not a declared {self.kind}"
                             + (f" (did you mean '{hint}'?)" if hint else "")
                             + f"; the {self.kind}s: {', '.join(self.names())}")

    def check(self, name: str, field: str | None = None) -> str:
        """``name`` if declared, else :meth:`unknown`'s error.

        Parameters
        ----------
        name : str
        field : str, optional

        Returns
        -------
        str
        """
        self.get(name, field)
        return name

    def names(self) -> tuple[str, ...]:
        """The declared names, in declaration order.

        Returns
        -------
        tuple of str
        """
        self._load()
        return tuple(self._entries)

    def items(self):
        """(name, declaration) pairs in declaration order.

        Returns
        -------
        list of (str, object)
        """
        self._load()
        return list(self._entries.items())

    def __contains__(self, name) -> bool:
        self._load()
        return name in self._entries

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __len__(self) -> int:
        return len(self.names())

    def __getitem__(self, name: str) -> T:
        return self.get(name)

    def __repr__(self) -> str:
        return f"Registry({self.kind!r}: {', '.join(self._entries) if self._loaded else '(not loaded)'})"


#: Image formers (:class:`salkit.focus.formers.FormerSpec`), declared in :mod:`salkit.focus`.
FORMERS: Registry = Registry("image former", "processing.algorithm", providers=("salkit.focus.pipeline",))
#: Metrics (:class:`salkit.metrics.table.MetricSpec`), declared in :mod:`salkit.metrics.table`.
METRICS: Registry = Registry("metric", "--metric", providers=("salkit.metrics.table",))
#: Kinds of scene object (:class:`salkit.simulate.objects.ObjectKind`), declared in
#: :mod:`salkit.simulate.objects`.
OBJECT_KINDS: Registry = Registry("scene object kind", "scene.extended.kind", providers=("salkit.simulate.objects",))
#: Built-in reflectivity patterns of the ``pattern`` object kind (:class:`salkit.simulate.objects.Pattern`).
PATTERNS: Registry = Registry("pattern", "scene.extended.pattern", providers=("salkit.simulate.objects",))
#: Materials: how a surface's reflectivity becomes scatterers (:class:`salkit.simulate.objects.Material`).
MATERIALS: Registry = Registry("material", "scene.extended.material", providers=("salkit.simulate.objects",))
#: Built-in 3-D shapes of ``scene.objects`` (:class:`salkit.simulate.targets.Shape`).
SHAPES: Registry = Registry("shape", "scene.objects.shape", providers=("salkit.simulate.targets",))
#: Surface kinds of 3-D objects (:class:`salkit.simulate.targets.Surface`): how a surface scatters back.
SURFACES: Registry = Registry("surface kind", "scene.objects.material.kind", providers=("salkit.simulate.targets",))
