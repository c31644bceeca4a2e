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
import logging
import math
import os
import pickle
import signal
import threading
import time
import warnings
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..deadline import NO_DEADLINE, AnalysisTimeout, Deadline
from ..errors import AnalysisError, ModelError, Problem, printable

if TYPE_CHECKING:
    from dask.distributed import Client, Future, LocalCluster

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
#: local workers per core at most (the tasks are numeric: more would only share the cores)
WORKERS_PER_CORE = 4
#: memory a local worker needs (its Python, numpy, scipy, sympy and the model), in bytes
WORKER_MEMORY = 256 * 2**20
#: seconds to connect to a scheduler when the command has no time limit
CONNECT_SECONDS = 30.0
#: schemes of a Dask scheduler address
SCHEMES = ("tcp", "tls", "inproc")


def _where(address: str) -> str:
    return f"scheduler '{printable(address, limit=80)}'"


def parse_scheduler(address: str) -> str:
    """A Dask scheduler's address, checked: ``tcp://HOST:PORT`` (``tls://`` too; an IPv6
    host in brackets, ``tcp://[::1]:8786``), or ``inproc://...``.

    Parameters
    ----------
    address : str

    Returns
    -------
    str
        The address, stripped of surrounding blanks.

    Raises
    ------
    ModelError
        For anything else, naming the address.

    Examples
    --------
    >>> parse_scheduler("tcp://[::1]:8786")
    'tcp://[::1]:8786'
    >>> parse_scheduler("tcp://[::1")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    resonant.errors.ModelError: scheduler 'tcp://[::1': the address has an unclosed '[' ...
    """
    text = address.strip()
    scheme, sep, rest = text.partition("://")
    problem = ""
    if not sep or scheme not in SCHEMES:
        problem = "the address is not tcp://HOST:PORT"
    elif scheme == "inproc":
        return text
    elif any(c.isspace() or c in "/?#@" for c in rest):
        problem = "the address is HOST:PORT after tcp:// (no path, blanks or user)"
    elif rest.startswith("["):
        host, close, after = rest[1:].partition("]")
        if not close:
            problem = "the address has an unclosed '[' (an IPv6 host is written " \
                      "tcp://[::1]:8786)"
        elif not host or not after.startswith(":"):
            problem = "the address is tcp://[IPv6 HOST]:PORT"
        port = after[1:]
    else:
        host, colon, port = rest.rpartition(":")
        if not colon or not host or ":" in host:
            problem = "the address is tcp://HOST:PORT (an IPv6 host in brackets)"
    if not problem and not (port.isdigit() and 1 <= int(port) <= 65535):
        problem = f"the port '{port}' is not a number from 1 to 65535"
    if problem:
        raise ModelError(Problem(problem, _where(address)))
    return text


def _available_memory() -> float:
    """Bytes of memory available to new processes (MemAvailable of Linux; else the free
    pages; else unbounded)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, OSError, ValueError):
        return math.inf


def machine_workers() -> tuple[int, int, float]:
    """The most local workers this machine can run, its cores and its available memory
    (GiB): :data:`WORKERS_PER_CORE` per core, and :data:`WORKER_MEMORY` each.

    Examples
    --------
    >>> most, cores, memory = machine_workers()
    >>> 1 <= most <= WORKERS_PER_CORE * cores
    True
    """
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    available = _available_memory()
    most = WORKERS_PER_CORE * cores
    if math.isfinite(available):
        most = min(most, int(available // WORKER_MEMORY))
    return max(1, most), cores, available / 2**30


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
    deadline : Deadline
        The limit of the whole run: connecting to a scheduler and waiting for results
        end with an error when it passes.

    Examples
    --------
    >>> Engine(mode="local", workers=2).workers
    2
    """

    mode: str = "auto"
    workers: int | None = None
    scheduler: str | None = None
    client: Client | None = None
    deadline: Deadline = field(default=NO_DEADLINE, compare=False, repr=False)

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ModelError(f"unknown engine mode '{self.mode}'; the modes are "
                             + ", ".join(MODES))
        if self.workers is not None and not 1 <= self.workers <= 1024:
            raise ModelError(f"workers must be from 1 to 1024, got {self.workers}")
        if self.mode == "cluster" and not (self.scheduler or self.client):
            raise ModelError("a cluster needs a scheduler address or a client")
        if self.scheduler is not None:
            parse_scheduler(self.scheduler)
        if self.mode == "local" and self.workers is not None:
            most, cores, memory = machine_workers()
            if self.workers > most:
                raise ModelError(Problem(
                    f"{self.workers} local workers are more than this machine runs: it has "
                    f"{cores} cores and {memory:.1f} GiB of memory available, enough for "
                    f"{most} workers; ask for at most {most}, or use a cluster (scheduler)",
                    "workers"))


