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
    # 150 asked; the steps follow the present amplitude, so the overhang takes a few more
    assert data["points"] >= 150 and data["stability"] is True
    assert sorted(data["folds"]) == pytest.approx([1.200968, 1.354340], abs=1e-5)
    assert 0 < data["continuation"] <= data["call"] < wall


def test_pyharm_extrema_of_the_fe_comparison_are_exact_on_parabolas() -> None:
    """pyHarm's folds and peak are refined by a parabola through three points: exact
    for a branch that is a parabola (omega and amplitude quadratic in the point index)."""
    import bench_nonlinear_fe

    index = [0.3 * k for k in range(9)]
    om = [1.7 - (t - 1.1) ** 2 for t in index]     # turns at omega = 1.7
    amp = [0.4 - 2 * (t - 1.25) ** 2 for t in index]  # largest amplitude 0.4
    folds, peak = bench_nonlinear_fe.pyharm_extrema(om, amp)
    assert folds == pytest.approx([1.7], abs=1e-12)
    assert peak == pytest.approx(0.4, abs=1e-12)
