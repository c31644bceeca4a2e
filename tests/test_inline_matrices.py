"""Large inline matrices of number literals: read as arrays, the same numbers as the parser.

``resonant check`` of a 3.9 MB model with inline 800 x 800 M, C, K took 24 s and 1 GB
(every entry an expression); the number-only fast path (resonant.model.inline_matrices,
docs/model-format.md) reads it in about 1.3 s and 130 MB (docs/performance.md).  Two
routes to one answer: with the size threshold lowered, the fast path and the expression
parser give bitwise the same matrices for random literals.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from resonant.api import loads
from resonant.errors import ModelError
from resonant.model import inline_matrices
from resonant.system import linear_system

literal = st.one_of(
    st.integers(-10**6, 10**6).map(str),
    st.floats(-1e6, 1e6, allow_nan=False).filter(lambda v: v == 0 or abs(v) > 1e-200)
    .map(lambda v: repr(float(v)).replace("inf", "1")),
    st.tuples(st.integers(1, 9), st.integers(0, 999), st.integers(-30, 30))
    .map(lambda t: f"{t[0]}.{t[1]}e{t[2]:+d}"),
)


def matrix_text(rows: list[list[str]]) -> str:
    return "[" + ",\n  ".join("[" + ", ".join(row) + "]" for row in rows) + "]"


def model_text(n: int, entries: list[str]) -> str:
    K = [entries[i * n:(i + 1) * n] for i in range(n)]
    M = [["1" if i == j else "0" for j in range(n)] for i in range(n)]
    return f"[matrices]\nM = {matrix_text(M)}\nK = {matrix_text(K)}\n"


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])  # set per example
@given(st.integers(3, 6).flatmap(
    lambda n: st.tuples(st.just(n), st.lists(literal, min_size=n * n, max_size=n * n))))
def test_the_fast_path_reads_the_numbers_the_parser_reads(monkeypatch_size, case):
    n, entries = case
    text = model_text(n, entries)
    monkeypatch_size(2)
    fast_model = loads(text)
    assert isinstance(fast_model.matrices.K, np.ndarray)  # the fast way, really
    fast = linear_system(fast_model).numeric()
    monkeypatch_size(10**9)
    exact = linear_system(loads(text)).numeric()
    assert isinstance(loads(text).matrices.K, list)  # the parser's way, really
    np.testing.assert_array_equal(np.asarray(fast.K), np.asarray(exact.K))
    np.testing.assert_array_equal(np.asarray(fast.M), np.asarray(exact.M))


@pytest.fixture
def monkeypatch_size():
    original = inline_matrices.INLINE_EXPRESSION_SIZE

    def set_size(size: int) -> None:
        inline_matrices.INLINE_EXPRESSION_SIZE = size

    yield set_size
    inline_matrices.INLINE_EXPRESSION_SIZE = original


def test_a_large_number_only_matrix_is_one_array():
    n = 250
    rows = [["2" if i == j else "-1" if abs(i - j) == 1 else "0" for j in range(n)]
            for i in range(n)]
    model = loads(f"[matrices]\nM = {matrix_text(rows)}\nK = {matrix_text(rows)}\n")
    assert isinstance(model.matrices.K, np.ndarray) and model.matrices.K.shape == (n, n)
    assert not model.matrices.K.flags.writeable
    assert model.matrices.K[0, 1] == -1.0 and model.matrices.K[5, 5] == 2.0


@pytest.mark.parametrize("change, words", [
    (lambda r: r.replace("[2, ", "[2, 1, ", 1), "must be square"),  # a longer row
    (lambda r: r.replace("[2, ", '["k", ', 1), "unknown name 'k'"),  # an expression
    (lambda r: r.replace("[2, ", "[1e301, ", 1), "number too large"),  # beyond the limits
    (lambda r: r.replace("[2, ", "[true, ", 1), "expected a number or an expression"),
])
def test_anything_but_plain_numbers_takes_the_parsers_way(change, words):
    n = 210
    rows = matrix_text([["2" if i == j else "0" for j in range(n)] for i in range(n)])
    with pytest.raises(ModelError, match=words):
        loads(f"[matrices]\nM = {rows}\nK = {change(rows)}\n")


def test_comments_and_other_tables_are_left_to_the_toml_parser():
    n = 210
    rows = [["1" if i == j else "0" for j in range(n)] for i in range(n)]
    commented = matrix_text(rows).replace("],\n", "],  # a comment\n", 1)
    model = loads(f"[matrices]\nM = {commented}\nK = {matrix_text(rows)}\n")
    assert math.isclose(float(np.trace(np.asarray(linear_system(model).numeric().M))), n)
    text, arrays = inline_matrices.extract_numeric_matrices(
        f"[other]\nK = {matrix_text(rows)}\n")
    assert arrays == {} and text.startswith("[other]\nK = [[")


def test_check_of_a_large_inline_model_is_fast_and_abbreviated(tmp_path):
    n = 800
    def rows(diagonal: str) -> str:
        return "[" + ",\n".join("[" + ",".join(diagonal if i == j else "0" for j in range(n))
                                + "]" for i in range(n)) + "]"
    path = tmp_path / "big.toml"
    path.write_text(f"[matrices]\nM = {rows('1')}\nC = {rows('2')}\nK = {rows('2000')}\n")
    run = subprocess.run([sys.executable, "-m", "resonant", "check", str(path)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert "800 coordinate(s): q1, q2" in run.stdout and "... and 788 more" in run.stdout
