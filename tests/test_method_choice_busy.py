"""The method ``auto`` chooses rests on the cost model, not on the machine: the same method
(and the same expansion points) while another process holds a core as on an idle
machine; and the BLAS threads never exceed the cores left idle."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("skfem")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import corpus  # noqa: E402

from resonant.analyses import kernel, threads  # noqa: E402
from resonant.system import NumericEOM, NumericHarmonic  # noqa: E402


def sweep_auto(s, w):
    eom = NumericEOM(tuple(f"q{i + 1}" for i in range(s.n)), s.M, s.C, s.K,
                     (NumericHarmonic(1.0, np.zeros(s.n), s.b.real.copy()),))
    batch = eom.batch("omega", w)
    return kernel.solve_harmonic(batch, batch.harmonics[0], "auto", tol=1e-6)


@pytest.mark.parametrize("name", ["grid", "plate"])
def test_same_method_with_a_busy_core(name, monkeypatch):
    monkeypatch.setattr(kernel, "REDUCED_WORTH", 0.0)   # small models: try reduced anyway
    s = corpus.build(name, 900 if name == "grid" else 481)
    w = np.linspace(*s.band, 80)
    idle = sweep_auto(s, w)
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.5)
        loaded = sweep_auto(s, w)
    finally:
        busy.kill()
        busy.wait()
    assert loaded.method == idle.method
    assert np.array_equal(np.isnan(loaded.Z), np.isnan(idle.Z))
    scale = np.abs(idle.Z).max()
    assert np.abs(loaded.Z - idle.Z).max() <= 1e-12 * scale


def test_points_from_the_cost_model_only():
    costs = {"sparse": 0.02, "banded": 0.5, "sparse_fill": 1e5}
    assert kernel.reduced_points(1.0, costs, 10_000) == kernel.reduced_points(1.0, costs,
                                                                              10_000)
    more = kernel.reduced_points(3.0, costs, 10_000)
    assert kernel.reduced_points(1.0, costs, 10_000) <= more <= 40


def test_blas_threads_at_most_the_idle_cores(monkeypatch):
    assert threads.threads_for(1e3) == 1
    monkeypatch.setattr(threads, "cores", lambda: 2)
    monkeypatch.setattr(threads.os, "getloadavg", lambda: (2.0, 2.0, 2.0))
    assert threads.idle_cores() == 1 and threads.threads_for(1e12) == 1
    monkeypatch.setattr(threads.os, "getloadavg", lambda: (1.0, 1.0, 1.0))
    monkeypatch.setattr(threads, "_running_now", lambda: 1.0)  # this process alone
    assert threads.idle_cores() == 2 and threads.threads_for(1e12) == 2
    # a process that has just started to keep a core busy: not in the average yet
    monkeypatch.setattr(threads, "_running_now", lambda: 2.0)
    assert threads.idle_cores() == 1 and threads.threads_for(1e12) == 1


def test_a_busy_core_is_seen_at_once():
    """A busy loop started a moment ago (the 1-minute average has not seen it): the BLAS
    calls get one thread."""
    if threads.cores() < 2 or threads._running_now() == 0:
        pytest.skip("needs two cores and Linux's /proc/stat")
    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.3)
        seen = [threads.idle_cores() for _ in range(20)]
    finally:
        busy.kill()
        busy.wait()
    assert min(seen) < threads.cores(), seen
