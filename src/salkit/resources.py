"""Memory guard: estimate a job's peak memory from its sizes and refuse it, with the numbers,
before any work when it would not fit (never let the kernel's out-of-memory killer decide).

The limit is the memory available now (``MemAvailable`` of /proc/meminfo, and the cgroup's
``memory.max`` less ``memory.current`` when smaller), or what ``--max-memory`` / the environment
variable ``SALKIT_MAX_MEMORY`` set, whichever is smaller.
"""
from __future__ import annotations

import logging
import multiprocessing
import os
import re
import signal
import sys
import threading
from contextlib import ExitStack, contextmanager
from functools import lru_cache
from multiprocessing import resource_tracker as _resource_tracker

from .errors import EnvironmentProblem, ResourceError, ScenarioError
from ._lazy import load as _deferred

_dask_distributed = _deferred("dask.distributed")  # not lazy_loader: it imports dask itself at once
_distributed_utils = _deferred("distributed.utils")
# not lazy_loader's stand-in either: that sits in sys.modules as "numba", and an ``import numba.core`` before
# its first use (unpickling anything that names a numba submodule does that) leaves numba.core without its
# ``config`` (a Dask worker of a script that imported salkit.resources at its top failed to start so)
_numba = _deferred("numba")

_LIMIT: int | None = None
_UNITS = {"": 1, "b": 1, "k": 1e3, "kb": 1e3, "m": 1e6, "mb": 1e6, "g": 1e9, "gb": 1e9, "t": 1e12, "tb": 1e12,
          "kib": 2 ** 10, "mib": 2 ** 20, "gib": 2 ** 30, "tib": 2 ** 40}


def parse_size(text: str, field: str = "--max-memory") -> int:
    """Bytes from "8GiB", "512 MB", "2e9".

    Parameters
    ----------
    text : str
    field : str
        Name for the error message.

    Returns
    -------
    int
        Bytes.

    Raises
    ------
    ScenarioError
        Unparseable or not positive.

    Examples
    --------
    >>> parse_size("8GiB"), parse_size("1.5 GB"), parse_size("4096")
    (8589934592, 1500000000, 4096)
    """
    m = re.fullmatch(r"\s*([0-9.]+(?:[eE][+-]?[0-9]+)?)\s*([A-Za-z]*)\s*", str(text))
    if not m or m.group(2).lower() not in _UNITS:
        raise ScenarioError(field, text, "must be a size such as 8GiB, 512MB or 2e9 (bytes)")
    v = float(m.group(1)) * _UNITS[m.group(2).lower()]
    if not v > 0:
        raise ScenarioError(field, text, "must be positive")
    return int(v)


def set_limit(nbytes: int | None) -> None:
    """Set (or with None clear) the user's memory limit, bytes.

    Parameters
    ----------
    nbytes : int or None
    """
    global _LIMIT
    _LIMIT = None if nbytes is None else int(nbytes)


def user_limit() -> int | None:
    """The user's memory limit (``--max-memory``, ``--memory-limit``, ``SALKIT_MAX_MEMORY``), bytes,
    or None: a cap on everything the process holds, unlike the memory available now, which
    already excludes what it holds.

    Returns
    -------
    int or None
    """
    cands = [v for v in (_LIMIT,) if v is not None]
    env = os.environ.get("SALKIT_MAX_MEMORY")
    if env:
        cands.append(parse_size(env, "SALKIT_MAX_MEMORY"))
    return min(cands) if cands else None


def _cgroup_room() -> int | None:
    try:
        mx = open("/sys/fs/cgroup/memory.max").read().strip()
        if mx == "max":
            return None
        cur = int(open("/sys/fs/cgroup/memory.current").read().strip())
        return max(int(mx) - cur, 0)
    except (OSError, ValueError):
        return None


