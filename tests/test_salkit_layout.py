"""Package faces hold no code, no import cycles, and the tests mirror the source file for file: ``tests/<package>/test_<module>[_<topic>].py`` tests
``src/salkit/<package>/<module>.py`` (``test_<package>`` for the package's ``__init__``), every test
file names a module that exists, and every module has a test file."""
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "salkit"
TESTS = ROOT / "tests"


def package_faces() -> list[Path]:
    """Every package's ``__init__.py``."""
    return sorted(SRC.rglob("__init__.py"))


def test_packages_are_faces():
    """An ``__init__.py`` holds the package's docstring, re-exports and lazy-loading hooks: no function
    or class of its own, at most 60 lines."""
    import ast
    bad = []
    for f in package_faces():
        text = f.read_text()
        defs = [n.name for n in ast.parse(text).body if isinstance(n, (ast.FunctionDef, ast.ClassDef))]
        if defs or len(text.splitlines()) > 60:
            bad.append(f"{f.relative_to(SRC)}: {len(text.splitlines())} lines, defines {defs}")
    assert not bad, "package faces holding code:\n" + "\n".join(bad)


def test_no_import_cycle_between_modules():
    """No module imports, directly or through others, a module that imports it back (grimp's graph
    of every import, those inside functions included)."""
    import grimp
    g = grimp.build_graph("salkit")
    edges = {m: set(g.find_modules_directly_imported_by(m)) for m in g.modules}
    index, low, stack, on, cycles, counter = {}, {}, [], set(), [], [0]

    def strongconnect(v):  # Tarjan's strongly connected components
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                strongconnect(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            strongconnect(v)
    assert not cycles, f"import cycles: {cycles}"


def modules() -> set[str]:
    """Source modules as 'package/module' ('package/package' for a package's __init__)."""
    out = set()
    for f in SRC.rglob("*.py"):
        rel = f.relative_to(SRC)
        pkg = rel.parent.as_posix()
        name = rel.stem.lstrip("_")
        if rel.name == "__init__.py":
            if pkg != "." and not any(line.startswith(("def ", "class ")) for line in f.read_text().splitlines()):
                continue  # re-exports only: tested through its modules
            name = "salkit" if pkg == "." else rel.parent.name
        out.add(f"{pkg}/{name}")
    return out


def test_module_of(test: Path) -> str | None:
    """The module a test file tests: the longest module name its topic starts with."""
    rel = test.relative_to(TESTS)
    pkg = rel.parent.as_posix()
    topic = rel.stem[len("test_"):]
    cands = [m for m in modules() if m.startswith(f"{pkg}/") and
             (topic == m.split("/")[-1] or topic.startswith(m.split("/")[-1] + "_"))]
    return max(cands, key=len) if cands else None


test_module_of.__test__ = False  # a helper, not a test


def test_every_test_file_names_a_module():
    bad = [str(t.relative_to(TESTS)) for t in TESTS.rglob("test_*.py")
           if test_module_of(t) is None]
    assert not bad, f"test files that name no module of src/salkit: {bad}"


def test_every_module_has_a_test_file():
    tested = {test_module_of(t) for t in TESTS.rglob("test_*.py")}
    missing = sorted(modules() - tested)
    assert not missing, f"modules without a test file: {missing}"


# Imports inside functions that stay there, with the reason. Everything else in the library imports
# at module level (heavy optional modules through lazy_loader); the command line (cli/) imports the
# library inside each command so that `salkit --help` loads none of it.
DEFERRED_IMPORTS = {
    ("io/cphd.py", "sarkit"): "sarkit's modules fail under lazy_loader (AttributeError on first use)",
    ("io/sicd.py", "sarkit"): "as io/cphd.py",
    ("io/cphd.py", "lxml"): "an extension module: lazy_loader cannot defer it",
    ("io/sicd.py", "lxml"): "as io/cphd.py",
    ("io/reading.py", "h5py"): "only to name a corrupt variable, after a read failed",
    ("simulate/objects.py", "matplotlib"): "only for image-file scenes",
    ("focus/pipeline.py", ".pfa"): "imported at module level it registers pfa ahead of the formers' declared order",
}


def test_library_imports_at_module_level():
    import ast
    bad = []
    for f in sorted(SRC.rglob("*.py")):
        rel = f.relative_to(SRC).as_posix()
        if rel.startswith("cli/"):
            continue
        t = ast.parse(f.read_text())
        funcs = [p for p in ast.walk(t) if isinstance(p, (ast.FunctionDef, ast.AsyncFunctionDef))]
        for n in ast.walk(t):
            if not isinstance(n, (ast.Import, ast.ImportFrom)):
                continue
            if not any(p.lineno < n.lineno <= p.end_lineno for p in funcs):
                continue
            mod = ("." * n.level + (n.module or "")) if isinstance(n, ast.ImportFrom) else n.names[0].name
            if not any(rel == r and (mod == m or mod.startswith(m + ".") or mod.startswith(m))
                       for r, m in DEFERRED_IMPORTS):
                bad.append(f"{rel}:{n.lineno} {ast.unparse(n)}")
    assert not bad, "imports inside functions (move them to module level):\n" + "\n".join(bad)
