"""Smoke tests of benchmarks/: every benchmark at a tiny size, so they keep working.

These are not timed tests: they check that each side runs, that both sides of
every benchmark agree (the same assertions the full run makes) and that the
report and the plot are written.  Reference value: the 1-link chain is the
simple pendulum, M = m1 l1^2, K = m1 g l1 (any mechanics text, e.g. Landau &
Lifshitz, Mechanics, Sect. 5 Problem 1 linearized); exact comparison.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

import bench_derivation  # noqa: E402
import bench_sweep  # noqa: E402
import common  # noqa: E402
import pendulum_chain  # noqa: E402
import run as run_all  # noqa: E402


def test_one_link_chain_is_the_simple_pendulum(tmp_path):
    import sympy

    import resonant

    eom = resonant.load(pendulum_chain.write_pendulum_chain(1, tmp_path)).linearize()
    m1, l1, g = (sympy.Symbol(n) for n in ("m1", "l1", "g"))
    plain = {s: sympy.Symbol(s.name) for s in eom.M.free_symbols | eom.K.free_symbols}
    assert sympy.expand(eom.M[0, 0].xreplace(plain) - m1 * l1**2) == 0
    assert sympy.expand(eom.K[0, 0].xreplace(plain) - m1 * g * l1) == 0


@pytest.mark.parametrize("method", ["lagrange", "kane"])
def test_sympy_side_agrees_with_resonant_exactly(method):
    ours, theirs = bench_derivation.child("resonant", 2), bench_derivation.child(method, 2)
    assert bench_derivation.symbolic_equal(ours["M_srepr"], theirs["M_srepr"])
    assert bench_derivation.symbolic_equal(ours["K_srepr"], theirs["K_srepr"])
    assert bench_derivation.numeric_difference(theirs["M"], ours["M"]) <= 1e-12


def test_symbolic_equal_detects_a_difference():
    import sympy

    a = sympy.srepr(sympy.ImmutableMatrix([[sympy.Symbol("m1") * 2]]))
    b = sympy.srepr(sympy.ImmutableMatrix([[sympy.Symbol("m1") * 3]]))
    assert not bench_derivation.symbolic_equal(a, b)


@given(st.floats(0.5, 4.0), st.floats(1e-3, 1e3),
       st.lists(st.integers(2, 10_000), min_size=2, max_size=6, unique=True))
@settings(max_examples=50, deadline=None)
def test_power_law_fit_recovers_exponent_and_scale(p, c, sizes):
    fit = common.fit_power_law(sizes, [c * s**p for s in sizes])
    assert math.isclose(fit[0], p, rel_tol=1e-9, abs_tol=1e-9)
    assert math.isclose(common.extrapolate(fit, 123.0), c * 123.0**p, rel_tol=1e-7)


@pytest.mark.parametrize("variant", bench_sweep.VARIANTS)
def test_every_sweep_side_agrees_at_a_tiny_size(variant):
    row = bench_sweep.run_case(variant, 12, 15, repeats=1, dense_budget=0.2)
    assert row["resonant"] is not None, row["method"]
    assert row["agreement_best"] <= 1e-9
    if variant != "dense":
        assert row["agreement_loop"] <= 1e-9


def test_banded_solve_matches_numpy_on_the_nonproportional_chain():
    import numpy as np

    M, C, K = bench_sweep.chain_matrices(8, "nonprop")
    omegas = bench_sweep.frequencies(M, K, "nonprop", 7)
    assert bench_sweep.agreement(bench_sweep.banded_solve(M, C, K, omegas),
                                 bench_sweep.dense_loop(M, C, K, omegas)) <= 1e-12
    assert not np.allclose(C.toarray(), 0.1 * M.toarray() + 1e-4 * K.toarray())


def test_whole_run_writes_report_and_plot(tmp_path):
    cfg = {"derivation_sizes": [1, 2], "derivation_skip_after": 5.0,
           "derivation_timeout": 60.0, "derivation_repeats": 1,
           "sweep_cases": [("chain", 10, 10), ("chain", 20, 10), ("dense", 10, 10)],
           "dense_budget": 0.2, "sweep_repeats": 1, "matmul_size": 200,
           "e2e_runs": 1, "memory_case": (100, 10)}
    results = {"meta": {"machine": "test", "cpus": 2, "python": "3", "sympy": "x",
                        "numpy": "x", "scipy": "x", "date": "today", "seconds": 1.0,
                        "load_before": "0", "load_after": "0", "threads": 1},
               "derivation": run_all.run_derivation(cfg), "sweep": run_all.run_sweep(cfg),
               "memory": run_all.run_memory(cfg)}
    e2e = {"floor": 1.0, "solve": 1.1, "ratio": 1.1, "runs": 1,
           "imports": bench_sweep_imports(), "profile": []}
    results["end_to_end"] = e2e
    out = tmp_path / "perf.md"
    run_all.plot(results, out.with_suffix(".png"))
    run_all.write_report(results, out, "python benchmarks/run.py --test")
    text = out.read_text()
    assert "## Targets" in text and "| 2 |" in text and "perf.png" in text
    assert out.with_suffix(".png").stat().st_size > 10_000
    assert results["memory"]["peak_mb"] > 10


def bench_sweep_imports():
    import bench_end_to_end

    return bench_end_to_end.parse_importtime(
        "import time: self [us] | cumulative | imported package\n"
        "import time:       150 |        250 |   numpy.core\n"
        "import time:       900 |       1250 | numpy\n")


def test_end_to_end_runs_both_commands():
    import bench_end_to_end

    data = bench_end_to_end.measure(runs=1)
    assert data["solve"] > 0 and data["floor"] > 0
