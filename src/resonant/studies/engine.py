"""Running tasks in order on Dask: in this process, on local workers, or on a cluster.

resonant does not schedule work itself: :func:`ordered_map` hands tasks to a
``dask.distributed`` client (a :class:`~distributed.LocalCluster` of worker
processes on this machine, or an existing cluster by its scheduler's address)
and hands their results back in the order of the tasks, keeping a bounded
window of tasks in flight so that memory stays bounded however many tasks
there are.  Dask re-runs the tasks of a worker that dies on the others; a task
is a pure function of its arguments, so a re-run gives the same bytes.

``mode="process"`` runs the tasks one after the other in this process (no
Dask at all); ``mode="auto"`` does so for the first two tasks (the first pays
for compiling the model), and starts local workers only when the time they
would save on the tasks left -- the second task's time times the tasks left,
times 1 - 1/workers -- exceeds :data:`START_UP_SECONDS`, the cost of starting
worker processes, which a small study would not earn back.

Examples
--------
>>> list(ordered_map(pow, [(2, 3), (3, 2)], Engine(mode="process")))
[8, 9]
"""

from __future__ import annotations

import collections
import contextlib
import gc
import os
import pickle
import time
import warnings
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import Any

from ..errors import ModelError

#: below this many seconds of estimated work, local workers are not started
START_UP_SECONDS = 4.0
#: the environment of local worker processes, over Dask's own: Dask sets glibc's
#: MALLOC_TRIM_THRESHOLD_ to 64 KiB, which also pins the mmap threshold at 128 KiB, so
#: that every larger array is mapped and unmapped page by page (a study of a
#: 10,000-coordinate model spent half its time in the kernel), and a heap trimmed at every
#: free is faulted in page by page again by the next array (0.35 s a sample of that model
#: instead of 0.23 s); arrays up to 32 MiB come from the heap instead, and up to 32 MiB
#: of free heap stay with the process
WORKER_ENVIRONMENT = {"MALLOC_MMAP_THRESHOLD_": 2**25, "MALLOC_TRIM_THRESHOLD_": 2**25}
#: Dask's diagnostics for its dashboard, which the local cluster here does not serve, off
#: or slowed down: the workers' statistical profiler (100 stack samples a second), the
#: event-loop health tick (50 a second in the scheduler and every nanny and worker) and
#: the system monitor's disk counters (twice a second); at rest they took 16% of a core
#: from a 2-worker study on 2 cores, 4% without them.  The nannies' memory monitor,
#: which restarts a worker about to run out of memory, keeps Dask's setting.
LOCAL_CLUSTER_CONFIG = {"distributed.worker.profile.enabled": False,
                        "distributed.admin.tick.interval": "1s",
                        "distributed.admin.system-monitor.interval": "2s",
                        "distributed.admin.system-monitor.disk": False}
MODES = ("auto", "process", "local", "cluster")


@dataclass(frozen=True)
class Engine:
    """Where tasks run.

    Parameters
    ----------
    mode : {"auto", "process", "local", "cluster"}
        ``process``: here, one after the other; ``local``: ``workers`` worker
        processes on this machine; ``cluster``: the cluster of ``scheduler`` or
        ``client``; ``auto``: here, or local workers when the work pays for them.
    workers : int or None
        Local worker processes (default: one per core).
    scheduler : str or None
        A Dask scheduler's address, ``tcp://HOST:PORT``.
    client : distributed.Client or None
        A client of the caller's (not closed here).

    Examples
    --------
    >>> Engine(mode="local", workers=2).workers
    2
    """

    mode: str = "auto"
    workers: int | None = None
    scheduler: str | None = None
    client: Any = None

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ModelError(f"unknown engine mode '{self.mode}'; the modes are "
                             + ", ".join(MODES))
        if self.workers is not None and not 1 <= self.workers <= 1024:
            raise ModelError(f"workers must be from 1 to 1024, got {self.workers}")
        if self.mode == "cluster" and not (self.scheduler or self.client):
            raise ModelError("a cluster needs a scheduler address or a client")
        if self.scheduler is not None and not self.scheduler.startswith(("tcp://", "tls://",
                                                                           "inproc://")):
            raise ModelError(f"a scheduler address is tcp://HOST:PORT, got "
                             f"'{self.scheduler}'")


@contextlib.contextmanager
def _client(engine: Engine, function: Callable[..., Any]) -> Iterator[Any]:
    """A Dask client for the engine, its local workers set up to run ``function``; what it
    starts, it stops."""
    import dask
    from dask.distributed import Client, LocalCluster

    if engine.client is not None:
        yield engine.client
        return
    if engine.scheduler is not None:
        try:
            client = Client(engine.scheduler, timeout="20s")
        except (OSError, TimeoutError) as exc:
            raise ModelError(f"cannot reach the Dask scheduler at {engine.scheduler}: "
                             f"{exc}") from None
        with client:
            yield client
        return
    workers = engine.workers or os.cpu_count() or 1
    config = {**LOCAL_CLUSTER_CONFIG, **{f"distributed.nanny.pre-spawn-environ.{k}": v
                                         for k, v in WORKER_ENVIRONMENT.items()}}
    with warnings.catch_warnings():  # Dask's notes on ports and sockets are not the user's
        warnings.simplefilter("ignore", ResourceWarning)
        warnings.filterwarnings("ignore", category=UserWarning, module="distributed")
        with dask.config.set(config), \
                LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                             host="127.0.0.1", dashboard_address=None,
                             silence_logs=50) as cluster, Client(cluster) as client:
            # a worker the setup misses (gone, or its import fails) imports the code with
            # its first task, as a worker Dask restarts after a fault does
            client.run(_set_up_worker, pickle.dumps(function), on_error="ignore")
            yield client
            client.run(gc.freeze, on_error="ignore")  # the workers' exits walk nothing