def available_memory() -> int:
    """Bytes this process may still use: the smallest of MemAvailable, the cgroup's room and the
    user's limit (``set_limit``, ``SALKIT_MAX_MEMORY``).

    Returns
    -------
    int
        Bytes.
    """
    cands = []
    try:
        with open("/proc/meminfo") as f:  # closed at once (an open file left to the collector warns)
            for line in f:
                if line.startswith("MemAvailable:"):
                    cands.append(int(line.split()[1]) * 1024)
                    break
    except OSError:
        pass
    if not cands:
        try:
            cands.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (ValueError, OSError):
            cands.append(8 * 2 ** 30)
    cg = _cgroup_room()
    if cg is not None:
        cands.append(cg)
    if _LIMIT is not None:
        cands.append(_LIMIT)
    env = os.environ.get("SALKIT_MAX_MEMORY")
    if env:
        cands.append(parse_size(env, "SALKIT_MAX_MEMORY"))
    return int(min(cands))


def gib(n: float) -> str:
    """A byte count in GiB, for messages.

    Parameters
    ----------
    n : float
        Bytes.

    Returns
    -------
    str

    Examples
    --------
    >>> gib(3 * 2 ** 30)
    '3 GiB'
    """
    return f"{n / 2 ** 30:.3g} GiB"


def size_text(n: float) -> str:
    """A byte count in MiB below 1 GiB, else in GiB, for messages.

    Parameters
    ----------
    n : float
        Bytes.

    Returns
    -------
    str

    Examples
    --------
    >>> size_text(512 * 2 ** 20), size_text(3 * 2 ** 30)
    ('512 MiB', '3 GiB')
    """
    return f"{n / 2 ** 20:.3g} MiB" if n < 2 ** 30 else gib(n)


def check_memory(need: float, what: str, hint: str) -> None:
    """Refuse a job whose estimated peak memory exceeds what is available.

    Parameters
    ----------
    need : float
        Estimated peak, bytes.
    what : str
        The job and the sizes that drive the estimate.
    hint : str
        What to reduce.

    Raises
    ------
    ResourceError
        "needs X GiB, Y GiB available; reduce ...".
    """
    have = available_memory()
    if need > have:
        raise ResourceError(f"{what} needs about {gib(need)} of memory, {gib(have)} available; {hint}")


__all__ = ["available_memory", "check_memory", "gib", "parse_size", "set_limit", "size_text", "user_limit", "in_dask_task"]


def in_dask_task() -> bool:
    """Whether this code runs inside a Dask worker's task.

    Returns
    -------
    bool
    """
    if "distributed" not in sys.modules:
        return False
    try:
        _dask_distributed.get_worker()
        return True
    except ValueError:
        return False


#: Dask settings of a local cluster salkit starts (its workers inherit them): Dask's own periodic
#: work made rare. The statistical profiler (every 10 ms, for a dashboard salkit does not start),
#: the event-loop tick (20 ms), the system and memory monitors (0.5 s, 0.1 s) and work stealing
#: (0.1 s) together kept 0.18 of a core busy on an idle 2-worker cluster (0.024 with these
#: settings, measured), taken from the tiles on a 2-core machine. A worker over its memory is
#: still stopped within a second.
_LOCAL_CLUSTER_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.scheduler.work-stealing-interval": "1s",
}

#: The environment of each local worker: one numba (and BLAS) thread, the worker's one core.
_LOCAL_WORKER_ENV = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


def task_numba_threads() -> int:
    """Called first in a Dask task salkit runs: numba kernels in this thread use the threads the
    worker's environment gives (``NUMBA_NUM_THREADS``, one on a local cluster salkit starts), at
    most the pool numba started with. A worker that loaded numba before its environment was set
    (a script's main module, imported again by the worker) has a pool of a thread a core; without
    this each of its kernels used them all.

    Returns
    -------
    int
        The threads this thread's kernels now use.
    """
    want = os.environ.get("NUMBA_NUM_THREADS")
    if want and want.isdigit() and int(want) >= 1:
        _numba.set_num_threads(min(int(want), _numba.config.NUMBA_NUM_THREADS))
    return _numba.get_num_threads()


