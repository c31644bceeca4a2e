"""The functions of the model language, in one table.

Every layer that evaluates an expression looks its functions up here: the
parser (names and arities), constant folding (``math``), numeric evaluation
(``numpy``), symbolic work (``sympy``; the jets and the full equations) and
the typeset output (LaTeX).

Examples
--------
>>> FUNCTIONS["atan2"].arity, FUNCTIONS["asin"].latex
(2, '\\\\arcsin')
>>> sorted(ARITY)[:3]
['abs', 'acos', 'asin']
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy


@dataclass(frozen=True)
class Function:
    """One function of the model language and its implementations.

    Parameters
    ----------
    name : str
        Its name in the model language.
    arity : int
        How many arguments it takes.
    math, numpy, sympy : callable
        Its implementations for floats, arrays and symbols.
    latex : str
        Its LaTeX operator (``\\sin``).
    javascript : str
        Its JavaScript function (``Math.sin``).
    latex_form : str
        How a call is written in LaTeX, ``{0}`` (and ``{1}``) the arguments; empty: the
        operator and the arguments in parentheses.

    Examples
    --------
    >>> FUNCTIONS["atan2"].arity
    2
    >>> FUNCTIONS["sqrt"].write_latex("x")
    '\\\\sqrt{x}'
    """

    name: str
    arity: int
    math: Callable[..., float]
    numpy: Callable[..., Any]
    sympy: Callable[..., Any]
    latex: str
    javascript: str = ""
    latex_form: str = ""

    def write_latex(self, *arguments: str) -> str:
        """A call of the function with these LaTeX arguments, as LaTeX."""
        if self.latex_form:
            return self.latex_form.format(*arguments)
        return self.latex + r"\left(" + ", ".join(arguments) + r"\right)"


def _function(name: str, arity: int, numpy_name: str, latex: str, latex_form: str = ""
              ) -> Function:
    return Function(name, arity, getattr(math, name), getattr(np, numpy_name),
                    getattr(sympy, name), latex, f"Math.{name}", latex_form)


#: name -> Function, in the order the documentation lists them
FUNCTIONS: dict[str, Function] = {f.name: f for f in (
    _function("sin", 1, "sin", r"\sin"), _function("cos", 1, "cos", r"\cos"),
    _function("tan", 1, "tan", r"\tan"), _function("asin", 1, "arcsin", r"\arcsin"),
    _function("acos", 1, "arccos", r"\arccos"), _function("atan", 1, "arctan", r"\arctan"),
    _function("atan2", 2, "arctan2", r"\operatorname{atan2}"),
    _function("sinh", 1, "sinh", r"\sinh"), _function("cosh", 1, "cosh", r"\cosh"),
    _function("tanh", 1, "tanh", r"\tanh"), _function("exp", 1, "exp", r"\exp"),
    _function("log", 1, "log", r"\ln"),
    _function("sqrt", 1, "sqrt", r"\sqrt", r"\sqrt{{{0}}}"),
    # |x|: for forces such as c x'|x'| (quadratic damping) of nonlinear elements
    Function("abs", 1, abs, np.abs, sympy.Abs, r"\operatorname{abs}", "Math.abs",
             r"\left|{0}\right|"),
)}
#: name -> number of arguments
ARITY: dict[str, int] = {name: f.arity for name, f in FUNCTIONS.items()}
#: name -> numpy implementation
NUMPY: dict[str, Callable[..., Any]] = {name: f.numpy for name, f in FUNCTIONS.items()}
#: name -> sympy constructor
SYMPY: dict[str, Callable[..., Any]] = {name: f.sympy for name, f in FUNCTIONS.items()}
#: name -> math (float) implementation
MATH: dict[str, Callable[..., float]] = {name: f.math for name, f in FUNCTIONS.items()}
#: sympy function class (``sympy.sin``, ``sympy.Abs``) -> JavaScript function; sqrt is a
#: power in sympy and has none
JAVASCRIPT: dict[Any, str] = {f.sympy: f.javascript for f in FUNCTIONS.values()
                              if isinstance(f.sympy, type)}

__all__ = ["Function", "FUNCTIONS", "ARITY", "NUMPY", "SYMPY", "MATH", "JAVASCRIPT"]
