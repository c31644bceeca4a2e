"""Smoke test of benchmarks/bench_nonlinear.py: resonant's side runs and finds both folds
(the timed comparison with pyHarm is the benchmark itself, docs/performance.md)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

import bench_nonlinear  # noqa: E402


def test_resonant_side_runs() -> None:
    wall, data = bench_nonlinear._run(bench_nonlinear.RESONANT)
    assert data["points"] >= 200 and data["stability"] is True
    assert sorted(data["folds"]) == pytest.approx([1.200968, 1.354340], abs=1e-5)
    assert 0 < data["continuation"] <= data["call"] < wall
