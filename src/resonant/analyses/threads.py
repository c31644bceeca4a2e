"""The BLAS threads that pay off for a piece of dense linear algebra.

OpenBLAS (and MKL) start one thread per core for every call.  A thread whose core
is busy with another process makes all the others wait for it at each step of a
blocked LU: on a two-core machine with one core busy, a stack of forty 200 x 200
complex solves took 17 s with two threads against 0.3 s with one (56x).  And for
small matrices threads never pay (their start-up costs more than the work).

:func:`blas_threads` limits the BLAS threads (through ``threadpoolctl``, when
installed) for the duration of a ``with`` block to :func:`threads_for` the work:
one thread below :data:`PARALLEL_FLOPS` floating-point operations per call; above,
the cores of this process's CPU set that are not busy with other processes (the
1-minute load average or the tasks running at this instant, whichever is larger, less
this process: a busy loop started a second ago is not in the average yet, and two
threads with a busy core made the 10,000-DOF random response 18.5 s instead of 4.5 s).
The method a sweep uses never depends on this: it is chosen from the cost model
(docs/sweeps.md); only the threads the chosen method runs with do.

Examples
--------
>>> threads_for(1e6)
1
>>> import numpy as np
>>> with blas_threads(1e6):
...     x = np.linalg.solve(np.eye(3), np.ones(3))
>>> x.tolist()
[1.0, 1.0, 1.0]
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from typing import Any

#: below this many floating-point operations per BLAS/LAPACK call one thread is used
PARALLEL_FLOPS = 2e8


def cores() -> int:
    """The cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # (not Linux)
        return max(1, os.cpu_count() or 1)


def idle_cores() -> int:
    """The cores of :func:`cores` not busy with other processes (at least 1): the cores
    less the larger of the 1-minute load average and the tasks running right now, this
    process's own run counted out.  The average lags by a minute (a process that has just
    started to keep a core busy is not in it yet); the tasks running now catch it."""
    total = cores()
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):  # (not Unix)
        return total
    busy = max(0.0, load - 1.0, _running_now() - 1.0)
    return int(max(1, min(total, round(total - busy))))


def _running_now() -> float:
    """The tasks running or ready to run at this instant, the caller among them (Linux's
    ``procs_running`` of /proc/stat; 0 where there is none)."""
    try:
        with open("/proc/stat", "rb") as stat:
            for line in stat:
                if line.startswith(b"procs_running "):
                    return float(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return 0.0


def threads_for(flops: float) -> int:
    """The BLAS threads for calls of about ``flops`` floating-point operations each."""
    if not flops >= PARALLEL_FLOPS:
        return 1
    return idle_cores()


@contextlib.contextmanager
def blas_threads(flops: float) -> Iterator[int]:
    """Run the block with :func:`threads_for` ``flops`` BLAS threads; yields the count.
    Without ``threadpoolctl`` the block runs with the library's default."""
    count = threads_for(flops)
    controller = _controller()
    if controller is None:  # threadpoolctl not installed: the default threads
        yield count
        return
    with controller.limit(limits=count, user_api="blas"):
        yield count


_CONTROLLER: list[Any] = []


def _controller() -> Any:
    """One ``threadpoolctl.ThreadpoolController`` (finding the BLAS libraries takes
    milliseconds: done once), or None without threadpoolctl."""
    if not _CONTROLLER:
        try:
            from threadpoolctl import ThreadpoolController
        except ImportError:
            _CONTROLLER.append(None)
        else:
            _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0]


__all__ = ["blas_threads", "threads_for", "idle_cores", "cores", "PARALLEL_FLOPS"]
