"""The automatic choice of where a study runs (docs/studies.md): local workers start only
when the time they save on the chunks left exceeds their start-up cost, so a study is
never slower than this process by more than that cost (a 20,000-sample study once took
19.4 s on a 2-worker cluster against 4-7 s here)."""

from __future__ import annotations

import time

import pytest

from resonant.studies import engine
from resonant.studies.engine import Engine, ordered_map


def _chunk(seconds: float, k: int) -> int:
    time.sleep(seconds)
    return k


def _where(seconds: float, count: int, monkeypatch: pytest.MonkeyPatch) -> tuple[str, list]:
    """Where ``count`` chunks of ``seconds`` each run on two cores, without starting
    anything: the workers' route is replaced by a marker."""
    monkeypatch.setattr(engine.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(engine, "_on_dask", lambda function, tasks, eng: iter(
        [("workers", list(tasks))]))
    said: list[str] = []
    out = list(ordered_map(_chunk, ((seconds, k) for k in range(count)), Engine("auto"),
                           on_start=said.append))
    return said[-1], out


def test_a_study_that_would_not_earn_the_start_back_stays_here(monkeypatch):
    # 40 chunks of 10 ms: two workers would save 0.2 s, far below the start-up cost
    where, out = _where(0.01, 40, monkeypatch)
    assert where == "this process" and out == list(range(40))


def test_workers_start_only_when_they_save_more_than_they_cost(monkeypatch):
    # chunks of 50 ms: two workers save 25 ms a chunk; 4 s of start-up takes 160 chunks
    needed = int(engine.START_UP_SECONDS / (0.05 * 0.5))
    where, _ = _where(0.05, needed // 4, monkeypatch)
    assert where == "this process"
    where, out = _where(0.05, needed + 40, monkeypatch)
    assert where != "this process" and out[:2] == [0, 1]  # the first two ran here
    assert out[2][0] == "workers"
