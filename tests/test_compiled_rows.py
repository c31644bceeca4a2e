"""Compiled expressions: ``rows`` (real values, varying rows) against the complex call, and
the numpy namespace of the module object against lambdify's ``"numpy"`` star import.

Two routes, one answer, bit for bit: the same printed code evaluated in either namespace,
and the same values returned as complex or as they came.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy

from resonant.system.batch import compile_expressions

x, y = sympy.symbols("x y")
EXPRESSIONS = [
    x + 1, sympy.Integer(0), sympy.Rational(1, 3) * y, sympy.sin(x) * sympy.cos(y),
    sympy.Abs(x - y), sympy.Heaviside(x - 0.5), sympy.sinc(x), sympy.Max(x, y),
    sympy.Min(x, 2 * y), sympy.Piecewise((x, x > 0.3), (y, True)), sympy.sqrt(x ** 2 + y),
    sympy.sign(x - y), sympy.atan2(y, x), sympy.exp(-x) * sympy.log(1 + y),
    sympy.floor(3 * x), sympy.Mod(7 * x, 2), sympy.asin(x / 2), sympy.tanh(y),
]


@pytest.mark.parametrize("args", [(np.linspace(0.1, 0.9, 7), 0.25),
                                  (0.5, np.linspace(0.2, 0.4, 7)), (0.5, 0.25)])
def test_module_namespace_gives_the_star_import_values(args):
    reference = sympy.lambdify([x, y], EXPRESSIONS, modules="numpy", cse=True)(*args)
    got = compile_expressions(EXPRESSIONS, [x, y])(*args)
    shape = np.broadcast_shapes(*(np.shape(a) for a in args))
    expected = np.array([np.broadcast_to(v, shape) for v in reference], dtype=complex)
    np.testing.assert_array_equal(got, expected)


def test_rows_are_the_call_real_with_the_varying_rows_marked():
    compiled = compile_expressions(EXPRESSIONS, [x, y])
    k = np.linspace(0.1, 0.9, 7)
    values, varying = compiled.rows(k, 0.25)
    assert values.dtype == float
    np.testing.assert_array_equal(values, compiled(k, 0.25).real)
    constant = [not e.has(x) for e in EXPRESSIONS]
    assert varying.tolist() == [not c for c in constant]
    assert (values[~varying] == values[~varying, :1]).all()


def test_rows_keep_complex_values_and_mark_infinite_entries_constant():
    compiled = compile_expressions([x * sympy.I, sympy.zoo, x], [x])
    values, varying = compiled.rows(np.array([1.0, 2.0]))
    assert values.dtype == complex
    assert np.isnan(values[1]).all() and varying.tolist() == [True, False, True]
    np.testing.assert_array_equal(values, compiled(np.array([1.0, 2.0])))