@contextlib.contextmanager
def _client(engine: Engine, function: Callable[..., Any]) -> Iterator[Client]:
    """A Dask client for the engine, its local workers set up to run ``function``; what it
    starts, it stops."""
    import dask
    from dask.distributed import Client, LocalCluster

    if engine.client is not None:
        yield engine.client
        return
    if engine.scheduler is not None:
        with _connect(engine) as client:
            yield client
        return
    workers = engine.workers or os.cpu_count() or 1
    config = {**LOCAL_CLUSTER_CONFIG, **{f"distributed.nanny.pre-spawn-environ.{k}": v
                                         for k, v in WORKER_ENVIRONMENT.items()}}
    with warnings.catch_warnings():  # Dask's notes on ports and sockets are not the user's
        warnings.simplefilter("ignore", ResourceWarning)
        warnings.filterwarnings("ignore", category=UserWarning, module="distributed")
        with dask.config.set(config), \
                _local_cluster(LocalCluster, workers, engine.deadline) as cluster, \
                Client(cluster) as client:
            # a worker the setup misses (gone, or its import fails) imports the code with
            # its first task, as a worker Dask restarts after a fault does
            client.run(_set_up_worker, pickle.dumps(function), on_error="ignore")
            yield client
            client.run(gc.freeze, on_error="ignore")  # the workers' exits walk nothing


@contextlib.contextmanager
def _local_cluster(cluster_type: Callable[..., LocalCluster], workers: int,
                   deadline: Deadline = NO_DEADLINE) -> Iterator[LocalCluster]:
    """Start local workers within the run's time limit; a failure to start them is an
    error in one line."""
    try:
        cluster = _started(cluster_type, workers, deadline)
    except (RuntimeError, OSError, TimeoutError, MemoryError) as exc:
        _abandon_clusters()
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise AnalysisError(f"{workers} local workers could not start ({printable(first)}); "
                            "ask for fewer workers or use a cluster (scheduler)") from None
    except BaseException:  # an interrupt or the time limit while they start
        _abandon_clusters()
        raise
    with cluster:
        yield cluster


def _started(cluster_type: Callable[..., LocalCluster], workers: int, deadline: Deadline
             ) -> LocalCluster:
    """The cluster, started on a thread and waited for no longer than the deadline allows
    (Dask bounds each worker's start by its own timeouts, not by the run's limit).  A
    cluster whose start is given up is closed as soon as it is up."""
    box: dict[str, Any] = {}
    given_up = threading.Event()

    def start() -> None:
        try:
            box["cluster"] = cluster_type(
                n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                dashboard_address=None, silence_logs=50)
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread
            box["error"] = exc
        if given_up.is_set():
            _abandon_clusters()

    thread = threading.Thread(target=start, name="resonant-workers", daemon=True)
    thread.start()
    try:
        thread.join(deadline.remaining())
    finally:
        if thread.is_alive():
            given_up.set()
    if thread.is_alive():
        # the abandoned start goes on logging (Dask restores its log level when a cluster
        # closes, and this one closes only once it is up): not the user's concern
        logging.getLogger("distributed").setLevel(logging.ERROR)
        raise AnalysisTimeout(
            f"the analysis exceeded the time limit of {deadline.seconds:g} s while starting "
            f"{workers} local workers; ask for fewer workers, or allow more time (timeout, "
            "0 for none)")
    if "error" in box:
        raise box["error"]
    return box["cluster"]


