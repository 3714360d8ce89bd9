"""salkit._lazy: a submodule deferred with its parent package (lazy_loader imports the parent)."""
import subprocess
import sys

from salkit._lazy import Deferred, load


def test_nothing_is_imported_before_the_first_attribute():
    name = "email.mime.audio"
    sys.modules.pop(name, None)
    m = load(name)
    assert isinstance(m, Deferred) and name not in sys.modules
    assert "loaded" not in repr(m)
    assert m.MIMEAudio.__name__ == "MIMEAudio"
    assert name in sys.modules and "loaded" in repr(m)


def test_a_missing_attribute_is_an_attribute_error():
    import pytest
    with pytest.raises(AttributeError):
        load("json").no_such_thing


def test_a_copy_does_not_recurse():
    import copy
    m = copy.copy(load("json"))
    assert m.dumps([1]) == "[1]"


def test_the_library_loads_dask_only_for_dask_work():
    # every module that talks to a cluster, and what `salkit run` loads: 0.3 s less of every command
    code = ("import sys\n"
            "import salkit.resources, salkit.focus.tiles, salkit.studies.engine, salkit.stack.stacking, salkit.report\n"
            "assert 'dask' not in sys.modules, sorted(m for m in sys.modules if m.startswith('dask'))[:5]\n"
            "from salkit.resources import _dask_distributed\n"
            "assert _dask_distributed.Client.__name__ == 'Client' and 'dask.distributed' in sys.modules\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-1500:]
