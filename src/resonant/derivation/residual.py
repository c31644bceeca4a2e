"""Is a residual zero?  Judging an expression against the size of the terms that form it.

A residual such as ``a*k*(-a + sqrt(a**2))/sqrt(a**2)`` is exactly zero, but
evaluated in floating point (even with 30 digits) it gives a tiny number like
``2.6e-141``.  Judging it against its own top-level terms (here: one product)
calls that tiny number a real residual.  :func:`magnitude` instead propagates
the size of every term through the expression tree -- the sum of the absolute
values of all the arguments of every sum, multiplied through products, powers
and functions (with the function's derivative) -- which bounds the rounding
error of the evaluation.  A value small against that bound is zero.

Examples
--------
>>> import sympy
>>> a, k = sympy.symbols("a k")
>>> expr = a*k*(-a + sympy.sqrt(a**2))/sympy.sqrt(a**2)
>>> is_zero(expr, {a: sympy.Rational(1, 2), k: 100})[0]
True
>>> is_zero(k*(a - sympy.Rational(1, 3)), {a: sympy.Rational(1, 2), k: 100})[0]
False
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import mpmath  # type: ignore[import-untyped]
import sympy

#: a residual is zero when smaller than this times the size of the terms forming it
RELATIVE_TOLERANCE = 1e-9
_DIGITS = 30
_DUMMY = sympy.Dummy("u")


def _number(expr: sympy.Expr, subs: Mapping[Any, Any]) -> complex:
    return complex(expr.evalf(_DIGITS, subs=dict(subs)))


def _walk(expr: sympy.Expr, subs: Mapping[Any, Any],
          memo: dict[sympy.Expr, tuple[Any, float]]) -> tuple[Any, float]:
    """(value, magnitude) of ``expr``; the value as an mpmath number of 30 digits."""
    if expr in memo:
        return memo[expr]
    if not expr.args or expr.is_Number or expr.is_Symbol:
        value = mpmath.mpc(_number(expr, subs)) if not expr.is_Number else \
            mpmath.mpc(complex(expr.evalf(_DIGITS)))
        result = (value, float(abs(value)))
    elif expr.is_Add:
        parts = [_walk(arg, subs, memo) for arg in expr.args]
        result = (mpmath.fsum(p[0] for p in parts), sum(p[1] for p in parts))
    elif expr.is_Mul:
        parts = [_walk(arg, subs, memo) for arg in expr.args]
        value, size = mpmath.mpc(1), 1.0
        for v, s in parts:
            value, size = value * v, size * s
        result = (value, size)
    elif expr.is_Pow:
        (base, bsize), (exp, esize) = (_walk(arg, subs, memo) for arg in expr.args)
        value = mpmath.power(base, exp) if base != 0 or exp.real > 0 else mpmath.mpc(0)
        if expr.exp.is_Number and base != 0:
            # first-order propagation of the error of the base: |e b^(e-1)| * size(b)
            size = float(abs(exp) * abs(mpmath.power(base, exp - 1))) * bsize
        else:
            size = float(abs(value)) + bsize + esize
        result = (value, max(size, float(abs(value))))
    else:
        parts = [_walk(arg, subs, memo) for arg in expr.args]
        value = mpmath.mpc(_number(expr, subs))
        size = float(abs(value))
        if len(expr.args) == 1 and isinstance(expr, sympy.Function):
            try:
                slope = expr.func(_DUMMY).diff(_DUMMY).subs(_DUMMY, expr.args[0])
                size += float(abs(_number(slope, subs))) * parts[0][1]
            except (TypeError, ValueError, ArithmeticError):
                size += parts[0][1]
        else:
            size += sum(p[1] for p in parts)
        result = (value, size)
    memo[expr] = result
    return result


def magnitude(expr: sympy.Expr, subs: Mapping[Any, Any]) -> tuple[complex, float]:
    """The value of ``expr`` at ``subs`` and the size of the terms that form it."""
    with mpmath.workdps(_DIGITS):
        value, size = _walk(sympy.sympify(expr), subs, {})
        return complex(value), size


def is_zero(expr: sympy.Expr, subs: Mapping[Any, Any]) -> tuple[bool, complex]:
    """Whether ``expr`` is zero at ``subs`` to the precision of its evaluation.

    Fast path: the value against the size of the top-level terms.  When that
    fails, the value against :func:`magnitude`, and for a small expression an
    exact decision (``simplify`` with positive symbols).
    """
    if expr == 0:
        return True, 0j
    value = _number(expr, subs)
    scale = sum(abs(_number(term, subs)) for term in sympy.Add.make_args(expr))
    if abs(value) <= RELATIVE_TOLERANCE * max(scale, 1e-300) or abs(value) <= 1e-300:
        return True, value
    try:
        value, size = magnitude(expr, subs)
    except (TypeError, ValueError, ArithmeticError):
        return False, value
    if abs(value) <= RELATIVE_TOLERANCE * size:
        return True, value
    return False, value


__all__ = ["RELATIVE_TOLERANCE", "magnitude", "is_zero"]
