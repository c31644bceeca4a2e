"""Mathematical notation of the report: names, expressions, numbers and matrices as LaTeX.

Model names become textbook symbols (``m1`` -> :math:`m_{1}`, ``eps`` ->
:math:`\\varepsilon`, ``x1'`` -> :math:`\\dot{x}_{1}`); parsed expressions are
printed from their syntax tree, so an energy reads as it was written in the
model file; derived (sympy) expressions are printed by :func:`sympy.latex` with
the same symbol names.

Examples
--------
>>> name_latex("m1"), name_latex("eps"), name_latex("x2", 1), name_latex("n_rpm")
('m_{1}', '\\\\varepsilon', '\\\\dot{x}_{2}', 'n_{\\\\mathrm{rpm}}')
>>> from resonant.expressions import parse
>>> expression_latex(parse("k*(x1 - r)^2/2 - m2*g*l/2*cos(phi)"), Namer())
'\\\\frac{k \\\\left(x_{1} - r\\\\right)^{2}}{2} - \\\\frac{m_{2} g l}{2} \\\\cos\\\\left(\\\\varphi\\\\right)'
>>> number_latex(0.0021656), number_latex(-1100.0), number_latex(2.5013e-4)
('0.002166', '-1100', '2.501 \\\\cdot 10^{-4}')
"""  # noqa: E501 - doctest expected output is one line and cannot be wrapped

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy

from ..errors import printable
from ..expressions import Expression
from ..expressions.functions import FUNCTIONS

GREEK = ("alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota",
         "kappa", "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "upsilon", "phi",
         "chi", "psi", "omega", "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma",
         "Upsilon", "Phi", "Psi", "Omega")
#: the letter forms of textbooks (the exercise writes varepsilon and varphi)
VARIANTS = {"eps": r"\varepsilon", "epsilon": r"\varepsilon", "phi": r"\varphi",
            "lam": r"\lambda"}
SIGNIFICANT = 4


def _word(word: str) -> str:
    if word in VARIANTS:
        return VARIANTS[word]
    if word in GREEK:
        return "\\" + word
    if len(word) == 1:
        return word
    return r"\mathrm{" + word.replace("_", r"\_") + "}"


def name_latex(name: str, primes: int = 0) -> str:
    """A model name (with ``primes`` time derivatives) as a LaTeX symbol.

    A trailing number or the part after the first underscore becomes a
    subscript; a Greek prefix followed by one or two letters (``thetaS``)
    becomes a Greek letter with a subscript; a two-letter name is a letter with a
    one-letter index, as textbooks write a suspension's stiffness ``ks`` -> :math:`k_{s}`.

    Examples
    --------
    >>> name_latex("ks"), name_latex("mu"), name_latex("stroke")
    ('k_{s}', '\\\\mu', '\\\\mathrm{stroke}')
    """
    base, _, sub = name.partition("_")
    if not sub:
        match = re.fullmatch(r"([A-Za-z]+?)([0-9]+)", base)
        if match:
            base, sub = match.groups()
        elif re.fullmatch(r"[A-Za-z]{2}", base) and base not in GREEK and base not in VARIANTS:
            base, sub = base[0], base[1]
        elif base not in GREEK and base not in VARIANTS:
            greek = next((g for g in sorted(GREEK, key=len, reverse=True)
                          if base.startswith(g) and 0 < len(base) - len(g) <= 2), None)
            if greek:
                base, sub = greek, base[len(greek):]
    head = _word(base)
    if primes == 1:
        head = r"\dot{" + head + "}"
    elif primes == 2:
        head = r"\ddot{" + head + "}"
    text = head
    if sub:
        text += "_{" + (sub if sub.isdigit() or len(sub) == 1 else _word(sub)) + "}"
    if primes > 2:
        text += "^{(" + str(primes) + ")}"
    return text


