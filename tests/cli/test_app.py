"""The application's guard: exit 2 for bad input, 1 for the environment (a full disk, memory),
130 when interrupted, 1 with "internal error" for a bug, one line each and no traceback; warnings
as one line on stderr."""
import errno

import pytest
import typer

from salkit.cli.app import _guard, show_warning
from salkit.errors import DataFileError, ScenarioError


@pytest.mark.parametrize("exc,code,line", [
    (ScenarioError("waveform.prf", -1, "must be > 0"), 2, "waveform.prf"),
    (DataFileError("x.nc: is a directory, not a file"), 2, "is a directory"),
    (OSError(errno.ENOSPC, "No space left on device", "out.nc"), 1, "no space left on the device: out.nc"),
    (MemoryError(), 1, "out of memory"),
    (KeyboardInterrupt(), 130, "interrupted: nothing was left behind"),
    (ZeroDivisionError("boom"), 1, "internal error (ZeroDivisionError: boom)"),
])
def test_guard_exit_codes(capsys, exc, code, line):
    def command():
        raise exc

    with pytest.raises(typer.Exit) as e:
        _guard(command)()
    assert e.value.exit_code == code
    err = capsys.readouterr().err
    assert line in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_guard_passes_results_and_exits_through():
    assert _guard(lambda: 7)() == 7

    def exits():
        raise typer.Exit(code=3)

    with pytest.raises(typer.Exit):
        _guard(exits)()


def test_warning_is_one_line(capsys):
    show_warning(UserWarning("grid [coarse]"), UserWarning, "f.py", 1)
    assert capsys.readouterr().err.strip() == "warning: grid [coarse]"


def test_a_kernel_compiling_is_said_once_and_a_cached_one_is_not(capsys, monkeypatch):
    """numba compiles a salkit kernel on its first use on a machine (a cache miss): the progress bar
    says so once on stderr, before the kernel compiles; a function outside salkit, and a second
    salkit kernel, say nothing more."""
    import numba
    from salkit.cli import app as app_module
    monkeypatch.setitem(app_module._COMPILING, "said", False)

    def kernel(name):  # a fresh, uncached dispatcher whose function lives in module `name`
        scope = {"__name__": name}
        exec("def f(x):\n    return x + 1\n", scope)
        return numba.njit(scope["f"])

    with app_module._Bar():
        assert kernel("elsewhere")(1) == 2
    assert app_module.COMPILE_NOTICE not in capsys.readouterr().err
    with app_module._Bar():
        assert kernel("salkit._probe")(1) == 2
        assert kernel("salkit._probe2")(2) == 3
    assert capsys.readouterr().err.count("compiling salkit's numba kernels") == 1


def test_a_users_text_is_printed_as_written_not_as_emoji(capsys):
    """rich turned ":-1:" in an error's value into a thumbs-down emoji ("log👎2:3")."""
    def command():
        raise ScenarioError("--vary", "waveform.bandwidth=log:-1:2:3", "a log sweep needs START and STOP > 0")

    with pytest.raises(typer.Exit):
        _guard(command)()
    assert "'waveform.bandwidth=log:-1:2:3'" in capsys.readouterr().err
    show_warning(UserWarning("axis :smile: [x]"), UserWarning, "f.py", 1)
    assert capsys.readouterr().err.strip() == "warning: axis :smile: [x]"