def _abandon_clusters() -> None:
    """Close the local clusters whose start was cut short, here and now: Dask's own
    closing of them when the program exits fails on a half-started one with a traceback.
    Their worker processes are daemons and end with this process."""
    from distributed.deploy.spec import SpecCluster

    clusters = list(SpecCluster._instances)
    for cluster in clusters:
        with contextlib.suppress(Exception):
            cluster.close(timeout=5)
    # forgotten by identity: the set's own ``discard`` compares clusters by name, which one
    # cut short in its constructor does not have yet (an AttributeError)
    others = [c for c in SpecCluster._instances if not any(c is d for d in clusters)]
    SpecCluster._instances.clear()
    SpecCluster._instances.update(others)


@contextlib.contextmanager
def _connect(engine: Engine) -> Iterator[Client]:
    """A client of the scheduler at ``engine.scheduler``, connected within the run's time
    limit (Dask's own connect timeout does not bound a peer that accepts the connection
    and never answers: the connection is made on a thread, waited for up to the limit)."""
    from dask.distributed import Client

    address = str(engine.scheduler)
    left = engine.deadline.remaining()
    seconds = CONNECT_SECONDS if left is None else max(left, 0.1)
    box: dict[str, Any] = {}

    def connect() -> None:
        try:
            box["client"] = Client(address, timeout=0.9 * seconds, set_as_default=False)
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread
            box["error"] = exc

    thread = threading.Thread(target=connect, name="resonant-connect", daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive() or "client" not in box:
        error = box.get("error")
        limit = engine.deadline.seconds or CONNECT_SECONDS
        why = (f"it did not answer within the time limit of {limit:g} s"
               if thread.is_alive() or isinstance(error, (TimeoutError, OSError)) else
               f"{printable(error) or type(error).__name__}")
        raise ModelError(Problem(f"cannot reach the Dask scheduler: {why}; check that it "
                                 "runs at this address (and allow more time with the "
                                 "timeout)", _where(address)))
    with box["client"] as client:
        yield client


def _set_up_worker(pickled_function: bytes) -> None:
    """In a local worker: import the tasks' code (unpickling the function by reference
    imports its module) with the cyclic garbage collector paused, then freeze what is
    alive.  A worker holds the libraries' and the model's long-lived objects for the whole
    study, as the program does (:func:`resonant.cli.program`): the collector's full passes
    over them free nothing (3% of a sample of a 10,000-coordinate chain), and the last
    one, when the worker exits, held up closing the cluster by 0.4 s."""
    with contextlib.suppress(ValueError):  # an interrupt is the main process's to handle: it
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # stops the workers, who say nothing
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
                    yield _result(window.popleft(), engine.deadline)
            while window:
                yield _result(window.popleft(), engine.deadline)
        finally:
            for future in window:
                future.cancel()


def _result(future: Future, deadline: Deadline) -> Any:
    """A task's result, waited for no longer than the deadline allows."""
    try:
        return future.result(timeout=deadline.remaining())
    except TimeoutError:
        if not deadline.expired:
            raise
        raise AnalysisTimeout(
            f"the analysis exceeded the time limit of {deadline.seconds:g} s while waiting "
            "for the workers; ask for less or allow more time (timeout, 0 for none)") from None


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
    count = engine.workers or os.cpu_count() or 1
    say(engine.scheduler or ("a client's cluster" if engine.client is not None else
                             f"{count} local worker{'s' if count != 1 else ''}"))
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
               client: Client | None = None, deadline: Deadline = NO_DEADLINE) -> Engine:
    """The engine for the usual arguments: ``workers=0`` this process, ``workers=N`` N
    local workers, a ``scheduler`` address or a ``client`` their cluster, none of them
    ``auto``.

    Parameters
    ----------
    workers : int, optional
    scheduler : str, optional
    client : distributed.Client, optional
    deadline : Deadline, optional
        The run's time limit (connecting and waiting for workers included).

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
        return Engine(mode="cluster", scheduler=scheduler, client=client, deadline=deadline)
    if workers == 0:
        return Engine(mode="process", deadline=deadline)
    if workers is not None:
        return Engine(mode="local", workers=workers, deadline=deadline)
    return Engine(deadline=deadline)


__all__ = ["Engine", "engine_for", "machine_workers", "ordered_map", "parse_scheduler",
           "START_UP_SECONDS"]
