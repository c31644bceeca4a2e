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
        How it is written in LaTeX.

    Examples
    --------
    >>> FUNCTIONS["atan2"].arity
    2
    """

    name: str
    arity: int
    math: Callable[..., float]
    numpy: Callable[..., Any]
    sympy: Callable[..., Any]
    latex: str


def _function(name: str, arity: int, numpy_name: str, latex: str) -> Function:
    return Function(name, arity, getattr(math, name), getattr(np, numpy_name),
                    getattr(sympy, name), latex)


#: name -> Function, in the order the documentation lists them
FUNCTIONS: dict[str, Function] = {f.name: f for f in (
    _function("sin", 1, "sin", r"\sin"), _function("cos", 1, "cos", r"\cos"),
    _function("tan", 1, "tan", r"\tan"), _function("asin", 1, "arcsin", r"\arcsin"),
    _function("acos", 1, "arccos", r"\arccos"), _function("atan", 1, "arctan", r"\arctan"),
    _function("atan2", 2, "arctan2", r"\operatorname{atan2}"),
    _function("sinh", 1, "sinh", r"\sinh"), _function("cosh", 1, "cosh", r"\cosh"),
    _function("tanh", 1, "tanh", r"\tanh"), _function("exp", 1, "exp", r"\exp"),
    _function("log", 1, "log", r"\ln"), _function("sqrt", 1, "sqrt", r"\sqrt"),
    # |x|: for forces such as c x'|x'| (quadratic damping) of nonlinear elements
    Function("abs", 1, abs, np.abs, sympy.Abs, r"\operatorname{abs}"),
)}
#: name -> number of arguments
ARITY: dict[str, int] = {name: f.arity for name, f in FUNCTIONS.items()}
#: name -> numpy implementation
NUMPY: dict[str, Callable[..., Any]] = {name: f.numpy for name, f in FUNCTIONS.items()}
#: name -> sympy constructor
SYMPY: dict[str, Callable[..., Any]] = {name: f.sympy for name, f in FUNCTIONS.items()}
#: name -> math (float) implementation
MATH: dict[str, Callable[..., float]] = {name: f.math for name, f in FUNCTIONS.items()}

__all__ = ["Function", "FUNCTIONS", "ARITY", "NUMPY", "SYMPY", "MATH"]
