"""The context every step of the worked solution shares, and the helpers of the steps."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import sympy

from ...analyses.correlate import Correlation
from ...analyses.measured_match import MatchedTest
from ...analyses.stationary import StationarySolution
from ...derivation import derivative_symbol
from ...derivation.lagrange import signal_derivatives
from ...expressions.notation import (
    Namer,
    column_latex,
    number_latex,
    sympy_latex,
)
from ...model import Model
from ...system.base import LinearSystem
from ...system.latex import SymbolicEquations, model_namer
from ..blocks import Equation, Figure, Math
from ..derivation import Derivation, SourceTerms

#: above this many coordinates, element-by-element listings and symbolic 2n x 2n
#: systems are left out (they would fill pages without helping anyone)
MAX_ELEMENTS = 6
MAX_SYMBOLIC_SYSTEM = 3
MAX_MATRIX = 12
EQ_ZERO = r"\mathbf{q}=\mathbf{0}"
MAX = r"\max"


@dataclass
class Context:
    """Everything the steps share; ``equation`` numbers the displayed equations."""

    model: Model
    system: LinearSystem
    eom: SymbolicEquations
    solution: StationarySolution
    derivation: Derivation | None
    plots: bool = True
    #: the test against the model (``resonant report --test``), shown by its step
    correlation: Correlation | None = None
    #: measured FRFs checked against the model (``resonant report --test FILE.uff``)
    measured: MatchedTest | None = None
    namer: Namer = field(init=False)
    names: dict[sympy.Symbol, str] = field(init=False)
    count: int = 0
    figures: int = 0
    labels: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.namer, self.names = model_namer(self.model)

    @property
    def n(self) -> int:
        return len(self.eom.coordinates)

    @property
    def derived(self) -> Derivation:
        """The derivation, for the steps that run only when there is one."""
        if self.derivation is None:
            raise ValueError("this step needs the derivation of the model's energies")
        return self.derivation

    def equation(self, latex: str, label: str | None = None) -> Equation:
        self.count += 1
        if label:
            self.labels[label] = self.count
        return Equation(latex, self.count)

    def ref(self, label: str) -> str:
        return f"({self.labels[label]})" if label in self.labels else ""

    def tex(self, expr: sympy.Basic) -> str:
        return sympy_latex(expr, self.names)

    def q_symbols(self, order: int = 0) -> list[str]:
        return [self.namer(c, order) for c in self.eom.coordinates]

    def figure(self, plot, caption: str) -> Figure:
        self.figures += 1
        return Figure(plot, caption, self.figures)


# -- helpers -------------------------------------------------------------------------------

def _m(latex: str) -> Math:
    return Math(latex)


def _vector(entries: Sequence[str]) -> str:
    return column_latex(entries)


def _is_zero(matrix: sympy.MatrixBase) -> bool:
    return all(e == 0 for e in matrix)


def _at_reference(ctx: Context) -> str:
    d = ctx.derivation
    return EQ_ZERO if d is None or d.at_zero else r"\mathbf{q}=\mathbf{q}_{0}"


def _partial(energy: str, variables: Sequence[str]) -> str:
    """``\\frac{\\partial^2 T}{\\partial \\dot{x}_1 \\partial \\dot{x}_2}`` (squares merged)."""
    order = len(variables)
    if order == 2 and variables[0] == variables[1]:
        denominator = rf"\partial {variables[0]}^{{2}}"
    else:
        denominator = " ".join(rf"\partial {v}" for v in variables)
    head = r"\partial" if order == 1 else rf"\partial^{{{order}}}"
    return rf"\frac{{{head} {energy}}}{{{denominator}}}"


def _energy_symbol(key: str) -> str:
    return r"\mathcal{D}" if key == "D" else key


def _signal_functions(ctx: Context, column_vars) -> dict[tuple[str, int], sympy.Expr]:

    return signal_derivatives(ctx.model, set(column_vars))


def _q_with_functions(ctx: Context, part_q: dict) -> sympy.Matrix:
    """Q = sum column * signal derivative, with the signals written as functions of t."""
    functions = _signal_functions(ctx, part_q)
    total = sympy.zeros(ctx.n, 1)
    for var, column in part_q.items():
        total += column * functions[var]
    return total


def _linear_vector(ctx: Context, part: SourceTerms, with_mass: bool = True) -> sympy.Matrix:
    """M q'' + C q' + K q - Q with symbols, as a column (the linearized terms)."""
    coords = ctx.eom.coordinates
    vec = sympy.zeros(ctx.n, 1)
    for order, mat in ((2, part.M), (1, part.C), (0, part.K)):
        if order == 2 and not with_mass:
            continue
        vec += mat * sympy.Matrix([derivative_symbol(c, order) for c in coords])
    return sympy.Matrix(vec - part.Q_vector(ctx.n))