@dataclass
class Namer:
    """LaTeX of the names of one model: signals carry ``(t)`` as in the exercise."""

    signals: frozenset[str] = frozenset()
    cache: dict[tuple[str, int], str] = field(default_factory=dict)

    def __call__(self, name: str, primes: int = 0) -> str:
        key = (name, primes)
        if key not in self.cache:
            text = name_latex(name, primes)
            if name in self.signals:
                text += "(t)"
            self.cache[key] = text
        return self.cache[key]

    def symbol_names(self, symbols: Iterable[sympy.Symbol]) -> dict[sympy.Symbol, str]:
        """``symbol_names`` for :func:`sympy.latex`: ``x1'`` -> ``\\dot{x}_{1}``."""
        out = {}
        for s in symbols:
            stripped = s.name.rstrip("'")
            if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", stripped):
                out[s] = self(stripped, len(s.name) - len(stripped))
        return out


# -- parsed expressions --------------------------------------------------------------------

_ADD, _MUL, _NEG, _POW, _ATOM = 1, 2, 3, 4, 5


def _paren(text: str) -> str:
    return r"\left(" + text + r"\right)"


class _LatexOps:
    """Folds a syntax tree into ``(latex, precedence, starts_with_digit)``."""

    def __init__(self, namer: Callable[[str, int], str]) -> None:
        self.namer = namer

    def num(self, text: str) -> tuple[str, int, bool]:
        mantissa, _, exponent = text.lower().partition("e")
        if exponent:
            exp = int(exponent)
            if mantissa.rstrip("0").rstrip(".") in ("1", "1."):
                return f"10^{{{exp}}}", _POW, True
            return f"{mantissa} \\cdot 10^{{{exp}}}", _MUL, True
        return text, _ATOM, True

    def pi(self) -> tuple[str, int, bool]:
        return r"\pi", _ATOM, False

    def name(self, name: str, primes: int) -> tuple[str, int, bool]:
        return self.namer(name, primes), _ATOM, False

    def add(self, a: tuple, b: tuple) -> tuple[str, int, bool]:
        right = b[0]
        if b[1] == _NEG:  # a + (-b) reads a - b only if written so; keep the sign visible
            right = _paren(right)
        return f"{a[0]} + {right}", _ADD, a[2]

    def sub(self, a: tuple, b: tuple) -> tuple[str, int, bool]:
        right = _paren(b[0]) if b[1] <= _ADD or b[1] == _NEG else b[0]
        return f"{a[0]} - {right}", _ADD, a[2]

    def mul(self, a: tuple, b: tuple) -> tuple[str, int, bool]:
        left = _paren(a[0]) if a[1] <= _ADD else a[0]
        right = _paren(b[0]) if b[1] <= _ADD or b[1] == _NEG else b[0]
        joiner = r" \cdot " if b[2] and b[1] != _NEG else " "
        return f"{left}{joiner}{right}", _MUL, a[2] and a[1] != _ADD

    def div(self, a: tuple, b: tuple) -> tuple[str, int, bool]:
        return rf"\frac{{{a[0]}}}{{{b[0]}}}", _MUL, False

    def pow(self, a: tuple, b: tuple) -> tuple[str, int, bool]:
        base = a[0] if a[1] == _ATOM and not a[0].endswith("(t)") else _paren(a[0])
        if a[1] == _ATOM and a[0].endswith("(t)"):
            base = a[0]  # r(t)^{2} reads like f(t)^2
        return f"{base}^{{{b[0]}}}", _POW, a[2]

    def neg(self, a: tuple) -> tuple[str, int, bool]:
        inner = _paren(a[0]) if a[1] <= _ADD else a[0]
        return f"-{inner}", _NEG, False

    def call(self, func: str, args: list[tuple]) -> tuple[str, int, bool]:
        # the form of the model language's one table of functions
        return FUNCTIONS[func].write_latex(*(a[0] for a in args)), _ATOM, False


def expression_latex(expression: Expression, namer: Callable[[str, int], str]) -> str:
    """A parsed expression as LaTeX, in the order and grouping it was written."""
    return expression.fold(_LatexOps(namer))[0]


# -- derived (sympy) expressions -------------------------------------------------------