@lru_cache(maxsize=1)
def _numba_threads_plugin_class():
    """The class of :func:`_numba_threads_plugin`, made on first use (distributed loads lazily)."""
    class NumbaThreadsFromEnvironment(_dask_distributed.WorkerPlugin):
        name = "salkit-numba-threads"

        def setup(self, worker):  # pragma: no cover - in the worker process (tested from a script)
            _reload_numba_config()  # a module-level function: pickled by name, no module of it by value

    return NumbaThreadsFromEnvironment


def _reload_numba_config() -> None:
    """numba's configuration read again from this process's environment (a Dask worker's, before any
    task runs); left as it is where numba's threads already run (tasks then use fewer of them:
    :func:`task_numba_threads`)."""
    try:
        _numba.core.config.reload_config()
    except RuntimeError:
        pass


def _numba_threads_plugin():
    """Dask worker plugin (registered on a local cluster salkit starts, so restarted workers get it
    too): numba's configuration read again from the worker's environment before any task runs.
    The nanny sets ``NUMBA_NUM_THREADS=1`` in the worker process only after that process has
    imported the calling script's main module again; a script that imports salkit at its top has
    loaded numba by then, configured for a thread a core, and a kernel compiled later in that
    worker would be refused ("Cannot set NUMBA_NUM_THREADS ..."). Not through Dask's pre-spawn
    environment instead: the nanny writes that into the calling process's own ``os.environ``, and
    numba there, its threads running, would then refuse to compile anything more."""
    return _numba_threads_plugin_class()()


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None):
    """A Dask client for the duration of a block: connected to ``scheduler`` if given, else to a
    local cluster of ``workers`` processes (default: one per core) started for the block, each
    with one compute thread (numba's own pool would otherwise put workers x cores threads on the
    cores). Called inside a Dask task (a sweep's point running a stack), the client of the cluster
    that task runs on (``worker_client``: the task leaves its worker's pool while its own tasks
    run there), not a cluster of its own. A local cluster's workers, restarted ones included, start
    by :data:`WORKER_START_METHOD` (forked from a server that has imported :data:`WORKER_MODULES`
    once, where the platform has one), whatever Dask's own setting for its clusters is.

    Parameters
    ----------
    scheduler : str, optional
        Address of an existing Dask scheduler, e.g. ``tcp://host:8786``.
    workers : int, optional
        Local worker processes.

    Yields
    ------
    dask.distributed.Client

    Raises
    ------
    EnvironmentProblem
        When no scheduler answers at ``scheduler`` (nothing has been written).
    """
    if scheduler is None and in_dask_task():  # nested (a sweep's point): the cluster it runs on
        with _dask_distributed.worker_client() as client:
            yield client
        return
    with ExitStack() as held:
        cluster = None
        try:  # connect first: an unreachable scheduler writes nothing
            if scheduler:
                client = _dask_distributed.Client(scheduler, timeout="5s")
            else:
                local = _dask_distributed.LocalCluster
                # held for the block: a worker restarted after one died is started the same way
                held.enter_context(_dask_distributed.dask.config.set(
                    {"distributed.worker.multiprocessing-method": WORKER_START_METHOD}))
                _preload_workers()
                try:
                    with _interrupts_held(), _dask_distributed.dask.config.set(_LOCAL_CLUSTER_CONFIG):
                        cluster = local(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                                        processes=True, dashboard_address=":0", env=_LOCAL_WORKER_ENV)
                    client = _dask_distributed.Client(cluster)
                    client.register_plugin(_numba_threads_plugin())  # restarted workers too
                    client.run(_quiet_worker_logs)
                except BaseException:
                    if cluster is not None:
                        with _quiet_dask():
                            cluster.close()
                    raise
        except (OSError, TimeoutError) as err:
            if cluster is not None:
                cluster.close()
            raise EnvironmentProblem(f"--scheduler {scheduler}: no Dask scheduler answers there "
                                     f"({type(err).__name__})") from None
        try:
            yield client
        finally:
            with _quiet_dask():
                client.close()
                if cluster is not None:
                    cluster.close()


