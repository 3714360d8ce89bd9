"""A stage's package is callable like its main function, and its submodules stay importable."""
import salkit


def test_stage_packages_call_their_function():
    import salkit.focus.pfa as pfa_module
    assert callable(salkit.focus) and callable(salkit.simulate)
    assert salkit.focus.__call__ is not None
    assert pfa_module.__name__ == "salkit.focus.pfa"  # the module, not the former


def test_call_forwards_arguments(monkeypatch):
    import salkit.focus as f
    seen = {}
    monkeypatch.setattr(f, "focus", lambda *a, **k: seen.setdefault("args", (a, k)))
    salkit.focus(1, algorithm="pfa")
    assert seen["args"] == ((1,), {"algorithm": "pfa"})


def test_the_callable_faces_show_their_functions_signature():
    """``inspect.signature(salkit.focus)`` shows focus's own parameters and hints (it used to say
    ``(*args, **kwargs)``); the package ships ``py.typed`` and a stub of its lazy face."""
    import inspect
    from pathlib import Path
    import salkit.focus.pipeline as p
    import salkit.simulate.registry as r
    assert inspect.signature(salkit.focus) == inspect.signature(p.focus)
    assert inspect.signature(salkit.simulate) == inspect.signature(r.simulate)
    assert "memory_limit" in inspect.signature(salkit.focus).parameters
    root = Path(salkit.__file__).parent
    assert (root / "py.typed").is_file()
    stub = (root / "__init__.pyi").read_text()
    for name in salkit.__all__:
        if name != "__version__":
            assert f" as {name}" in stub, name
