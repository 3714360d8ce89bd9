"""The memory guard: estimates from sizes, refusals with the numbers, before any work."""
import os
import sys
import time

import pytest

from salkit.errors import ResourceError, ScenarioError
from salkit.params import parse_scenario
from salkit.resources import WORKER_START_METHOD, available_memory, check_memory, parse_size, set_limit

from .conftest import SPOT, merge


def test_parse_size():
    assert parse_size("8GiB") == 8 * 2 ** 30 and parse_size("512 MB") == 512_000_000 and parse_size("2e9") == 2e9
    for bad in ("lots", "-1GB", "0", "5 parsecs"):
        with pytest.raises(ScenarioError):
            parse_size(bad)


def test_limit_and_refusal_message():
    set_limit(2 ** 30)
    try:
        assert available_memory() <= 2 ** 30
        with pytest.raises(ResourceError, match=r"job needs about 2 GiB of memory, 1 GiB available; reduce it"):
            check_memory(2 * 2 ** 30, "job", "reduce it")
    finally:
        set_limit(None)


@pytest.mark.parametrize("sets", [{"receiver__adc_rate": 1e12}, {"platform__aperture_length": 1e6}])
def test_simulate_refuses_before_any_work(sets):
    from salkit import simulate
    sc = parse_scenario(merge(SPOT, **sets))
    t0 = time.perf_counter()
    with pytest.raises(ResourceError, match="needs about .* GiB of memory"):
        simulate(sc)
    assert time.perf_counter() - t0 < 2.0


def test_estimate_tracks_the_real_allocation():
    """The estimate is an upper bound of the signal actually made, within a small factor."""
    from salkit import simulate
    from salkit.simulate import memory_estimate
    sc = parse_scenario(SPOT)
    raw = simulate(sc)
    need, _ = memory_estimate(sc)
    sig = raw["signal"].nbytes
    assert 2 * sig <= need < 4 * sig + 1e6


def test_screens_refused():
    from salkit.atmosphere import phase_screens
    with pytest.raises(ResourceError):
        phase_screens(1_000_000, 0.01, 0.05)
    with pytest.raises(ResourceError):
        phase_screens(256, 0.01, 0.05, count=10 ** 9)
    with pytest.raises(ScenarioError, match="below the outer scale"):
        phase_screens(64, 0.01, 0.05, outer_scale=1.0, inner_scale=10.0)
    with pytest.raises(ScenarioError, match="seed = -4"):
        phase_screens(64, 0.01, 0.05, seed=-4)


def test_ffbp_estimate_bounds_its_allocation():
    """FFBP's estimate covers what it allocates (tracemalloc: its polar-grid buffers, profiles
    and image) and is not far above it."""
    import tracemalloc

    import numpy as np

    from salkit import simulate
    from salkit.focus import memory_estimate, phase_history
    from salkit.focus.formers import ImageGrid, get_former
    from salkit.signals.windows import Window
    sc = parse_scenario(SPOT)
    raw = simulate(sc)
    ph = phase_history(raw)
    grid = ImageGrid.of(ph, sc.processing.grid)
    former, win = get_former("ffbp"), Window("none")
    former(ph, grid, win)  # compiled before measuring
    tracemalloc.start()
    former(ph, grid, win)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    P, M = raw["signal"].shape
    need, what = memory_estimate(P, M, sc.processing.grid.nx, sc.processing.grid.ny, "ffbp")
    assert "ffbp" in what
    assert peak <= need < 5 * peak, (peak, need)
    assert np.isfinite(need)


def test_the_workers_plugin_sets_up_where_the_script_imported_only_salkit_resources():
    """The plugin a local cluster's workers get is unpickled there after the worker imported the calling
    script again; a script that imports ``salkit.resources`` and no numba at its top (``from
    salkit.resources import dask_client``) left numba unloaded there. numba was then a stand-in in
    ``sys.modules`` (lazy_loader's), the plugin's pickle imported ``numba.core`` past it, and its
    setup failed ("module 'numba.core' has no attribute 'config'"): no cluster started. Here the
    plugin is pickled in one process and set up in another that imported only ``salkit.resources``;
    and there, ``import numba.core`` before any salkit use of numba leaves numba whole."""
    import subprocess
    import sys
    dump = ("import sys, cloudpickle, salkit.resources as r\n"
            "sys.stdout.buffer.write(cloudpickle.dumps(r._numba_threads_plugin()))\n")
    load = ("import sys, cloudpickle\n"
            "import salkit.resources\n"
            "plugin = cloudpickle.loads(sys.stdin.buffer.read())\n"
            "plugin.setup(None)\n"
            "import numba.core\n"
            "import numba\n"
            "print(numba.core.config.NUMBA_NUM_THREADS, numba.njit(lambda x: x + 1)(1))\n")
    blob = subprocess.run([sys.executable, "-c", dump], capture_output=True, timeout=60, check=True).stdout
    r = subprocess.run([sys.executable, "-c", load], input=blob, capture_output=True, timeout=60,
                       env={**os.environ, "NUMBA_NUM_THREADS": "1"})
    assert r.returncode == 0, r.stderr.decode()
    assert r.stdout.decode().split() == ["1", "2"]


