"""Smoke test of benchmarks/bench_corpus.py at a tiny size (not timed): every column is
filled, the reduced model's estimate is at least its true error, the table prints."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

pytest.importorskip("skfem")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import bench_corpus  # noqa: E402


@pytest.mark.parametrize("name", ["chain", "plate"])
def test_bench_corpus_runs(name):
    row = bench_corpus.run_case(name, 150, 24)
    assert row["method"] in ("dense", "banded", "sparse", "modal", "reduced")
    assert row["estimated"] >= row["true"]
    assert all(row[k] > 0 for k in ("auto", "loop", "sparse", "same"))
    text = bench_corpus.table([row])
    assert text.count("\n") == 2 and f"| {name} |" in text
