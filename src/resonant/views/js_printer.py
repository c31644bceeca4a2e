"""resonant's own printer of sympy expressions as JavaScript (for the explore page).

The explore page computes M, C, K, the loads, the outputs and the drawing in the
browser from the model's symbolic results.  Those reach the page as JavaScript
written here by walking the expression tree -- numbers, symbols, ``+``, ``*``,
powers and the functions of the model language (``Math.sin``, ``Math.sqrt``, ...)
-- never as the text of the model file, and never for ``eval`` or ``new Function``:
the page holds the printed functions as ordinary script.  Every symbol is printed
as an element of an array argument (``p[3]``), so a model's names never become
JavaScript identifiers; anything the printer does not know (a sympy function outside
the model language, infinity, NaN) is refused with :class:`NotPrintable`.

Examples
--------
>>> import sympy
>>> k, m = sympy.symbols("k m")
>>> js_expression(sympy.sqrt(k / m), {k: "p[0]", m: "p[1]"})
'Math.sqrt((p[0]/p[1]))'
>>> print(js_function("f", [k + m, 2 * k * sympy.cos(k + m)], {k: "p[0]", m: "p[1]"}))
function f(p) {
  const t0 = (p[0] + p[1]);
  return [t0, (2*p[0]*Math.cos(t0))];
}
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import sympy

from ..expressions.functions import JAVASCRIPT

#: sympy functions of the model language -> their JavaScript ``Math`` function (the
#: model language's one table, :data:`resonant.expressions.functions.FUNCTIONS`)
FUNCTIONS_JS: dict[type, str] = dict(JAVASCRIPT)
#: the integers that JavaScript's doubles hold exactly
EXACT_INTEGER = 2 ** 53


class NotPrintable(ValueError):
    """An expression the JavaScript printer cannot write (outside the model language).

    Examples
    --------
    >>> raise NotPrintable("zoo")
    Traceback (most recent call last):
    ...
    resonant.views.js_printer.NotPrintable: zoo
    """


def js_number(value: float) -> str:
    """A finite float as a JavaScript literal that reads back to the same double.

    Parameters
    ----------
    value : float
        The number.

    Returns
    -------
    str
        Its shortest round-trip text (Python's ``repr``, which JavaScript parses alike).

    Raises
    ------
    NotPrintable
        For infinity or NaN.

    Examples
    --------
    >>> js_number(0.1), js_number(-2.0), js_number(1e300)
    ('0.1', '(-2.0)', '1e+300')
    """
    if not math.isfinite(value):
        raise NotPrintable(f"the number {value} has no JavaScript literal")
    text = repr(float(value))
    return f"({text})" if text.startswith("-") else text


def _integer(value: int) -> str:
    if abs(value) < EXACT_INTEGER:
        return f"({value})" if value < 0 else str(value)
    return js_number(float(value))


class _Printer:
    """The tree walk; ``names`` maps each symbol (and shared subexpression) to its text."""

    def __init__(self, names: Mapping[sympy.Basic, str]) -> None:
        self.names = names

    def print(self, expr: sympy.Basic) -> str:
        if expr in self.names:
            return self.names[expr]
        if isinstance(expr, sympy.Integer):
            return _integer(int(expr))
        if isinstance(expr, sympy.Rational):
            return f"({_integer(int(expr.p))}/{_integer(int(expr.q))})"
        if isinstance(expr, sympy.Float):
            return js_number(float(expr))
        if expr is sympy.pi:
            return "Math.PI"
        if expr is sympy.E:
            return "Math.E"
        if isinstance(expr, sympy.Add):
            return "(" + " + ".join(self.print(a) for a in expr.args) + ")"
        if isinstance(expr, sympy.Mul):
            return self.product(expr)
        if isinstance(expr, sympy.Pow):
            return self.power(expr)
        function = FUNCTIONS_JS.get(type(expr))
        if function is not None:
            return f"{function}({', '.join(self.print(a) for a in expr.args)})"
        raise NotPrintable(f"cannot write {type(expr).__name__} ({str(expr)[:80]}) as "
                           "JavaScript: it is outside the model language")

    def product(self, expr: sympy.Mul) -> str:
        """``a*b/(c*d)``: the factors with negative integer exponents divide."""
        coefficient, factors = expr.as_coeff_mul()
        top: list[str] = []
        bottom: list[str] = []
        for f in factors:
            if isinstance(f, sympy.Pow) and isinstance(f.args[1], sympy.Integer) \
                    and f.args[1] < 0:
                bottom.append(self.print(f.args[0] ** -f.args[1]))
            else:
                top.append(self.print(f))
        sign = ""
        if isinstance(coefficient, sympy.Rational):
            numerator, denominator = int(coefficient.p), int(coefficient.q)
            if numerator < 0:
                sign, numerator = "-", -numerator
            if numerator != 1 or not top:
                top.insert(0, _integer(numerator))
            if denominator != 1:
                bottom.insert(0, _integer(denominator))
        else:
            top.insert(0, self.print(coefficient))
        text = "*".join(top)
        if bottom:
            text += "/" + (bottom[0] if len(bottom) == 1 else "(" + "*".join(bottom) + ")")
        return f"({sign}{text})"

    def power(self, expr: sympy.Pow) -> str:
        base, exponent = expr.args
        if base is sympy.E:
            return f"Math.exp({self.print(exponent)})"
        b = self.print(base)
        if exponent == sympy.Rational(1, 2):
            return f"Math.sqrt({b})"
        if exponent == sympy.Rational(-1, 2):
            return f"(1/Math.sqrt({b}))"
        if isinstance(exponent, sympy.Integer) and 0 < abs(int(exponent)) <= 4:
            e = abs(int(exponent))
            product = "*".join([b] * e) if e > 1 else b
            return f"({product})" if exponent > 0 else f"(1/({product}))"
        return f"Math.pow({b}, {self.print(exponent)})"


def js_expression(expr: sympy.Basic, names: Mapping[sympy.Basic, str]) -> str:
    """One sympy expression as a JavaScript expression.

    Parameters
    ----------
    expr : sympy.Basic
        An expression of the model language (numbers, symbols, + * ^, its functions).
    names : mapping
        symbol -> its JavaScript text (e.g. ``"p[3]"``); every free symbol needs one.

    Returns
    -------
    str

    Raises
    ------
    NotPrintable
        For a node outside the model language or a symbol without a name.

    Examples
    --------
    >>> x = sympy.Symbol("x")
    >>> js_expression(-x**2 / 3 + sympy.pi, {x: "q[0]"})
    '(Math.PI + (-(q[0]*q[0])/3))'
    """
    missing = sorted(str(s) for s in sympy.sympify(expr).free_symbols if s not in names)
    if missing:
        raise NotPrintable(f"no JavaScript name for the symbol '{missing[0]}'")
    return _Printer(names).print(sympy.sympify(expr))


def js_function(name: str, expressions: Sequence[sympy.Basic],
                names: Mapping[sympy.Basic, str], arguments: Sequence[str] = ("p",)) -> str:
    """A JavaScript function returning the array of ``expressions``, shared parts once.

    Common subexpressions (sympy's ``cse``) become ``const`` temporaries.

    Parameters
    ----------
    name : str
        The function's name (an identifier chosen by resonant, not by a model).
    expressions : sequence of sympy.Basic
        What the returned array holds, in order.
    names : mapping
        symbol -> its JavaScript text, in terms of ``arguments``.
    arguments : sequence of str, optional
        The function's parameters (default ``("p",)``).

    Returns
    -------
    str
        The function's source.

    Raises
    ------
    NotPrintable
        If an expression cannot be written.

    Examples
    --------
    >>> x = sympy.Symbol("x")
    >>> print(js_function("g", [x, 2], {x: "q[0]"}, ("q",)))
    function g(q) {
      return [q[0], 2];
    }
    """
    exprs = [sympy.sympify(e) for e in expressions]
    symbols = sympy.numbered_symbols("__cse")
    shared, reduced = sympy.cse(exprs, symbols=symbols, order="none") if exprs else ([], [])
    table: dict[sympy.Basic, str] = dict(names)
    lines = [f"function {name}({', '.join(arguments)}) {{"]
    for k, (temporary, value) in enumerate(shared):
        lines.append(f"  const t{k} = {js_expression(value, table)};")
        table[temporary] = f"t{k}"
    lines.append("  return [" + ", ".join(js_expression(e, table) for e in reduced) + "];")
    lines.append("}")
    return "\n".join(lines)


__all__ = ["js_expression", "js_function", "js_number", "NotPrintable", "FUNCTIONS_JS"]
