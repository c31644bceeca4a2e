"""The options of the analyses as records (resonant.model.options, docs/architecture.md):
the keywords and the record are two routes to one result, a value out of range gets one
message whichever route it came by, and the command line offers exactly the record's
choices."""

from __future__ import annotations

import argparse

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import resonant
from conftest import EXAMPLES, run_cli
from resonant.errors import AnalysisError
from resonant.model.options import (
    MAX_GIVEN_HARMONICS,
    SWEEP_METHODS,
    BalanceOptions,
    SimulationOptions,
    SweepOptions,
)


@pytest.fixture(scope="module")
def cart():
    return resonant.load(EXAMPLES / "cart_pendulum.toml")


@settings(max_examples=15, deadline=None)
@given(method=st.sampled_from(["auto", "direct", "dense"]),
       values=st.lists(st.floats(1.0, 30.0), min_size=1, max_size=6, unique=True))
def test_record_and_keywords_give_one_sweep(cart, method, values):
    eom = cart.linearize()
    a = eom.sweep("omega", sorted(values), method=method, names=["x1"])
    b = eom.sweep("omega", sorted(values), options=SweepOptions(method=method, names=("x1",)))
    assert a.to_dict() == b.to_dict()


def test_record_and_keywords_give_one_branch_and_one_simulation():
    duffing = resonant.load(EXAMPLES / "duffing.toml")
    a = duffing.nonlinear_sweep("omega", 0.8, 1.2, harmonics=1, points=15, linear=False)
    b = duffing.nonlinear_sweep("omega", 0.8, 1.2,
                                options=BalanceOptions(harmonics=1, points=15, linear=False))
    np.testing.assert_array_equal(a.coefficients, b.coefficients)
    model = resonant.load(EXAMPLES / "two_dof_free.toml")
    s1 = model.simulate(0.05, initial={"x1": 0.01})
    s2 = model.simulate(options=SimulationOptions(duration=0.05, initial={"x1": 0.01}))
    assert s1.to_dict() == s2.to_dict()


def test_record_and_keywords_together_are_refused(cart):
    with pytest.raises(AnalysisError, match=r"either as options= or as keywords.*\(method\)"):
        cart.linearize().sweep("omega", [5.0], method="dense",
                               options=SweepOptions(method="sparse"))
    with pytest.raises(AnalysisError, match="options must be a SweepOptions"):
        cart.linearize().sweep("omega", [5.0], options=BalanceOptions())  # type: ignore[arg-type]


@pytest.mark.parametrize(("make", "message"), [
    (lambda: SweepOptions(method="fastest"), "unknown method 'fastest'"),
    (lambda: SweepOptions(tol=1.5), "between 0 and 1"),
    (lambda: SweepOptions(tol=float("nan")), "between 0 and 1"),
    (lambda: BalanceOptions(harmonics=MAX_GIVEN_HARMONICS + 1), "harmonics must be between"),
    (lambda: BalanceOptions(harmonics=True), "harmonics must be between"),
    (lambda: BalanceOptions(points=2), "points must be at least 3"),
    (lambda: BalanceOptions(samples=0), "samples must be a positive"),
    (lambda: SimulationOptions(duration=-1.0), "positive number of seconds"),
    (lambda: SimulationOptions(periods=float("inf")), "periods must be positive"),
    (lambda: SimulationOptions(method="Euler"), "method must be one of"),
    (lambda: SimulationOptions(rtol=0.0), "rtol must be"),
])
def test_a_value_out_of_range_is_named(make, message):
    with pytest.raises(AnalysisError, match=message):
        make()


def test_keywords_and_command_line_get_the_records_message(cart):
    with pytest.raises(AnalysisError, match="harmonics must be between 1 and 200, not 500"):
        resonant.load(EXAMPLES / "duffing.toml").nonlinear_sweep("omega", 0.8, 1.2,
                                                                 harmonics=500)
    code, _, err = run_cli(["sweep", EXAMPLES / "cart_pendulum.toml", "--param", "omega",
                            "--from", "1", "--to", "2", "--method", "fastest"])
    assert code == 2 and "fastest" in err and "Traceback" not in err


def test_the_command_lines_methods_are_the_records():
    import resonant.cli.analyses as cli_analyses

    parser = argparse.ArgumentParser()
    cli_analyses.register(parser.add_subparsers(), argparse.ArgumentParser(add_help=False))
    sweep = parser._subparsers._group_actions[0].choices["sweep"]  # type: ignore[union-attr]
    method = next(a for a in sweep._actions if a.dest == "method")
    assert tuple(method.choices) == SWEEP_METHODS


def test_the_methods_table_of_the_guide_is_the_code_table():
    """docs/sweeps.md lists each method of ``SOLVE_METHODS`` with its own words: a new
    method is one entry in the code, and the guide cannot drift from it."""
    from pathlib import Path

    from resonant.model.options import SOLVE_METHODS

    text = (Path(__file__).resolve().parents[1] / "docs" / "sweeps.md").read_text(
        encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith("| `")]
    listed = {}
    for row in rows:
        cells = [cell.strip() for cell in row.strip("|").split("|")]
        listed[cells[0].strip("`")] = (cells[1], cells[2])
    for name, method in SOLVE_METHODS.items():
        key = next(k for k in listed if k.split("`")[0] == name)
        assert listed[key] == (method.does, method.exact), name
    assert set(SWEEP_METHODS) == set(SOLVE_METHODS)


def test_every_method_the_kernel_is_given_is_one_it_knows():
    """An unknown method is refused by the kernel itself, not solved as another one."""
    import numpy as np

    from resonant.analyses.kernel import solve_harmonic
    from resonant.system.batch import BatchHarmonic

    eom = resonant.load(EXAMPLES / "cart_pendulum.toml").linearize()
    batch = eom.batch("omega", np.array([1.0, 2.0]))
    n = len(batch.coordinates)
    harmonic = BatchHarmonic(np.array([1.0, 2.0]), np.zeros(n), np.ones(n))
    with pytest.raises(AnalysisError, match="unknown method 'fastest'"):
        solve_harmonic(batch, harmonic, "fastest")
