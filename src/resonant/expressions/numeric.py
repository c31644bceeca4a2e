"""Numeric evaluation of parsed expressions with numpy (sympy only to prepare compilation).

Examples
--------
>>> import numpy as np
>>> from resonant.expressions.parser import parse
>>> parse("k*(2 + x^2)").fold(FloatOps({"k": 2.0, "x": np.array([0.0, 1.0])}))
array([4., 6.])
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, TypeAlias, TypeVar

import numpy as np
import numpy.typing as npt
import sympy

from .functions import NUMPY
from .parser import Expression

#: a value while folding: a number, or an array of them (one per set of parameter values)
Value: TypeAlias = float | npt.NDArray[np.floating[Any]]
_E = TypeVar("_E")


class FloatOps:
    """Fold operations evaluating a parsed expression with numpy floats.

    Names resolve through ``values`` (name -> float or array), so an
    expression is evaluated for a whole array of parameter values at once.

    Parameters
    ----------
    values : mapping
        The value of every name the expression uses.

    Examples
    --------
    >>> import numpy as np
    >>> from resonant.expressions.parser import parse
    >>> parse("k/m").fold(FloatOps({"k": np.array([4.0, 9.0]), "m": 1.0}))
    array([4., 9.])
    """

    def __init__(self, values: Mapping[str, Value]) -> None:
        self.values = values

    def num(self, text: str) -> float:
        return float(text)

    def name(self, name: str, primes: int) -> Value:
        if primes:
            return 0.0  # parameters are constants: their time derivatives vanish
        return self.values[name]

    def pi(self) -> float:
        return float(np.pi)

    def add(self, a: Value, b: Value) -> Value:
        return a + b

    def sub(self, a: Value, b: Value) -> Value:
        return a - b

    def mul(self, a: Value, b: Value) -> Value:
        return a * b

    def div(self, a: Value, b: Value) -> Value:
        return np.divide(a, b)

    def neg(self, a: Value) -> Value:
        return -a

    def pow(self, a: Value, b: Value) -> Value:
        return np.power(np.asarray(a, dtype=float), b)

    def call(self, func: str, args: list[Value]) -> Value:
        return NUMPY[func](*args)


def numeric_value(expression: Expression, values: Mapping[str, Any]) -> Any:
    """The float (or array) value of a parsed expression.

    Parameters
    ----------
    expression : Expression
        A parsed expression.
    values : mapping
        name -> number or array, for every name the expression uses.

    Returns
    -------
    float or ndarray
        NaN or infinity where the arithmetic fails (no exception).

    Examples
    --------
    >>> from resonant.expressions.parser import parse
    >>> float(numeric_value(parse("sqrt(k/m)"), {"k": 400, "m": 1}))
    20.0
    """
    with np.errstate(all="ignore"):
        return expression.fold(FloatOps(values))


#: exact numbers beyond this magnitude (or with a larger denominator) are compiled as floats
_EXACT_LIMIT = 2**53


def _inexact(number: sympy.Basic) -> bool:
    return bool(number.is_Rational and (abs(number.p) > _EXACT_LIMIT or number.q > _EXACT_LIMIT))


def compilable(expression: _E) -> _E:
    """``expression`` with its huge exact numbers as floats, ready for :func:`sympy.lambdify`.

    A lambdified sympy expression writes an exact integer as a Python ``int``;
    one beyond 64 bits (``123456789012345678901234567``, or ``10^1196`` built
    by the derivation) reaches numpy as an object and fails inside the
    ufuncs.  As a float it is exact to 16 digits, or infinite beyond 1e308,
    which the callers report as "not finite".

    Parameters
    ----------
    expression : sympy.Expr
        Any sympy expression.

    Returns
    -------
    sympy.Expr
        The same with integers and rationals beyond 64 bits as floats.

    Examples
    --------
    >>> x = sympy.Symbol("x")
    >>> compilable(sympy.cos(x + sympy.Integer(10)**30))
    cos(x + 1.0e+30)
    >>> compilable(x + 1)
    x + 1
    """
    if not isinstance(expression, sympy.Basic) or not any(
            _inexact(a) for a in expression.atoms(sympy.Rational)):
        return expression
    return expression.xreplace({a: sympy.Float(a, 17) for a in expression.atoms(sympy.Rational)
                                if _inexact(a)})


__all__ = ["FloatOps", "numeric_value", "compilable"]