def sympy_latex(expr: sympy.Basic, names: Mapping[sympy.Symbol, str]) -> str:
    """:func:`sympy.latex` with the report's symbol names; matrices as ``bmatrix``."""
    if isinstance(expr, sympy.MatrixBase):
        rows = [" & ".join(sympy_latex(expr[i, j], names) for j in range(expr.cols))
                for i in range(expr.rows)]
        return r"\begin{bmatrix} " + r" \\ ".join(rows) + r" \end{bmatrix}"
    # order="none" keeps positive terms first (k x_1 - k r, not -k r + k x_1), as textbooks do
    return sympy.latex(expr, symbol_names=dict(names), order="none")


# -- numbers ---------------------------------------------------------------------------------

def number_latex(value: float, digits: int = SIGNIFICANT) -> str:
    """A float with ``digits`` significant digits; powers of ten outside [1e-3, 1e5)."""
    if value == 0 or not math.isfinite(value):
        return "0" if value == 0 else (r"\infty" if value > 0 else r"-\infty")
    magnitude = abs(value)
    if 1e-3 <= magnitude < 1e5:
        text = f"{value:.{digits}g}"
        if "e" in text:  # e.g. 1.000e+04 for digits smaller than the integer part
            text = f"{value:.0f}"
        return text
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    mantissa = mantissa.rstrip("0").rstrip(".") if "." in mantissa else mantissa
    return rf"{mantissa} \cdot 10^{{{int(exponent)}}}"


def with_subscript(symbol_latex: str, extra: str) -> str:
    """``x_{1}`` + ``\\max`` -> ``x_{1,\\max}``; ``\\varphi`` -> ``\\varphi_{\\max}``."""
    if symbol_latex.endswith("}") and "_{" in symbol_latex and "^" not in symbol_latex:
        return symbol_latex[:-1] + "," + extra + "}"
    if "_" in symbol_latex or "^" in symbol_latex:
        return "{" + symbol_latex + "}_{" + extra + "}"
    return symbol_latex + "_{" + extra + "}"


def number_text(value: float, digits: int = SIGNIFICANT) -> str:
    """A float for running text: ``4.511e-05`` style outside [1e-3, 1e5)."""
    if value == 0 or 1e-3 <= abs(value) < 1e5:
        return number_latex(value, digits)
    return f"{value:.{digits - 1}e}"


def vector_latex(values: Iterable[float], digits: int = SIGNIFICANT) -> str:
    return (r"\begin{bmatrix} " + r" \\ ".join(number_latex(float(v), digits)
                                                 for v in values) + r" \end{bmatrix}")


def matrix_latex(matrix: np.ndarray, digits: int = SIGNIFICANT) -> str:
    rows = [" & ".join(number_latex(float(v), digits) for v in row)
            for row in np.atleast_2d(matrix)]
    return r"\begin{bmatrix} " + r" \\ ".join(rows) + r" \end{bmatrix}"


def column_latex(entries: Iterable[str]) -> str:
    return r"\begin{bmatrix} " + r" \\ ".join(entries) + r" \end{bmatrix}"


def math_name(name: str) -> str:
    """A model name typeset for matplotlib (``x1`` -> ``$x_{1}$``, ``phi`` -> ``$\\varphi$``),
    or the name as plain text where mathtext cannot set it.

    Examples
    --------
    >>> print(math_name("x1"), math_name("omega"), math_name("F0"))
    $x_{1}$ $\\omega$ $F_{0}$
    """
    from matplotlib.mathtext import MathTextParser

    text = f"${name_latex(name)}$"
    try:
        MathTextParser("path").parse(text)
    except ValueError:
        return printable(name, limit=40).replace("$", r"\$")
    return text


def dollar_name(name: str) -> str:
    """A model name as a chart label (math between dollar signs)."""
    return f"${name_latex(name)}$"


__all__ = ["math_name", "Namer", "name_latex", "expression_latex", "sympy_latex", "number_latex",
           "number_text", "with_subscript", "vector_latex", "matrix_latex", "column_latex"]
