"""Let a stage's subpackage be called like its main function (``salkit.focus(raw)``) while its
submodules stay importable (``import salkit.focus.pfa``)."""
import functools
import inspect
import sys
import types


def make_callable(module_name: str, func_name: str) -> None:
    """Turn ``sys.modules[module_name]`` into a module whose call runs its ``func_name``.

    Parameters
    ----------
    module_name : str
        A module already in ``sys.modules``.
    func_name : str
        The function of that module a call runs.
    """
    mod = sys.modules[module_name]
    func = getattr(mod, func_name)

    class _CallableModule(types.ModuleType):
        @functools.wraps(func)
        def __call__(self, *args, **kwargs):
            return getattr(self, func_name)(*args, **kwargs)

    mod.__class__ = _CallableModule
    # ``inspect.signature(salkit.focus)`` and editors show the function's own parameters and hints
    mod.__signature__ = inspect.signature(func)
