"""The local cluster's worker processes: set up to run the study's tasks, without the
dashboard's diagnostics, and stopped at the end."""

from __future__ import annotations

import gc
import os
import sys

import dask
import pytest

from resonant.studies.engine import LOCAL_CLUSTER_CONFIG, Engine, _client
from resonant.studies.run import evaluate_chunk


def _worker_state() -> dict:
    return {"pid": os.getpid(), "frozen": gc.get_freeze_count(), "enabled": gc.isenabled(),
            "loaded": "resonant.studies.run" in sys.modules,
            "config": {key: dask.config.get(key) for key in LOCAL_CLUSTER_CONFIG}}


def test_local_workers_load_the_task_code_and_freeze_their_heap():
    """Each worker imported the tasks' module before the first task, froze what was alive
    (so that its full collections and its exit do not walk the libraries' objects), left
    the collector running, ran with the dashboard's diagnostics off, and is gone after."""
    with _client(Engine(mode="local", workers=2), evaluate_chunk) as client:
        states = list(client.run(_worker_state).values())
    assert len(states) == 2
    for state in states:
        assert state["loaded"] and state["enabled"]
        assert state["frozen"] > 10_000  # numpy, sympy and resonant, at least
        assert state["config"] == LOCAL_CLUSTER_CONFIG
        with pytest.raises(ProcessLookupError):  # exited and reaped
            os.kill(state["pid"], 0)
