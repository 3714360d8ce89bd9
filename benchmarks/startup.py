"""startup: ``import salkit`` and ``salkit --help`` in fresh interpreters against ``import numpy,
xarray``.

``make bench NAME=startup`` (or ``python benchmarks/startup.py``) runs it alone.
"""
from __future__ import annotations

import sys
import time


def bench_startup(repeat=5):
    """Start-up: ``import salkit`` and ``salkit --help`` against ``import numpy, xarray``, each in a
    fresh interpreter, best of ``repeat`` (issue 12 target: within 1.5x)."""
    import subprocess

    def best(cmd):
        t = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            subprocess.run(cmd, check=True, capture_output=True)
            t.append(time.perf_counter() - t0)
        return min(t)
    py = sys.executable
    base = best([py, "-c", "import numpy, xarray"])
    imp = best([py, "-c", "import salkit"])
    hlp = best([py, "-m", "salkit.cli.main", "--help"])
    return {"startup_import_numpy_xarray_s": base, "startup_import_salkit_s": imp, "startup_help_s": hlp,
            "startup_import_ratio": imp / base, "startup_help_ratio": hlp / base}


if __name__ == "__main__":
    import runner
    runner.main(["startup"])
