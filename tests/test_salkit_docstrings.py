"""Every public function of salkit has a numpydoc docstring: a summary, a Parameters section when
it takes arguments and a Returns (or Yields) section when it returns a value. The command-line
commands are exempt: their options carry their own help text (``salkit CMD --help``)."""
import ast
import re
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "salkit"


def _own_returns(fn) -> bool:
    stack = list(fn.body)
    while stack:
        x = stack.pop()
        if isinstance(x, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            continue
        if isinstance(x, ast.Return) and x.value is not None:
            return True
        stack.extend(ast.iter_child_nodes(x))
    return False


def _is_cli_command(fn) -> bool:
    """A command: guarded (``@_guard``, registered in ``cli.main.COMMANDS``) or ``@app.command()``."""
    return any((isinstance(d, ast.Call) and getattr(d.func, "attr", "") == "command")
               or (isinstance(d, ast.Name) and d.id == "_guard") for d in fn.decorator_list)


def _problems():
    for f in sorted(SRC.rglob("*.py")):
        for n in ast.parse(f.read_text()).body:
            if not isinstance(n, ast.FunctionDef) or n.name.startswith("_") or _is_cli_command(n):
                continue
            doc = ast.get_docstring(n) or ""
            args = [a.arg for a in n.args.args + n.args.kwonlyargs if a.arg not in ("self", "cls")]
            where = f"{f.relative_to(SRC)}:{n.name}"
            if not doc:
                yield where, "no docstring"
            elif args and "\nParameters\n" not in f"\n{doc}":
                yield where, "no Parameters section"
            elif _own_returns(n) and "\nReturns\n" not in doc and "\nYields\n" not in doc:
                yield where, "no Returns section"


def test_public_functions_have_numpydoc_sections():
    bad = list(_problems())
    assert not bad, "\n".join(f"{w}: {p}" for w, p in bad)


def test_the_check_can_fail(tmp_path, monkeypatch):
    (tmp_path / "m.py").write_text("def f(x):\n    '''Summary.'''\n    return x\n")
    monkeypatch.setattr("tests.test_salkit_docstrings.SRC", tmp_path)
    assert list(_problems()) == [("m.py:f", "no Parameters section")]


def _summary(text: str) -> str:
    """The first sentence as Sphinx's autosummary cuts it: up to the first period followed by
    white space (``x .. y`` included), the text joined on one line."""
    text = " ".join(text.split())
    m = re.search(r"\.\s", text + " ")
    return text[: m.start() + 1] if m else text


def _summaries(path: Path):
    """(line, summary) of each public function's and class's docstring and each ``#:`` comment."""
    src = path.read_text()
    for n in ast.parse(src).body:
        if isinstance(n, (ast.FunctionDef, ast.ClassDef)) and not n.name.startswith("_"):
            if doc := ast.get_docstring(n):
                yield n.lineno, _summary(doc)
    block, start = [], 0
    for i, line in enumerate(src.splitlines() + [""], 1):
        if line.startswith("#:"):
            block, start = block + [line[2:]], start or i
        elif block:
            yield start, _summary(" ".join(block))
            block, start = [], 0


def _broken_summaries():
    for f in sorted(SRC.rglob("*.py")):
        for line, s in _summaries(f):
            if s.count("``") % 2:
                yield f"{f.relative_to(SRC)}:{line}: {s!r}"


def test_summaries_keep_their_literals_whole():
    """The API reference's summary tables cut each docstring at its first sentence; a cut inside a
    literal (``j .. j+7``) is a docutils warning and ``make api`` fails on warnings."""
    bad = list(_broken_summaries())
    assert not bad, "\n".join(bad)


def test_the_summary_check_can_fail(tmp_path, monkeypatch):
    (tmp_path / "m.py").write_text("#: For pixels ``j .. j+7``: the kernel.\nA = 1\n")
    monkeypatch.setattr("tests.test_salkit_docstrings.SRC", tmp_path)
    assert len(list(_broken_summaries())) == 1
