"""salkit.interrupts: one record of the interrupt, shared by the run folder and the command line,
which reads it on every exit without loading the library."""
import subprocess
import sys

from salkit import interrupts
from salkit.io import runfolder

# the whole `salkit --help`, entry point and exit included; then what it loaded
HELP = """
import sys
sys.argv = ["salkit", "--help"]
from salkit.cli.main import main
try:
    main()
except SystemExit as e:
    assert e.code in (0, None), e.code
heavy = sorted(m for m in ("xarray", "numba.core", "pandas", "scipy", "matplotlib", "dask", "salkit.io", "salkit.focus")
               if m in sys.modules)
print("LOADED", heavy)
"""


def test_run_folder_and_command_line_share_one_record():
    assert runfolder.INTERRUPTED is interrupts.INTERRUPTED
    assert interrupts.INTERRUPTED == {"signal": None}


def test_help_loads_none_of_the_library():
    # the exit path read the record from salkit.io.runfolder, whose package loads xarray and pandas:
    # 2.8 s for `salkit --help` where 0.9 s is needed
    r = subprocess.run([sys.executable, "-c", HELP], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "Usage" in r.stdout
    assert r.stdout.strip().splitlines()[-1] == "LOADED []", r.stdout[-300:]
