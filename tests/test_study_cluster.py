"""A real Dask cluster on this machine: a scheduler and two workers on 127.0.0.1.

`resonant study --scheduler` gives the same bytes as the run in one process, also when
one worker is killed while it holds tasks (Dask runs them again on the other).
Everything the tests start, they stop.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

distributed = pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "absorber_tolerances.toml"
#: a study of ~20 chunks of about 0.3 s each (peaks over a band of 400 points)
STUDY = ["--samples", "16000", "--seed", "4", "--quantity", "peak:x1",
         "--quantity", "natural_frequency:2", "--band", "omega=10:30:400"]


def _dask(*args: str, log: Path) -> subprocess.Popen:
    handle = log.open("w")
    return subprocess.Popen([sys.executable, "-m", "distributed.cli." + args[0], *args[1:]],
                            stdout=handle, stderr=subprocess.STDOUT, start_new_session=True)


def _stop(process: subprocess.Popen) -> None:
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGTERM)
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait(10)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """A scheduler and two single-threaded workers without nannies (a killed worker stays
    dead); yields (address, {name: process}).  One cluster for the module: the test that
    kills a worker comes last (a test that ran after it would still have one worker)."""
    tmp_path = tmp_path_factory.mktemp("cluster")
    info = tmp_path / "scheduler.json"
    processes = [_dask("dask_scheduler", "--host", "127.0.0.1", "--port", "0",
                       "--no-dashboard", "--scheduler-file", str(info),
                       log=tmp_path / "scheduler.log")]
    workers: dict[str, subprocess.Popen] = {}
    try:
        deadline = time.monotonic() + 60
        while not info.exists() or not info.read_text().strip():
            assert time.monotonic() < deadline, (tmp_path / "scheduler.log").read_text()
            time.sleep(0.2)
        address = json.loads(info.read_text())["address"]
        for name in ("w1", "w2"):
            workers[name] = _dask("dask_worker", address, "--nthreads", "1", "--no-nanny",
                                  "--name", name, "--no-dashboard", "--local-directory",
                                  str(tmp_path / name), log=tmp_path / f"{name}.log")
            processes.append(workers[name])
        with distributed.Client(address, timeout=60) as client:
            client.wait_for_workers(2, timeout=60)
        yield address, workers
    finally:
        for process in reversed(processes):
            _stop(process)


def _study(output: Path, *where: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "resonant", "study", str(MODEL), "-o",
                             str(output), *STUDY, *where], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def test_cluster_gives_the_bytes_of_one_process(cluster, tmp_path):
    address, _ = cluster
    local, remote = tmp_path / "local.parquet", tmp_path / "remote.parquet"
    runs = [_study(local, "--workers", "0"), _study(remote, "--scheduler", address)]
    for run in runs:
        out, err = run.communicate(timeout=600)
        assert run.returncode == 0, err
    assert address in out  # the text says where the chunks ran
    assert local.read_bytes() == remote.read_bytes()


def test_a_killed_worker_loses_nothing(cluster, tmp_path):
    address, workers = cluster
    local, remote = tmp_path / "local.parquet", tmp_path / "remote.parquet"
    reference = _study(local, "--workers", "0")
    run = _study(remote, "--scheduler", address)
    with distributed.Client(address, timeout=60) as client:
        pids = client.run(os.getpid)  # worker address -> process id
        deadline = time.monotonic() + 120
        while True:  # kill a worker while it is computing a chunk
            busy = [w for w, tasks in client.processing().items() if tasks]
            if busy:
                break
            assert time.monotonic() < deadline and run.poll() is None, "no task started"
            time.sleep(0.05)
        victim = next(p for p in workers.values() if p.pid == pids[busy[0]])
        victim.send_signal(signal.SIGKILL)
        victim.wait(10)
    out, err = run.communicate(timeout=600)
    assert run.returncode == 0, err
    reference.communicate(timeout=600)
    assert reference.returncode == 0
    assert local.read_bytes() == remote.read_bytes()
