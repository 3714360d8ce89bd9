"""Registries: declarations checked when made (unknown and missing properties named), unknown
names refused with the nearest, providers imported on the first lookup."""
import dataclasses
import sys

import pytest

from salkit.errors import ScenarioError
from salkit.registry import FORMERS, Registry, declare, nearest


@dataclasses.dataclass(frozen=True)
class Thing:
    name: str
    size: int
    colour: str = "grey"


def test_declare_names_unknown_and_missing_properties():
    assert declare(Thing, "thing 'a'", name="a", size=1) == Thing("a", 1)
    with pytest.raises(TypeError, match=r"'sise' is not a property of Thing \(did you mean 'size'\?\)"):
        declare(Thing, "thing 'a'", name="a", sise=1)
    with pytest.raises(TypeError, match="thing 'a': undeclared size"):
        declare(Thing, "thing 'a'", name="a")


def test_lookups_refuse_unknown_names_with_the_nearest():
    r = Registry("thing", "scene.thing")
    r.add("alpha", Thing("alpha", 1))
    r.add("beta", Thing("beta", 2))
    assert r.names() == ("alpha", "beta") and "alpha" in r and len(r) == 2
    with pytest.raises(ScenarioError, match=r"scene.thing = 'alpah': is not a declared thing \(did you mean 'alpha'\?\)"):
        r.get("alpah")
    with pytest.raises(ScenarioError, match="--thing = 'x'"):
        r.check("x", "--thing")
    with pytest.raises(ValueError, match="already declared"):
        r.add("alpha", Thing("alpha", 3))
    with pytest.raises(ValueError, match="must be an identifier"):
        r.add("two words", Thing("x", 0))
    r.remove("beta")
    assert r.names() == ("alpha",)
    assert nearest("fbp", ["bp", "ffbp"]) == "ffbp" and nearest("zzz", ["bp"]) is None


def test_providers_are_imported_on_the_first_lookup(tmp_path, monkeypatch):
    (tmp_path / "provider_mod.py").write_text(
        "from tests.test_registry import Thing, LATE\nLATE.add('late', Thing('late', 7))\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    sys.modules.pop("provider_mod", None)
    assert "provider_mod" not in sys.modules
    assert LATE.get("late").size == 7 and "provider_mod" in sys.modules
    assert set(FORMERS.names()) >= {"bp", "ffbp", "pfa", "omegak", "exact"}  # salkit.focus declares them


LATE = Registry("late thing", "x", providers=("provider_mod",))
