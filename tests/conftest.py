"""Shared fixtures: small, fast scenarios built from dicts."""
from __future__ import annotations

import copy
import os
import sys
from pathlib import Path

import pytest

from salkit.params import parse_scenario


def pytest_configure(config):
    """Under pytest-xdist (``make test`` runs ``-n auto``, one worker a core), each worker's share
    of the cores for numba's kernels and BLAS, and for the ``salkit`` processes tests start: the
    workers' parallel kernels then do not contend for the same cores."""
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "0") or 0)
    if workers > 1:
        share = str(max(1, (os.cpu_count() or 1) // workers))
        os.environ["NUMBA_NUM_THREADS"] = share
        os.environ["OMP_NUM_THREADS"] = share
        if "numba" in sys.modules:  # imported before this hook (by a conftest): read the share now, before
            # its threads start; else a kernel loaded from the cache could start them at a thread a core and
            # the next kernel compiled would be refused ("Cannot set NUMBA_NUM_THREADS ... once the
            # threads have been launched")
            sys.modules["numba"].core.config.reload_config()


#: The longest test files, run first: under xdist's ``--dist loadfile`` files go to workers in
#: collection order, and one of these last would leave the other worker idle for its length at the
#: end. Ordered by their measured totals (``--durations=0``, 0.21.0, 2 workers: 106, 84, 81, 62, 51,
#: 48, 40, 36, 34, 25 s, then 13 to 20 s).
LONGEST_FIRST = ("cli/test_demo.py", "cli/test_main_reliability.py", "cli/test_main_budgets.py",
                 "systems/test_turbulence.py", "atmosphere/test_beam.py", "systems/test_study_examples.py",
                 "focus/test_exact_accuracy.py", "autofocus/test_pulses.py", "atmosphere/test_spherical.py",
                 "stack/test_stacking.py", "focus/test_tiles.py", "cli/test_studies.py",
                 "report/test_docs_tutorials.py", "systems/test_spaceborne.py", "simulate/test_sal_noise.py",
                 "cli/test_data.py", "atmosphere/test_screens.py", "simulate/test_sal.py", "studies/test_engine.py")


def pytest_collection_modifyitems(session, config, items):
    rank = {name: k for k, name in enumerate(LONGEST_FIRST)}
    tests = Path(__file__).resolve().parent

    def key(item):
        path = Path(item.path).resolve()
        name = path.relative_to(tests).as_posix() if path.is_relative_to(tests) else ""
        return rank.get(name, len(rank))

    items.sort(key=key)  # stable: the rest keep their order


#: A ``salkit`` command in a fresh interpreter, entry point and exit included: its exit status and what it
#: loaded of the modules named (numba.core, not numba: lazy_loader puts a stand-in "numba" in sys.modules).
_FRESH = """
import sys
watch, sys.argv = sys.argv[1].split(","), ["salkit"] + sys.argv[2:]
from salkit.cli.main import main
code = 0
try:
    main()
except SystemExit as e:
    code = e.code
print("EXIT", code)
print("LOADED", sorted(m for m in watch if m in sys.modules))
"""


def fresh_command(args, watch):
    """Run ``salkit ARGS`` in a fresh interpreter: (exit status as printed, the watched modules it
    loaded, stdout before those two lines, stderr)."""
    import subprocess
    r = subprocess.run([sys.executable, "-c", _FRESH, ",".join(watch), *map(str, args)], capture_output=True,
                       text=True, timeout=120)
    lines = r.stdout.rstrip().splitlines()
    assert len(lines) >= 2 and lines[-2].startswith("EXIT ") and lines[-1].startswith("LOADED "), (r.stdout, r.stderr)
    return lines[-2][5:], lines[-1][7:], "\n".join(lines[:-2]), r.stderr


ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
DL_EXAMPLE = EXAMPLES / "downlooking_3d.yaml"


def dl_scenario(*sets):
    """The shipped down-looking example with ``key.path=value`` overrides."""
    from salkit.params import load_scenario
    return load_scenario(DL_EXAMPLE, list(sets))

SPOT = {
    "name": "test_spot", "seed": 1,
    "waveform": {"wavelength": 1.55e-6, "bandwidth": 7.5e9, "pulse_width": 10e-6, "prf": 25000.0},
    "platform": {"mode": "spotlight", "speed": 20.0, "altitude": 3000.0, "standoff": 4000.0,
                 "real_aperture": 0.005, "aperture_length": 0.19375},
    "scene": {"points": [{"x": 0.0, "y": 0.0, "amplitude": 1.0, "phase": 0.7}]},
    "receiver": {"adc_rate": 20e6},
    "processing": {"algorithm": "bp", "grid": {"nx": 128, "ny": 128, "dx": 0.015, "dy": 0.015}},
}

STRIP = {
    "name": "test_strip", "seed": 2,
    "waveform": {"wavelength": 1.55e-6, "bandwidth": 7.5e9, "pulse_width": 10e-6, "prf": 2000.0},
    "platform": {"mode": "stripmap", "speed": 10.0, "altitude": 3000.0, "standoff": 4000.0,
                 "real_aperture": 0.03},
    "scene": {"points": [{"x": 0.1, "y": 0.05, "amplitude": 1.0, "phase": -0.4}]},
    "receiver": {"adc_rate": 6e6},
    "processing": {"algorithm": "omegak", "grid": {"nx": 128, "ny": 64, "dx": 0.01, "dy": 0.015}},
}

GEO = {
    "name": "test_geo", "seed": 3,
    "waveform": {"wavelength": 1.55e-6, "bandwidth": 3e9, "pulse_width": 10e-6, "prf": 400.0},
    "platform": {"mode": "spotlight", "speed": 7.3, "altitude": 0.0, "standoff": 200000.0,
                 "real_aperture": 0.19, "aperture_length": 3.1},
    "scene": {"points": [{"x": 0.0, "y": 0.0, "amplitude": 1.0, "phase": -1.2}]},
    "receiver": {"adc_rate": 12e6},
    "processing": {"algorithm": "bp", "grid": {"nx": 96, "ny": 96, "dx": 0.04, "dy": 0.04}},
}


def merge(base: dict, **paths) -> dict:
    """Copy ``base`` and set dotted paths given as keyword args with '__' for '.'."""
    d = copy.deepcopy(base)
    for key, value in paths.items():
        node = d
        parts = key.split("__")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = value
    return d


@pytest.fixture
def spot():
    return parse_scenario(SPOT)


@pytest.fixture
def strip():
    return parse_scenario(STRIP)


@pytest.fixture
def geo():
    return parse_scenario(GEO)