@pytest.mark.skipif(WORKER_START_METHOD != "forkserver", reason="no fork server on this platform: workers spawn")
def test_local_cluster_workers_are_forked_with_salkits_task_modules_loaded_restarted_ones_too():
    """A local cluster's workers come from multiprocessing's fork server, which imported salkit's task
    modules once: before any task, each worker has them, and its parent is the server, not this
    process (a spawned worker imports them itself, ~3 s of CPU each). A worker restarted (here all of
    them, by ``restart``) is forked the same way; the numba threads of a task stay one."""
    from salkit.resources import WORKER_MODULES, dask_client, task_numba_threads

    def origin():
        return os.getppid(), all(m in sys.modules for m in WORKER_MODULES)

    with dask_client(workers=1) as client:
        before = list(client.run(origin).values())
        client.restart()
        after = list(client.run(origin).values())
        threads = client.submit(task_numba_threads, pure=False).result()
    (server, loaded), = before
    assert server != os.getpid() and loaded
    assert after == [(server, True)]
    assert threads == 1


def test_local_cluster_workers_run_numba_on_one_thread_even_from_a_script(tmp_path):
    """A script that imports salkit (so numba) at its top, runs a parallel kernel (its own numba
    threads started, a thread a core) and starts a local cluster in its ``__main__`` block: each
    worker imports the script again before the nanny's ``env`` applies, yet runs its kernels on one
    thread (they ran on every core: 4 threads on 2 cores, each tile twice as slow); and the calling
    process's environment is left alone, so that it compiles new kernels afterwards (setting the
    workers' thread count through Dask's pre-spawn environment wrote it into the caller's
    ``os.environ``, and numba there refused: "Cannot set NUMBA_NUM_THREADS ..."; `make demo` failed)."""
    import os
    import subprocess
    import sys
    script = tmp_path / "job.py"
    script.write_text(
        "import os\n"
        "import numba\n"
        "import numpy as np\n"
        "import salkit.focus  # numba loaded here, and again by each worker\n"
        "from salkit.resources import dask_client\n"
        "from salkit.resources import task_numba_threads\n"
        "def threads():\n"
        "    return numba.config.NUMBA_NUM_THREADS, numba.get_num_threads()\n"
        "def in_task():  # as salkit's tasks (tiles, sub-images, sweep points) begin\n"
        "    task_numba_threads()\n"
        "    return numba.njit(parallel=True)(lambda a: a.sum())(np.ones(10)), threads()\n"
        "if __name__ == '__main__':\n"
        "    here = threads()\n"
        "    numba.njit(parallel=True)(lambda a: a.sum())(np.ones(10))  # this process's threads started\n"
        "    with dask_client(workers=2) as client:\n"
        "        print(sorted(c for c, _ in client.run(threads).values()), client.submit(in_task, pure=False).result())\n"
        "    assert 'NUMBA_NUM_THREADS' not in os.environ, os.environ['NUMBA_NUM_THREADS']\n"
        "    numba.njit(parallel=True)(lambda a: a.max())(np.ones(10))  # compiles after the cluster\n"
        "    print(threads() == here)\n")
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_NUM_THREADS"}  # as a user's shell has it
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().splitlines()[-2:] == ["[1, 1] (10.0, (1, 1))", "True"], r.stdout


@pytest.mark.parametrize("alg,upsample", [("bp", 16), ("bp", 32), ("bp_cubic", 16), ("bp_fitted", 16)])
def test_backprojection_estimate_bounds_its_allocation(alg, upsample):
    """Backprojection's estimate covers what it allocates (tracemalloc: a kernel call's upsampled
    profiles and their packed or padded copy, the accumulators and the image) at the standard and
    the high upsampling, and is not far above it."""
    import tracemalloc

    from salkit import simulate
    from salkit.focus import memory_estimate, phase_history
    from salkit.focus.formers import ImageGrid, get_former
    from salkit.signals.windows import Window
    sc = parse_scenario(SPOT)
    raw = simulate(sc)
    ph = phase_history(raw)
    grid = ImageGrid.of(ph, sc.processing.grid)
    former, win = get_former(alg), Window("none")
    former(ph, grid, win, upsample=upsample)  # compiled before measuring
    tracemalloc.start()
    former(ph, grid, win, upsample=upsample)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    P, M = raw["signal"].shape
    need, what = memory_estimate(P, M, sc.processing.grid.nx, sc.processing.grid.ny, alg, upsample=upsample)
    assert alg in what
    assert peak <= need < 5 * peak, (peak, need)
