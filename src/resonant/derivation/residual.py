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
from typing import Any, SupportsFloat

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


class Sized:
    """A float together with the size of the terms that formed it (see :func:`magnitude`).

    The numeric counterpart of :func:`magnitude`, for the numeric derivation of large
    models: sums add the sizes, products multiply them, a function adds its slope times
    the size of its argument.  A value within :data:`RELATIVE_TOLERANCE` of its size is
    zero (:meth:`is_zero`), as :func:`is_zero` judges the exact expression.

    Examples
    --------
    >>> a, b = Sized(0.1), Sized(0.2)
    >>> r = a + b - Sized(0.3)
    >>> r.value != 0, r.is_zero(), (a * 3 - b).is_zero()
    (True, True, False)
    """

    __slots__ = ("value", "size")

    def __init__(self, value: float, size: float | None = None) -> None:
        self.value = value
        self.size = abs(value) if size is None else size

    @staticmethod
    def of(x: SupportsFloat) -> Sized:
        return x if isinstance(x, Sized) else Sized(float(x))

    def is_zero(self) -> bool:
        """Whether the value is rounding noise of the terms that formed it."""
        return abs(self.value) <= RELATIVE_TOLERANCE * self.size or abs(self.value) <= 1e-300

    def __add__(self, other: SupportsFloat) -> Sized:
        o = Sized.of(other)
        return Sized(self.value + o.value, self.size + o.size)

    __radd__ = __add__

    def __sub__(self, other: SupportsFloat) -> Sized:
        o = Sized.of(other)
        return Sized(self.value - o.value, self.size + o.size)

    def __rsub__(self, other: SupportsFloat) -> Sized:
        return Sized.of(other) - self

    def __neg__(self) -> Sized:
        return Sized(-self.value, self.size)

    def __mul__(self, other: SupportsFloat) -> Sized:
        o = Sized.of(other)
        return Sized(self.value * o.value, self.size * o.size)

    __rmul__ = __mul__

    def __truediv__(self, other: SupportsFloat) -> Sized:
        o = Sized.of(other)
        # a * b^-1, the size of b^-1 as magnitude() propagates it: size(b) / b^2
        return Sized(self.value / o.value, self.size * o.size / o.value**2)

    def __rtruediv__(self, other: SupportsFloat) -> Sized:
        return Sized.of(other) / self

    def __pow__(self, exponent: SupportsFloat) -> Sized:
        e = float(exponent.value if isinstance(exponent, Sized) else exponent)
        value = self.value ** e
        if not isinstance(value, float):
            raise ValueError("a power that is not real")
        size = abs(e * self.value ** (e - 1)) * self.size if self.value != 0 else abs(value)
        return Sized(value, max(size, abs(value)))

    def __abs__(self) -> float:
        return abs(self.value)

    def __float__(self) -> float:
        return float(self.value)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Sized):
            return self.value == other.value and self.size == other.size
        # only a value formed of nothing is zero (a cancellation is judged by is_zero)
        return bool(self.value == other and (other != 0 or self.size == 0))

    def __hash__(self) -> int:
        return hash((self.value, self.size))

    def __repr__(self) -> str:
        return f"Sized({self.value!r}, {self.size!r})"


__all__ = ["RELATIVE_TOLERANCE", "magnitude", "is_zero", "Sized"]
