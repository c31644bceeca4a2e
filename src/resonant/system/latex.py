"""The equation of motion typeset: M q'' + C q' + K q = Q(t) as one LaTeX display.

The Jupyter reprs of the linear systems (``_repr_latex_``) and of a model write with it,
in the notation of the worked-solution report (:mod:`resonant.expressions.notation`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol

from ..derivation import derivative_symbol
from ..expressions.notation import Namer, column_latex, sympy_latex
from ..model import Model, symbol

Var = tuple[str, int]


class SymbolicEquations(Protocol):
    """A linear system's equations in symbols: what the report, the display and the time
    integration read of a system derived from energies or given by its matrices
    (:meth:`LinearSystem.symbolic`)."""

    @property
    def model(self) -> Model: ...
    @property
    def coordinates(self) -> tuple[str, ...]: ...
    @property
    def M(self) -> Any: ...
    @property
    def C(self) -> Any: ...
    @property
    def K(self) -> Any: ...
    @property
    def Q(self) -> Any: ...
    @property
    def Q_signals(self) -> Any: ...
    @property
    def excitation(self) -> Mapping[Var, Any]: ...
    @property
    def signal_functions(self) -> Mapping[Var, Any]: ...
    @property
    def harmonics(self) -> Any: ...
    @property
    def outputs(self) -> Mapping[str, Any]: ...


def model_namer(model: Model) -> tuple[Namer, dict[Any, str]]:
    """The namer of a model's symbols (coordinates with their dots, signals, parameters)
    and the LaTeX name of each symbol."""
    namer = Namer(frozenset(model.signals))
    symbols = [symbol(p) for p in model.parameters]
    for name in [*model.coordinates, *model.signals]:
        symbols.extend(derivative_symbol(name, order) for order in range(4))
    return namer, namer.symbol_names(symbols)


def eom_latex(eom: SymbolicEquations) -> str:
    """The equation of motion as one LaTeX display (Jupyter ``_repr_latex_``).

    Examples
    --------
    >>> from resonant.api import loads
    >>> eom = loads('''
    ... [parameters]
    ... m = 2
    ... k = 8
    ... [coordinates]
    ... x = "displacement"
    ... [energy]
    ... T = "m*x'^2/2"
    ... U = "k*x^2/2"
    ... ''').linearize()
    >>> print(eom_latex(eom)[:40])
    $\\displaystyle \\begin{bmatrix} m \\end{bm
    """
    namer, names = model_namer(eom.model)
    parts = []
    for mat, order in ((eom.M, 2), (eom.C, 1), (eom.K, 0)):
        if any(e != 0 for e in mat):
            parts.append(sympy_latex(mat, names)
                         + column_latex([namer(c, order) for c in eom.coordinates]))
    lhs = " + ".join(parts) or "0"
    return rf"$\displaystyle {lhs} = {sympy_latex(eom.Q, names)}$"


__all__ = ["eom_latex", "model_namer", "SymbolicEquations"]