def _set_up_worker(pickled_function: bytes) -> None:
    """In a local worker: import the tasks' code (unpickling the function by reference
    imports its module) with the cyclic garbage collector paused, then freeze what is
    alive.  A worker holds the libraries' and the model's long-lived objects for the whole
    study, as the program does (:func:`resonant.cli.program`): the collector's full passes
    over them free nothing (3% of a sample of a 10,000-coordinate chain), and the last
    one, when the worker exits, held up closing the cluster by 0.4 s."""
    paused = gc.isenabled()
    gc.disable()
    try:
        pickle.loads(pickled_function)
    finally:
        if paused:
            gc.enable()
    gc.freeze()


def _on_dask(function: Callable[..., Any], tasks: Iterator[tuple], engine: Engine
             ) -> Iterator[Any]:
    with _client(engine, function) as client:
        threads = sum(client.nthreads().values()) or 1
        window: collections.deque = collections.deque()
        try:
            for args in tasks:
                window.append(client.submit(function, *args, pure=False))
                if len(window) >= 2 * threads + 2:
                    yield window.popleft().result()
            while window:
                yield window.popleft().result()
        finally:
            for future in window:
                future.cancel()


def ordered_map(function: Callable[..., Any], tasks: Iterable[tuple], engine: Engine,
                on_start: Callable[[str], None] | None = None) -> Iterator[Any]:
    """``function(*args)`` for every ``args`` of ``tasks``, in order.

    Parameters
    ----------
    function : callable
        A module-level function (it travels to the workers by name).
    tasks : iterable of tuple
        The arguments of each call.
    engine : Engine
    on_start : callable, optional
        Told where the tasks run ("this process", "4 local workers", the address).

    Yields
    ------
    Any
        The results, in the order of ``tasks``.

    Examples
    --------
    >>> list(ordered_map(divmod, [(7, 2), (9, 4)], Engine(mode="process")))
    [(3, 1), (2, 1)]
    """
    tasks = iter(tasks)
    say = on_start or (lambda where: None)
    if engine.mode == "process":
        say("this process")
        yield from (function(*args) for args in tasks)
        return
    if engine.mode == "auto":
        # the first task pays for one-time work (compiling the model): the second one's
        # time is the estimate, and workers start only when they save more than they cost
        workers = engine.workers or os.cpu_count() or 1
        elapsed = 0.0
        for _ in range(2):
            args = next(tasks, None)
            if args is None:
                return
            start = time.perf_counter()
            yield function(*args)
            elapsed = time.perf_counter() - start
        saving = elapsed * (1.0 - 1.0 / workers)
        rest = list(_peek(tasks, int(START_UP_SECONDS / max(saving, 1e-6)) + 2))
        if len(rest) * saving < START_UP_SECONDS or workers < 2:
            say("this process")
            yield from (function(*args) for args in rest)
            yield from (function(*args) for args in tasks)
            return
        tasks = _chain(rest, tasks)
    say(engine.scheduler or ("a client's cluster" if engine.client is not None else
                             f"{engine.workers or os.cpu_count()} local workers"))
    yield from _on_dask(function, tasks, engine)


def _peek(tasks: Iterator[tuple], count: int) -> Iterator[tuple]:
    for _ in range(count):
        item = next(tasks, None)
        if item is None:
            return
        yield item


def _chain(first: list[tuple], rest: Iterator[tuple]) -> Iterator[tuple]:
    yield from first
    yield from rest


def engine_for(workers: int | None = None, scheduler: str | None = None,
               client: Any = None) -> Engine:
    """The engine for the usual arguments: ``workers=0`` this process, ``workers=N`` N
    local workers, a ``scheduler`` address or a ``client`` their cluster, none of them
    ``auto``.

    Parameters
    ----------
    workers : int, optional
    scheduler : str, optional
    client : distributed.Client, optional

    Returns
    -------
    Engine

    Examples
    --------
    >>> engine_for(0).mode, engine_for(2).mode, engine_for().mode
    ('process', 'local', 'auto')
    """
    if (scheduler is not None or client is not None) and workers is not None:
        raise ModelError("give either a number of local workers or a cluster, not both")
    if scheduler is not None or client is not None:
        return Engine(mode="cluster", scheduler=scheduler, client=client)
    if workers == 0:
        return Engine(mode="process")
    if workers is not None:
        return Engine(mode="local", workers=workers)
    return Engine()


__all__ = ["Engine", "engine_for", "ordered_map", "START_UP_SECONDS"]
