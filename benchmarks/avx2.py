"""avx2: run a benchmark with the code an AVX2-only machine gets, on this one.

``python benchmarks/avx2.py SCRIPT [ARGS ...]`` runs ``benchmarks/SCRIPT`` with numba generating code
for an AVX2-only Zen 3 (``NUMBA_CPU_NAME=znver3``, ``NUMBA_CPU_FEATURES`` = this CPU's features with
every ``avx512*`` one off, its own ``NUMBA_CACHE_DIR``) and FastSAR's C++ kernels compiled with
``-O3 -march=znver3`` (``FFBP_CPU_FLAGS``, its own ``FASTSAR_CACHE_DIR``). The figures are AVX2 code
on this core, not a Zen 3 machine's: say so beside them. On a machine without AVX-512 there is
nothing to emulate: run the script itself.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path


def avx2_environment() -> dict:
    """The environment variables of an AVX2-only build on this machine."""
    import llvmlite.binding as llvm
    llvm.initialize_native_target()
    feats = llvm.get_host_cpu_features()
    flat = ",".join(("-" if k.startswith("avx512") else ("+" if v else "-")) + k for k, v in sorted(feats.items()))
    root = Path(tempfile.gettempdir())
    return {"NUMBA_CPU_NAME": "znver3", "NUMBA_CPU_FEATURES": flat,
            "NUMBA_CACHE_DIR": str(root / "salkit-avx2-numba-cache"),
            "FFBP_CPU_FLAGS": "-O3 -march=znver3", "FASTSAR_CACHE_DIR": str(root / "salkit-avx2-fastsar-cache")}


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    env = dict(os.environ, **avx2_environment())
    script = Path(__file__).resolve().parent / sys.argv[1]
    print(f"avx2: {script.name} with NUMBA_CPU_NAME=znver3, avx512* off, FFBP_CPU_FLAGS='-O3 -march=znver3'", flush=True)
    sys.exit(subprocess.call([sys.executable, str(script), *sys.argv[2:]], env=env))
