"""salkit.interrupts: one record of the interrupt, shared by the run folder and the command line,
which reads it on every exit without loading the library."""
from salkit import interrupts
from salkit.io import runfolder

from .conftest import fresh_command


def test_run_folder_and_command_line_share_one_record():
    assert runfolder.INTERRUPTED is interrupts.INTERRUPTED
    assert interrupts.INTERRUPTED == {"signal": None}


def test_help_loads_none_of_the_library():
    # the exit path read the record from salkit.io.runfolder, whose package loads xarray and pandas:
    # 2.8 s for `salkit --help` where 0.9 s is needed
    code, loaded, stdout, stderr = fresh_command(["--help"], ("xarray", "numba.core", "pandas", "scipy", "matplotlib",
                                                              "dask", "salkit.io", "salkit.focus"))
    assert code in ("0", "None"), stderr
    assert "Usage" in stdout
    assert loaded == "[]", loaded
