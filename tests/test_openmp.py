"""salkit._openmp: OpenMP's threads told to sleep between parallel regions, unless the user says
otherwise, before numba starts them."""
import os
import subprocess
import sys


def _run(code: str, **env) -> str:
    base = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    return subprocess.run([sys.executable, "-c", code], env={**base, **env}, capture_output=True, text=True,
                          check=True, timeout=120).stdout.strip()


def test_importing_salkit_asks_for_passive_waiting_before_numba_loads_openmp():
    out = _run("import os, sys, salkit; print(os.environ.get('OMP_WAIT_POLICY'), "
               "'numba.np.ufunc.omppool' in sys.modules)")
    assert out == "passive False"  # set, and no OpenMP runtime loaded yet that would have read it first


def test_a_policy_the_user_set_is_kept():
    assert _run("import os, salkit; print(os.environ['OMP_WAIT_POLICY'])", OMP_WAIT_POLICY="active") == "active"


def test_numba_kernels_run_under_it():
    code = ("import os, salkit, numba, numpy as np\n"
            "@numba.njit(parallel=True)\n"
            "def f(a):\n"
            "    s = 0.0\n"
            "    for i in numba.prange(a.size):\n"
            "        s += a[i]\n"
            "    return s\n"
            "print(f(np.ones(1000)), numba.threading_layer(), os.environ['OMP_WAIT_POLICY'])")
    value, layer, policy = _run(code).split()
    assert float(value) == 1000.0 and policy == "passive" and layer in ("omp", "tbb", "workqueue")
