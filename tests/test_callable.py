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