def _matrix_terms(part: SourceTerms, labels: dict[str, str], q_label: str) -> str:
    """``\\mathbf{K}\\mathbf{q} - \\mathbf{Q}^{r}(t)``: the matrix form of a linear part."""
    terms = []
    for key, dots in (("M", r"\ddot{\mathbf{q}}"), ("C", r"\dot{\mathbf{q}}"),
                      ("K", r"\mathbf{q}")):
        if not _is_zero(getattr(part, key)):
            terms.append(labels.get(key, rf"\mathbf{{{key}}}") + dots)
    text = " + ".join(terms) if terms else "0"
    if part.Q:
        text += rf" - \mathbf{{Q}}^{{{q_label}}}(t)"
    return text


def _source_labels(ctx: Context) -> dict[str, str]:
    """Superscripts of the parts of Q: the signal names, or the source when shared."""
    d = ctx.derivation
    sources: dict[str, SourceTerms] = {}
    if d is not None:
        for key in ("T", "D", "U"):
            if d.parts[key].Q:
                sources[key] = d.parts[key]
        for i, force in enumerate(d.forces):
            if force.part.Q:
                sources[f"F{i}"] = force.part
    labels = {}
    signal_sets = {key: tuple(p.signals) for key, p in sources.items()}
    for key, signals in signal_sets.items():
        unique = list(signal_sets.values()).count(signals) == 1 and signals
        if unique:
            labels[key] = ",".join(ctx.namer(s).replace("(t)", "") for s in signals)
        elif key.startswith("F"):
            several = d is not None and len(d.forces) > 1
            labels[key] = rf"F_{{{int(key[1:]) + 1}}}" if several else "F"
        else:
            labels[key] = _energy_symbol(key)
    return labels


def _cases(rows: list[list[tuple[str, bool]]], unknowns: Sequence[str],
           rhs: Sequence[str]) -> str:
    """A system of linear equations; a coefficient is ``(latex, negative)``."""
    lines = []
    for row, right in zip(rows, rhs):
        terms: list[str] = []
        for (coef, negative), unknown in zip(row, unknowns):
            if coef == "":
                continue
            text = unknown if coef == "1" else f"{coef} {unknown}"
            if terms:
                terms.append(("- " if negative else "+ ") + text)
            else:
                terms.append(("-" if negative else "") + text)
        lines.append((" ".join(terms) or "0") + " = " + right)
    return r"\begin{cases} " + r", \\ ".join(lines) + r". \end{cases}"


def _numeric_coef(value: float) -> tuple[str, bool]:
    if value == 0:
        return "", False
    return number_latex(abs(value)), value < 0


def _symbolic_coef(ctx: Context, value: sympy.Expr) -> tuple[str, bool]:
    if value == 0:
        return "", False
    negative = value.could_extract_minus_sign()
    body = -value if negative else value
    text = ctx.tex(body)
    if isinstance(body, sympy.Add):
        text = r"\left(" + text + r"\right)"
    return text, negative