#: How a local cluster's worker processes start: forked from multiprocessing's fork server, which
#: imports :data:`WORKER_MODULES` once, where the platform has one (Linux, macOS); else (Windows)
#: each spawns a fresh interpreter that imports them itself. Spawning cost each worker 3 s of CPU
#: on a 2.45 GHz Zen 3 (2 workers: 6.3 CPU-s, 1.8 s to start and 1.4 s more before the first
#: task ran); forked, the first cluster of a process starts in 2.9 s, its first tasks 0.03 s, and
#: every later cluster of the same process in 0.2 s.
WORKER_START_METHOD = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"

#: The modules of the tasks salkit sends to a local cluster's workers (tiles, simulation blocks,
#: sweep points, sub-images), and Dask's: imported once in the fork server.
WORKER_MODULES = ("distributed", "salkit.focus.tiles", "salkit.focus.pipeline", "salkit.simulate.sal",
                  "salkit.studies.engine", "salkit.stack.stacking")


def _preload_workers() -> None:
    """Name :data:`WORKER_MODULES` to the fork server before it starts (a no-op once it runs, and
    where workers spawn). Dask's own choice of modules is made first, once a process, so that it
    does not replace these when its first worker starts."""
    if WORKER_START_METHOD == "forkserver":
        _distributed_utils.get_mp_context().set_forkserver_preload(list(WORKER_MODULES))


@contextmanager
def _interrupts_held():
    """SIGINT held, not lost, while a local cluster is started, and never delivered to its workers.

    The main thread blocks SIGINT for the block: the cluster's event-loop thread, created now,
    inherits the block, and so do the threads it starts and every worker process they spawn (a
    signal mask survives fork and exec; Python never unblocks it), now or when a nanny restarts a
    worker. A Ctrl-C at the terminal, which reaches every process of the group, then interrupts
    only this process, which closes the cluster (each worker would otherwise print a
    KeyboardInterrupt traceback). A Ctrl-C while the workers start (a thread started earlier, which
    does not block it, may take it) is recorded and raised as the block ends, through the handler
    in place before it. Only in the main thread (where signals are set)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    # multiprocessing's resource tracker, started by the first worker's spawn, unblocks SIGINT in
    # the thread that starts it (it blocks it only for its own start): started here, before the block
    _resource_tracker.ensure_running()
    seen: list[int] = []
    before = signal.signal(signal.SIGINT, lambda signum, frame: seen.append(signum))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.SIG_DFL if before is None else before)
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a held Ctrl-C is delivered here
        if seen:
            signal.raise_signal(signal.SIGINT)  # one taken by another thread while held


def _quiet_worker_logs():
    """Run on each worker of a local cluster salkit started: Dask's own log silenced there (what
    goes wrong in a task reaches the caller as its exception; a worker that dies is reported by
    its nanny in the calling process)."""
    for name in ["distributed"] + [n for n in logging.root.manager.loggerDict if n.startswith("distributed.")]:
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)


@contextmanager
def _quiet_dask():
    """Dask's own log silenced while a client and its cluster close: after an interrupt its
    scheduler and nannies report, with tracebacks, the tasks and connections the closing cut short
    (the run's own message says what happened; the interrupt is tested to leave only that)."""
    names = ["distributed"] + [n for n in logging.root.manager.loggerDict if n.startswith("distributed.")]
    loggers = [logging.getLogger(n) for n in names]
    levels = [lg.level for lg in loggers]
    for lg in loggers:
        lg.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for lg, level in zip(loggers, levels):
            lg.setLevel(level)
