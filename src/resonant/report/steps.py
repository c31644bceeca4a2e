"""The steps of the worked solution, one function per step, in the exercise's order.

Each step takes the shared :class:`Context` (model, equation of motion,
stationary solution, derivation, equation counter) and returns a list of
blocks.  The order and notation follow the reference exercise "Practice 12 -
2 DoF forced system": Data; Task 1 (method, Eqs. (1)-(6); coordinates (7);
kinetic energy and M (8)-(20); potential energy and K (21)-(29); excitation
forces (30)-(34); the equation of motion (35)); Task 2 (stationary solution,
(36)-(44)); Task 3 (maximal excursions, (45)-(48)); then natural frequencies,
stability, plots and warnings.  A free-vibration model shows its modes
instead of Tasks 2 and 3.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy

import resonant.report.parts as part_steps

from ..analyses.modes import modes
from ..analyses.stationary import StationarySolution
from ..derivation import derivative_symbol
from ..derivation.lagrange import signal_derivatives
from ..expressions import numeric_value
from ..model import Model, symbol
from ..system import LinearEOM
from ..system.stability import undamped_eigen
from ..views.notation import (
    Namer,
    column_latex,
    expression_latex,
    matrix_latex,
    number_latex,
    number_text,
    sympy_latex,
    vector_latex,
    with_subscript,
)
from ..views.units_display import NO_UNIT, RAD, result_units, unit_latex
from .blocks import Block, Equation, Figure, Heading, Math, Note, Table, cell, paragraph
from .derivation import Derivation, LinearPart
from .plots import frequency_response, time_history

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
    eom: LinearEOM
    solution: StationarySolution
    derivation: Derivation | None
    plots: bool = True
    namer: Namer = field(init=False)
    names: dict[sympy.Symbol, str] = field(init=False)
    count: int = 0
    figures: int = 0
    labels: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.namer = Namer(frozenset(self.model.signals))
        symbols = [symbol(p) for p in self.model.parameters]
        for name in [*self.model.coordinates, *self.model.signals]:
            symbols.extend(derivative_symbol(name, order) for order in range(4))
        self.names = self.namer.symbol_names(symbols)

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


def _linear_vector(ctx: Context, part: LinearPart, with_mass: bool = True) -> sympy.Matrix:
    """M q'' + C q' + K q - Q with symbols, as a column (the linearized terms)."""
    coords = ctx.eom.coordinates
    vec = sympy.zeros(ctx.n, 1)
    for order, mat in ((2, part.M), (1, part.C), (0, part.K)):
        if order == 2 and not with_mass:
            continue
        vec += mat * sympy.Matrix([derivative_symbol(c, order) for c in coords])
    return sympy.Matrix(vec - part.Q_vector(ctx.n))


def _matrix_terms(part: LinearPart, labels: dict[str, str], q_label: str) -> str:
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
    sources: dict[str, LinearPart] = {}
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


# -- steps -------------------------------------------------------------------------------

def title(ctx: Context) -> list[Block]:
    blocks: list[Block] = []
    if ctx.model.source:
        blocks.append(paragraph("Worked solution of the model ", f"“{ctx.model.source}”",
                                ", derived by resonant in the order and notation of a "
                                "textbook exercise: the linearized equation of motion, "
                                "the stationary solution and the maximal excursions."))
    return blocks


def data(ctx: Context) -> list[Block]:
    model = ctx.model
    blocks: list[Block] = [Heading("Data")]
    rows = []
    units = model.units
    for name, expression in model.parameters.items():
        value = model.parameter_values[name]
        given = expression_latex(expression, ctx.namer)
        shown = number_latex(value, 6)
        if units is not None:  # "500 mm" given, 0.5 m the (SI) value
            written = units.given.get(name)
            if written is not None:
                given = expression_latex(written[0], ctx.namer) + unit_latex(written[1].text)
            dim = units.dimensions.get(name)
            same = written is not None and written[1].factor == 1 and not written[1].pi_power
            shown += unit_latex(written[1].text if same and written is not None
                                else dim.text() if dim is not None and not dim.dimensionless
                                else "rad" if written is not None and written[1].angle else "")
        rows.append((cell(_m(ctx.namer(name))),
                     cell(_m(given)) if given != shown else cell(""),
                     cell(_m(shown))))
    if rows:
        blocks.append(Table((cell("parameter"), cell("given as"), cell("value")), tuple(rows)))
    if model.signals:
        blocks.append(paragraph("The prescribed excitations (signals, small of first order) "
                                "are"))
        for name, expression in model.signals.items():
            blocks.append(ctx.equation(ctx.namer(name) + " = "
                                       + expression_latex(expression, ctx.namer),
                                       label=f"signal:{name}"))
    return blocks


def method(ctx: Context) -> list[Block]:
    blocks: list[Block] = [Heading("Task 1: the linearized equation of motion"),
                           paragraph("The matrix formulation of the linearized equation of "
                                     "motion is")]
    blocks.append(ctx.equation(r"\mathbf{M}\ddot{\mathbf{q}}(t) + \mathbf{C}\dot{\mathbf{q}}(t)"
                               r" + \mathbf{K}\mathbf{q}(t) = \mathbf{Q}(t),", label="eom"))
    blocks.append(paragraph(
        "where ", _m(r"\mathbf{M}"), " is the mass matrix, ", _m(r"\mathbf{C}"),
        " the damping matrix, ", _m(r"\mathbf{K}"), " the stiffness matrix, ",
        _m(r"\mathbf{Q}(t)"), " contains the excitations and ", _m(r"\mathbf{q}"),
        f" is the vector of the generalized coordinates (n = {ctx.n}). The elements of the "
        "matrices are the second derivatives of the kinetic energy T, the Rayleigh "
        "dissipation function ", _m(r"\mathcal{D}"), " and the potential function U at the "
        "equilibrium:"))
    ref = _at_reference(ctx)
    for label, energy, dotted in (("mij", "T", True), ("cij", r"\mathcal{D}", True),
                                  ("kij", "U", False)):
        letter = label[0]
        q = r"\dot{q}" if dotted else "q"
        blocks.append(ctx.equation(
            rf"{letter}_{{ij}} = \left.\frac{{\partial^{{2}} {energy}}}{{\partial {q}_{{i}}"
            rf" \partial {q}_{{j}}}}\right|_{{{ref}}},", label=label))
    d = ctx.derivation
    dependent = [k for k in ("T", "D", "U") if d is not None and d.parts[k].Q]
    blocks.append(paragraph("The vector ", _m(r"\mathbf{Q}"), " follows from the power of the "
                            "active forces that have no potential or dissipation function."))
    if dependent:
        which = ", ".join(_energy_name(k) for k in dependent)
        blocks.append(paragraph(
            f"Here the {which} depend{'s' if len(dependent) == 1 else ''} explicitly on time "
            "through the prescribed signals, so the corresponding parts of Lagrange's "
            "equation of the second kind,"))
        blocks.append(ctx.equation(
            r"\frac{\mathrm{d}}{\mathrm{d}t}\frac{\partial T}{\partial \dot{q}_{k}} - "
            r"\frac{\partial T}{\partial q_{k}} + \frac{\partial \mathcal{D}}{\partial "
            r"\dot{q}_{k}} + \frac{\partial U}{\partial q_{k}} = Q_{k}^{*}, \quad "
            r"k = 1, \dots, n,", label="lagrange"))
        blocks.append(paragraph(
            "are linearized as well: besides ", _m(r"\mathbf{M}\ddot{\mathbf{q}}"), ", ",
            _m(r"\mathbf{C}\dot{\mathbf{q}}"), " and ", _m(r"\mathbf{K}\mathbf{q}"),
            " they give a part of ", _m(r"-\mathbf{Q}(t)"), "."))
    return blocks


def _energy_name(key: str) -> str:
    return {"T": "kinetic energy T", "D": "dissipation function D",
            "U": "potential function U"}[key]


def coordinates(ctx: Context, heading: str = "Kinetic energy and mass matrix") -> list[Block]:
    coords = ctx.eom.coordinates
    blocks: list[Block] = [Heading(heading, 3)]
    blocks.append(paragraph(f"The system has {ctx.n} degree{'s' if ctx.n != 1 else ''} of "
                            "freedom, therefore the vector of generalized coordinates is"))
    generic = [f"q_{{{i + 1}}}" for i in range(ctx.n)]
    blocks.append(ctx.equation(r"\mathbf{q} = " + _vector(generic) + " = "
                               + _vector(ctx.q_symbols()) + ",", label="q"))
    described = [(c, ctx.model.descriptions.get(c, "")) for c in coords]
    described = [(c, text) for c, text in described if text]
    if described:
        parts: list = ["where "]
        for i, (c, text) in enumerate(described):
            if i:
                parts.append("; " if i < len(described) - 1 else " and ")
            parts.extend([_m(ctx.namer(c)), " is the " + text])
        parts.append(".")
        blocks.append(paragraph(*parts))
    model = ctx.model
    if model.equilibrium and any(model.equilibrium.values()):
        blocks.append(paragraph("The reference state (equilibrium) is"))
        blocks.append(ctx.equation(r"\mathbf{q}_{0} = " + _vector(
            [expression_latex(model.equilibrium[c], ctx.namer) if c in model.equilibrium
             else "0" for c in coords]) + "."))
    if model.definitions:
        blocks.append(paragraph("The model uses the definitions"))
        for name, expression in model.definitions.items():
            blocks.append(ctx.equation(ctx.namer(name) + " = "
                                       + expression_latex(expression, ctx.namer) + ","))
    return blocks


def _uses_definitions(ctx: Context, key: str) -> bool:
    return any(n in ctx.model.definitions for n, _ in ctx.model.energy[key].names())


def _energy_statement(ctx: Context, key: str, intro: str) -> list[Block]:
    """The energy as given and, if it uses definitions, in the coordinates."""
    d = ctx.derived
    symbol_ = _energy_symbol(key)
    blocks: list[Block] = [paragraph(intro)]
    given = expression_latex(ctx.model.energy[key], ctx.namer)
    if _uses_definitions(ctx, key):
        blocks.append(ctx.equation(f"{symbol_} = {given},"))
        blocks.append(paragraph("and with the definitions substituted"))
        blocks.append(ctx.equation(f"{symbol_} = {ctx.tex(d.energies[key])}.", label=key))
    else:
        blocks.append(ctx.equation(f"{symbol_} = {given}.", label=key))
    return blocks


def _derivatives(ctx: Context, key: str, dotted: bool, letter: str) -> list[Block]:
    """First derivatives, the second derivatives element by element and their values."""
    d = ctx.derived
    order = 1 if dotted else 0
    names = ctx.q_symbols(order)
    energy = _energy_symbol(key)
    blocks: list[Block] = []
    if ctx.n > MAX_ELEMENTS:
        blocks.append(paragraph(f"(With {ctx.n} coordinates, the derivatives are not listed "
                                "element by element.)"))
        return blocks
    blocks.append(paragraph("The first derivatives with respect to the generalized "
                            + ("velocities" if dotted else "coordinates") + " are"))
    for k in range(ctx.n):
        blocks.append(ctx.equation(_partial(energy, [names[k]]) + " = "
                                   + ctx.tex(d.first[key][k]) + ","))
    entries = d.second[key]
    if not entries:
        return blocks
    ref = _at_reference(ctx)
    at = f"Eq. {ctx.ref(letter + 'ij')}" if ctx.ref(letter + 'ij') else ""
    blocks.append(paragraph("and the second derivatives, taken at the equilibrium "
                            f"({at}), give the nonzero elements"))
    for (i, j), (full, value) in entries.items():
        element = f"{letter}_{{{i + 1}{j + 1}}}"
        if i != j:
            element += f" = {letter}_{{{j + 1}{i + 1}}}"
        derivative = _partial(energy, [names[i], names[j]])
        text = rf"{element} = \left.{derivative}\right|_{{{ref}}}"
        if sympy.simplify(full - value) != 0 if sympy.count_ops(full) < 40 else True:
            text += rf" = \left.{ctx.tex(full)}\right|_{{{ref}}}"
        blocks.append(ctx.equation(text + f" = {ctx.tex(value)},"))
    return blocks


def _time_part(ctx: Context, key: str, lhs: str, matrix_labels: dict[str, str],
               label: str) -> list[Block]:
    """The linearized part of Lagrange's equation of one energy that holds signals."""
    d = ctx.derived
    part = d.parts[key]
    if not part.Q and _is_zero(part.C if key == "T" else sympy.zeros(1)) and \
            (key != "T" or _is_zero(part.K)):
        return []
    blocks: list[Block] = []
    linear = _linear_vector(ctx, part)
    blocks.append(paragraph("By the linearization of these around the equilibrium we obtain "
                            "the terms of the linearized equation of motion:"))
    blocks.append(ctx.equation(lhs + r" \approx " + ctx.tex(linear) + r" \equiv "
                               + _matrix_terms(part, matrix_labels, label) + ","))
    if part.Q:
        q_sym = part.Q_vector(ctx.n)
        q_fun = _q_with_functions(ctx, part.Q)
        text = rf"\mathbf{{Q}}^{{{label}}}(t) = {ctx.tex(q_sym)}"
        if sympy.simplify(q_fun - q_sym) != sympy.zeros(ctx.n, 1):
            text += f" = {ctx.tex(q_fun)}"
        blocks.append(paragraph("from where the generalized force of the signals in "
                                + _energy_symbol_text(key) + " is"))
        blocks.append(ctx.equation(text + ".", label=f"Q:{key}"))
    return blocks


def _energy_symbol_text(key: str) -> str:
    return "D" if key == "D" else key


def kinetic(ctx: Context) -> list[Block]:
    d = ctx.derived
    blocks = _energy_statement(ctx, "T", "The kinetic energy of the system is")
    if d.time_dependent("T"):
        blocks.append(paragraph("The kinetic energy depends explicitly on time through the "
                                "signals, so its part of Lagrange's equation is computed "
                                f"({'Eq. ' + ctx.ref('lagrange')})."))
    else:
        blocks.append(paragraph("The kinetic energy does not depend explicitly on time, so "
                                "the mass matrix follows directly from Eq. "
                                + ctx.ref("mij") + "."))
    blocks.extend(_derivatives(ctx, "T", True, "m"))
    lhs = (_vector([rf"\frac{{\mathrm{{d}}}}{{\mathrm{{d}}t}}{_partial('T', [v])} - "
                    f"{_partial('T', [c])}" for v, c in zip(ctx.q_symbols(1), ctx.q_symbols())])
           if ctx.n <= MAX_ELEMENTS else r"\frac{\mathrm{d}}{\mathrm{d}t}\frac{\partial T}"
           r"{\partial \dot{\mathbf{q}}} - \frac{\partial T}{\partial \mathbf{q}}")
    labels = {"C": r"\mathbf{C}^{T}", "K": r"\mathbf{K}^{T}"}
    blocks.extend(_time_part(ctx, "T", lhs, labels, _source_labels(ctx).get("T", "T")))
    blocks.append(paragraph("The mass matrix is"))
    blocks.append(ctx.equation(r"\mathbf{M} = " + ctx.tex(ctx.eom.M) + ".", label="M"))
    return blocks


def dissipation(ctx: Context) -> list[Block]:
    d = ctx.derived
    if "D" not in ctx.model.energy or d.energies["D"] == 0:
        return []
    blocks: list[Block] = [Heading("Dissipation function and damping matrix", 3)]
    blocks.extend(_energy_statement(ctx, "D", "Rayleigh's dissipation function is"))
    blocks.extend(_derivatives(ctx, "D", True, "c"))
    lhs = _vector([_partial(r"\mathcal{D}", [v]) for v in ctx.q_symbols(1)]) \
        if ctx.n <= MAX_ELEMENTS else r"\frac{\partial \mathcal{D}}{\partial \dot{\mathbf{q}}}"
    blocks.extend(_time_part(ctx, "D", lhs, {"C": r"\mathbf{C}", "K": r"\mathbf{K}^{D}"},
                             _source_labels(ctx).get("D", r"\mathcal{D}")))
    return blocks


def potential(ctx: Context) -> list[Block]:
    d = ctx.derived
    blocks: list[Block] = [Heading("Potential energy function and stiffness matrix", 3)]
    if "U" not in ctx.model.energy or d.energies["U"] == 0:
        blocks.append(paragraph("There is no potential energy: U = 0."))
    else:
        blocks.extend(_energy_statement(ctx, "U", "The potential function is"))
        if d.time_dependent("U"):
            signals = sorted({s.name.rstrip("'") for s in d.energies["U"].free_symbols
                              if s.name.rstrip("'") in ctx.model.signals})
            blocks.append(paragraph(
                "The potential function depends explicitly on time through ",
                *_join_math([ctx.namer(s) for s in signals]),
                ", so the stiffness matrix and the related excitation are calculated from "
                "its part of Lagrange's equation" + (f" (Eq. {ctx.ref('lagrange')})"
                                                     if ctx.ref("lagrange") else "") + "."))
        names = ctx.q_symbols()
        if ctx.n <= MAX_ELEMENTS:
            blocks.append(paragraph("The first derivatives of the potential function with "
                                    "respect to the generalized coordinates are"))
            for k in range(ctx.n):
                blocks.append(ctx.equation(_partial("U", [names[k]]) + " = "
                                           + ctx.tex(d.first["U"][k]) + ","))
            if d.parts["U"].Q:
                lhs = _vector([_partial("U", [c]) for c in names])
                label = _source_labels(ctx).get("U", "U")
                blocks.append(paragraph("By the linearization of these around the "
                                        "equilibrium, we obtain the terms ",
                                        _m(r"\mathbf{K}\mathbf{q}"), " and ",
                                        _m(rf"-\mathbf{{Q}}^{{{label}}}(t)"), ":"))
                blocks.append(ctx.equation(lhs + r" \approx " + ctx.tex(_linear_vector(
                    ctx, d.parts["U"])) + r" \equiv \mathbf{K}\mathbf{q} - "
                    rf"\mathbf{{Q}}^{{{label}}}(t),"))
                q_sym = d.parts["U"].Q_vector(ctx.n)
                q_fun = _q_with_functions(ctx, d.parts["U"].Q)
                blocks.append(paragraph("from where the generalized force related to the "
                                        "signals in U is"))
                blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}}(t) = {ctx.tex(q_sym)}"
                                           f" = {ctx.tex(q_fun)},", label="Q:U"))
    others = _other_stiffness(ctx)
    blocks.append(paragraph("and the stiffness matrix is" + others))
    blocks.append(ctx.equation(r"\mathbf{K} = " + ctx.tex(ctx.eom.K) + ".", label="K"))
    if "U" in ctx.model.energy and d.energies["U"] != 0 and ctx.n <= MAX_ELEMENTS \
            and d.second["U"]:
        ref = _at_reference(ctx)
        blocks.append(paragraph("The elements of the stiffness matrix from Eq. "
                                + ctx.ref("kij") + " are"))
        for (i, j), (full, value) in d.second["U"].items():
            element = f"k_{{{i + 1}{j + 1}}}" + (f" = k_{{{j + 1}{i + 1}}}" if i != j else "")
            text = rf"{element} = \left.{_partial('U', [names[i], names[j]])}\right|_{{{ref}}}"
            if full != value:
                text += rf" = \left.{ctx.tex(full)}\right|_{{{ref}}}"
            blocks.append(ctx.equation(text + f" = {ctx.tex(value)},"))
    return blocks


def _other_stiffness(ctx: Context) -> str:
    d = ctx.derived
    sources = []
    if not _is_zero(d.parts["T"].K):
        sources.append("the kinetic energy")
    if not _is_zero(d.parts["D"].K):
        sources.append("the dissipation function")
    if any(not _is_zero(f.part.K) for f in d.forces):
        sources.append("the forces")
    return f" (including the terms from {' and '.join(sources)})" if sources else ""


def _join_math(items: Sequence[str]) -> list:
    out: list = []
    for i, item in enumerate(items):
        if i:
            out.append(", " if i < len(items) - 1 else " and ")
        out.append(_m(item))
    return out


def forces(ctx: Context) -> list[Block]:
    d = ctx.derived
    blocks: list[Block] = [Heading("Excitation forces", 3)]
    labels = _source_labels(ctx)
    parts_shown = [(labels[k], k) for k in ("T", "D", "U") if k in labels]
    if parts_shown:
        blocks.append(paragraph("One part of the excitation, ",
                                *_join_math([rf"\mathbf{{Q}}^{{{lab}}}(t)"
                                             for lab, _ in parts_shown]),
                                ", was found above."))
    qdots = ctx.q_symbols(1)
    for i, force in enumerate(d.forces):
        label = labels.get(f"F{i}", rf"F_{{{i + 1}}}" if len(d.forces) > 1 else "F")
        if force.given:
            blocks.append(paragraph("The force ", f"“{force.name}”", " is given by its "
                                    "generalized components:"))
            blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}} = "
                                       + ctx.tex(sympy.Matrix(force.generalized))
                                       + " (given directly).", label=f"F{i}"))
        else:
            vec = ctx.tex(sympy.Matrix(force.vector))
            vel = ctx.tex(sympy.Matrix(force.velocity))
            blocks.append(paragraph("The power of the force ", f"“{force.name}”",
                                    " is the force times the velocity of the point where "
                                    "it acts:"))
            blocks.append(ctx.equation(
                rf"P = \mathbf{{F}} \cdot \mathbf{{v}} = {vec} \cdot {vel} = "
                + ctx.tex(force.power) + r" \equiv \sum_{k=1}^{n} Q_{k} \dot{q}_{k},",
                label=f"P{i}"))
            blocks.append(paragraph("from which (the coefficients of ",
                                    *_join_math(qdots), ")"))
            blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}} = "
                                       + ctx.tex(sympy.Matrix(force.generalized)) + ".",
                                       label=f"F{i}"))
        part = force.part
        if not (_is_zero(part.M) and _is_zero(part.C) and _is_zero(part.K)):
            blocks.append(paragraph("Linearized, the force depends on the motion; those terms "
                                    "belong to the left side of Eq. " + ctx.ref("eom") + ":"))
            blocks.append(ctx.equation(rf"\mathbf{{Q}}^{{{label}}} \approx "
                                       + ctx.tex(-_linear_vector(ctx, part)) + "."))
    blocks.extend(total_excitation(ctx, labels))
    return blocks


def total_excitation(ctx: Context, labels: dict[str, str]) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = []
    if not eom.excitation:
        blocks.append(paragraph("There is no excitation: ", _m(r"\mathbf{Q}(t) = \mathbf{0}"),
                                ", the system vibrates freely."))
        return blocks
    names = [rf"\mathbf{{Q}}^{{{lab}}}(t)" for lab in labels.values()]
    head = r"\mathbf{Q}(t) = " + (" + ".join(names) + " = " if len(names) > 1 else "")
    text = head + ctx.tex(eom.Q_signals) if len(names) > 1 else head + ctx.tex(eom.Q_signals)
    q_t = eom.Q
    if q_t != eom.Q_signals:
        text += " = " + ctx.tex(q_t)
    blocks.append(paragraph("Finally, the excitation force is"))
    blocks.append(ctx.equation(text + ".", label="Q"))
    blocks.extend(harmonic_split(ctx))
    return blocks


def _frequencies(ctx: Context) -> list[sympy.Expr]:
    h = ctx.eom.harmonics
    return list(h.frequencies) if h is not None else []


def harmonic_split(ctx: Context) -> list[Block]:
    eom = ctx.eom
    h = eom.harmonics
    if h is None:
        return [paragraph("The signals are not sums of harmonics, so there is no "
                          "stationary solution of the form of Eq. (37); the equation of "
                          "motion holds for any signals.")]
    blocks: list[Block] = [paragraph("For the stationary solution the excitation is written "
                                     "in the form")]
    freqs = _frequencies(ctx)
    terms = []
    for i, w in enumerate(freqs):
        sub = "" if len(freqs) == 1 else f",{i + 1}"
        if w == 0:
            terms.append(rf"\mathbf{{F}}_{{C{sub}}}")
        else:
            wt = ctx.tex(w * sympy.Symbol("t"))
            terms.append(rf"\mathbf{{F}}_{{S{sub}}} \sin\left({wt}\right) + "
                         rf"\mathbf{{F}}_{{C{sub}}} \cos\left({wt}\right)")
    blocks.append(ctx.equation(r"\mathbf{Q}(t) = " + " + ".join(terms) + ",", label="QSC"))
    blocks.append(paragraph("where, using trigonometric identities,"))
    for i, w in enumerate(freqs):
        sub = "" if len(freqs) == 1 else f",{i + 1}"
        f_s, f_c = h.forcing(eom.excitation, w)
        f_s = f_s.applyfunc(sympy.factor_terms)
        f_c = f_c.applyfunc(sympy.factor_terms)
        text = rf"\mathbf{{F}}_{{S{sub}}} = {ctx.tex(f_s)}, \quad " if w != 0 else ""
        text += rf"\mathbf{{F}}_{{C{sub}}} = {ctx.tex(f_c)}"
        blocks.append(ctx.equation(text + ("," if len(freqs) > 1 else "."), label=f"FSC{i}"))
    num_lines = []
    for x in ctx.solution.eom.harmonics:
        sub = "" if len(freqs) == 1 else rf",\,\omega = {number_latex(x.omega)}"
        line = (rf"\mathbf{{F}}_{{S{sub}}} = {vector_latex(x.F_S)}, \quad " if x.omega else "")
        num_lines.append(line + rf"\mathbf{{F}}_{{C{sub}}} = {vector_latex(x.F_C)}")
    if num_lines:
        blocks.append(paragraph("With the data:"))
        for line in num_lines:
            blocks.append(ctx.equation(line + "."))
    return blocks


def equation_of_motion(ctx: Context) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = [Heading("The linearized equation of motion", 3)]
    refs = [f"the {what} {ctx.ref(label)}" for what, label in
            (("mass matrix", "M"), ("damping matrix", "C"), ("stiffness matrix", "K"),
             ("excitation", "FSC0")) if ctx.ref(label)]
    listed = ", ".join(refs[:-1]) + " and " + refs[-1] if len(refs) > 1 else "".join(refs)
    blocks.append(paragraph("Substituting " + listed + " into Eq. " + ctx.ref("eom")
                            + " gives the equation of motion:" if refs else
                            "The equation of motion is"))
    lhs = []
    for mat, order in ((eom.M, 2), (eom.C, 1), (eom.K, 0)):
        if not _is_zero(mat):
            lhs.append(ctx.tex(mat) + _vector(ctx.q_symbols(order)))
    rhs = _rhs_latex(ctx)
    blocks.append(ctx.equation(" + ".join(lhs) + " = " + rhs + ".", label="EOM"))
    if _is_zero(eom.C):
        blocks.append(paragraph("Note that there is no damping in the system, i.e. ",
                                _m(r"\mathbf{C} = \mathbf{0}"), "."))
    if ctx.n <= MAX_MATRIX:
        num = ctx.solution.eom
        blocks.append(paragraph("With the data, the matrices are"))
        text = rf"\mathbf{{M}} = {matrix_latex(num.M)}, \quad "
        if not _is_zero(eom.C):
            text += rf"\mathbf{{C}} = {matrix_latex(num.C)}, \quad "
        text += rf"\mathbf{{K}} = {matrix_latex(num.K)}."
        blocks.append(ctx.equation(text, label="MCK"))
    return blocks


def _rhs_latex(ctx: Context) -> str:
    eom = ctx.eom
    h = eom.harmonics
    if not eom.excitation:
        return ctx.tex(sympy.zeros(ctx.n, 1))
    if h is None:
        return ctx.tex(eom.Q)
    terms = []
    for w in _frequencies(ctx):
        f_s, f_c = h.forcing(eom.excitation, w)
        f_s = f_s.applyfunc(sympy.factor_terms)
        f_c = f_c.applyfunc(sympy.factor_terms)
        wt = ctx.tex(w * sympy.Symbol("t"))
        if w == 0:
            terms.append(ctx.tex(f_c))
            continue
        if not _is_zero(f_s):
            terms.append(ctx.tex(f_s) + rf" \sin\left({wt}\right)")
        if not _is_zero(f_c):
            terms.append(ctx.tex(f_c) + rf" \cos\left({wt}\right)")
    return " + ".join(terms)


# -- Task 2 ---------------------------------------------------------------------------------

def stationary(ctx: Context) -> list[Block]:
    sol = ctx.solution
    blocks: list[Block] = [Heading("Task 2: the stationary solution")]
    if not sol.available:
        blocks.append(Note(("The signals are not sums of harmonics: there is no stationary "
                            "solution of this form (use resonant simulate).",)))
        return blocks
    blocks.append(paragraph("The equation of motion of a harmonically excited linear system "
                            "has the form"))
    blocks.append(ctx.equation(r"\mathbf{M}\ddot{\mathbf{q}}(t) + \mathbf{C}\dot{\mathbf{q}}(t)"
                               r" + \mathbf{K}\mathbf{q}(t) = \mathbf{F}_{S}\sin(\omega t) + "
                               r"\mathbf{F}_{C}\cos(\omega t),", label="eom-harmonic"))
    blocks.append(paragraph("whose stationary (particular) solution is"))
    blocks.append(ctx.equation(r"\mathbf{q}_{p}(t) = \mathbf{L}\cos(\omega t) + "
                               r"\mathbf{N}\sin(\omega t).", label="qp"))
    blocks.append(paragraph("Substituting it and its derivatives into Eq. "
                            + ctx.ref("eom-harmonic") + " and collecting the coefficients of ",
                            _m(r"\cos(\omega t)"), " and ", _m(r"\sin(\omega t)"),
                            " gives the linear algebraic equations"))
    blocks.append(ctx.equation(
        r"\begin{bmatrix} -\omega^{2}\mathbf{M} + \mathbf{K} & \omega\mathbf{C} \\ "
        r"-\omega\mathbf{C} & -\omega^{2}\mathbf{M} + \mathbf{K} \end{bmatrix} "
        r"\begin{bmatrix} \mathbf{L} \\ \mathbf{N} \end{bmatrix} = "
        r"\begin{bmatrix} \mathbf{F}_{C} \\ \mathbf{F}_{S} \end{bmatrix}.", label="LN"))
    freqs = _frequencies(ctx)
    responses = sol.harmonics
    several = len(responses) > 1
    for response in responses:
        if several:
            what = "the static part" if response.omega == 0 else \
                f"the frequency ω = {number_text(response.omega)} rad/s"
            blocks.append(paragraph(f"For {what}:"))
        symbolic_w = _symbolic_frequency(ctx, response.omega, freqs)
        blocks.extend(_symbolic_system(ctx, symbolic_w))
        blocks.extend(_numeric_system(ctx, response))
    blocks.append(paragraph("Finally, the stationary solution reads"))
    terms = []
    for r in responses:
        if r.omega == 0:
            terms.append(vector_latex(r.L))
            continue
        wt = number_latex(r.omega) + "t"
        terms.append(vector_latex(r.L) + rf"\cos({wt}) + " + vector_latex(r.N)
                     + rf"\sin({wt})")
    blocks.append(ctx.equation(r"\mathbf{q}_{p}(t) = " + " + ".join(terms) + ".",
                               label="qp-numeric"))
    return blocks


def _symbolic_frequency(ctx: Context, omega: float, freqs: list[sympy.Expr]) -> sympy.Expr | None:
    values = {symbol(n): v for n, v in ctx.model.parameter_values.items()}
    for w in freqs:
        try:
            if math.isclose(abs(float(w.evalf(subs=values))), omega, rel_tol=1e-9, abs_tol=1e-12):
                return w
        except (TypeError, ValueError):
            continue
    return None


def _symbolic_system(ctx: Context, w: sympy.Expr | None) -> list[Block]:
    eom = ctx.eom
    n = ctx.n
    if w is None or n > MAX_SYMBOLIC_SYSTEM or ctx.model.matrices is not None:
        return []
    A = eom.K - w**2 * eom.M
    B = (w * eom.C).applyfunc(sympy.expand)
    big = sympy.zeros(2 * n, 2 * n)
    big[:n, :n] = A
    big[n:, n:] = A
    big[:n, n:] = B
    big[n:, :n] = -B
    assert eom.harmonics is not None  # a stationary solution exists: the signals are harmonic
    f_s, f_c = eom.harmonics.forcing(eom.excitation, w)
    rhs = sympy.Matrix([*f_c.applyfunc(sympy.factor_terms), *f_s.applyfunc(sympy.factor_terms)])
    unknowns = [f"L_{{{i + 1}}}" for i in range(n)] + [f"N_{{{i + 1}}}" for i in range(n)]
    blocks: list[Block] = [
        paragraph("For our system this yields"),
        ctx.equation(ctx.tex(big) + _vector(unknowns) + " = " + ctx.tex(rhs) + ",",
                     label="LN-symbolic")]
    if all(e == 0 for e in eom.C):
        # no damping: the system splits into one for L and one for N (exercise (40)-(41))
        rows = [[_symbolic_coef(ctx, A[i, j]) for j in range(n)]
                for i in range(n)]
        blocks.append(paragraph("which can be divided into two independent systems of "
                                f"equations with {n} unknowns:"))
        for names, vector, label in ((unknowns[:n], rhs[:n], "L-symbolic"),
                                     (unknowns[n:], rhs[n:], "N-symbolic")):
            blocks.append(ctx.equation(_cases(rows, names, [ctx.tex(v) for v in vector]),
                                       label=label))
    return blocks


def _numeric_system(ctx: Context, response) -> list[Block]:
    num = ctx.solution.eom
    n = ctx.n
    w = response.omega
    blocks: list[Block] = []
    if n > MAX_MATRIX:
        blocks.append(paragraph(f"Solving the {2 * n} equations numerically gives L and N "
                                "(not listed for this many coordinates)."))
        return blocks
    A = num.K - w**2 * num.M
    B = w * num.C
    L_names = [f"L_{{{i + 1}}}" for i in range(n)]
    N_names = [f"N_{{{i + 1}}}" for i in range(n)]
    solution_L = ", ".join(f"{a} = {number_latex(v)}" for a, v in zip(L_names, response.L))
    solution_N = ", ".join(f"{a} = {number_latex(v)}" for a, v in zip(N_names, response.N))
    blocks.append(paragraph("By substituting the numerical data, it yields"))
    if not np.any(B) or w == 0:
        blocks.append(paragraph("two independent systems (the damping terms vanish):")
                      if w != 0 else paragraph("the static system:"))
        rows = [[_numeric_coef(v) for v in row] for row in A]
        blocks.append(ctx.equation(_cases(rows, L_names, [number_latex(v) for v in response.F_C])
                                   + r" \implies " + solution_L + ",", label="L-numeric"))
        if w != 0:
            blocks.append(ctx.equation(_cases(rows, N_names,
                                              [number_latex(v) for v in response.F_S])
                                       + r" \implies " + solution_N + ".", label="N-numeric"))
        return blocks
    big = np.block([[A, B], [-B, A]])
    rhs = np.concatenate([response.F_C, response.F_S])
    rows = [[_numeric_coef(v) for v in row] for row in big]
    blocks.append(ctx.equation(_cases(rows, L_names + N_names, [number_latex(v) for v in rhs]),
                               label="LN-numeric"))
    blocks.append(paragraph("whose solution is"))
    blocks.append(ctx.equation(solution_L + r", \quad " + solution_N + "."))
    return blocks


# -- Task 3 ---------------------------------------------------------------------------------

def _reference_values(ctx: Context) -> dict[str, float]:
    """The numeric reference state q0 of every coordinate ([equilibrium], else 0)."""
    values = ctx.model.parameter_values
    out = {}
    for c in ctx.eom.coordinates:
        expression = ctx.model.equilibrium.get(c)
        out[c] = float(numeric_value(expression, values)) if expression is not None else 0.0
    return out


def excursions(ctx: Context) -> list[Block]:
    sol = ctx.solution
    if not sol.available or not sol.harmonics:
        return []
    blocks: list[Block] = [Heading("Task 3: the maximal excursions")]
    moving = [r for r in sol.harmonics if r.omega > 0]
    single = len(sol.harmonics) == 1 and len(moving) == 1
    coords = ctx.eom.coordinates
    if single:
        blocks.append(paragraph("Each coordinate of Eq. " + ctx.ref("qp-numeric")
                                + " is a harmonic function,"))
        blocks.append(ctx.equation(r"q_{k}(t) = L_{k}\cos(\omega t) + N_{k}\sin(\omega t) = "
                                   r"X_{k}\sin(\omega t + \delta_{k}), \quad X_{k} = "
                                   r"\sqrt{L_{k}^{2} + N_{k}^{2}}, \quad \delta_{k} = "
                                   r"\mathrm{atan2}(L_{k}, N_{k}),", label="X"))
        blocks.append(paragraph("so the maximal excursions are"))
    else:
        blocks.append(paragraph("With several frequencies, the maximal excursion is the peak "
                                "of the sum over the common period:"))
    rows = []
    units = result_units(ctx.model)
    si = {name: unit_latex(text) for name, text in units.si.items() if text != "1"} \
        if units is not None else {}
    shifted = {c: q0 for c, q0 in _reference_values(ctx).items() if q0 != 0}
    if shifted:
        blocks.append(paragraph(
            "The coordinates " + ", ".join(ctx.namer(c) for c in shifted) + " oscillate "
            "about their reference values, so their excursions are deviations from them, "
            "written with a Δ:"))
    for k, c in enumerate(coords):
        amp = sol.amplitudes[c]
        name = (r"\Delta " + ctx.namer(c)) if c in shifted else ctx.namer(c)
        if single:
            L, N = sol.output_harmonics[c][0]
            phase = sol.phases.get(c)
            text = (rf"{with_subscript(name, MAX)} = X_{{{k + 1}}} = \sqrt{{L_{{{k + 1}}}^{{2}} + "
                    rf"N_{{{k + 1}}}^{{2}}}} = {number_latex(amp)}{si.get(c, '')}")
            if phase is not None:
                text += rf", \quad \delta_{{{k + 1}}} = {number_latex(phase)}\ \text{{rad}}"
            blocks.append(ctx.equation(text + ",", label=f"X:{c}"))
        else:
            blocks.append(ctx.equation(rf"\max_{{t}} \left|{name}(t)\right| = "
                                       f"{number_latex(amp)},", label=f"X:{c}"))
        if c in shifted:  # the absolute values a reader expects
            q0 = shifted[c]
            plain = ctx.namer(c)
            blocks.append(ctx.equation(
                rf"{plain}_{{0}} = {number_latex(q0)}, \quad {plain}(t) \in "
                rf"[{number_latex(q0 - amp)},\ {number_latex(q0 + amp)}],",
                label=f"range:{c}"))
        rows.append((c, amp))
    outputs = ctx.eom.outputs
    if outputs:
        blocks.append(paragraph("The outputs of the model are linearized like everything "
                                "else:"))
    deviation = {c: sympy.Symbol(f"Delta_{c}") for c in shifted}
    for c, s in deviation.items():
        ctx.names[s] = r"\Delta " + ctx.namer(c)
    for name, out in outputs.items():
        # linear in the deviations: Delta r (not r) where the reference value is not zero
        lin = out.value + sum((coef * (deviation[v] if order == 0 and v in deviation
                                       else derivative_symbol(v, order))
                               for (v, order), coef in out.terms.items()), sympy.Integer(0))
        given = expression_latex(ctx.model.outputs[name], ctx.namer)
        pretty = ctx.namer(name)
        blocks.append(ctx.equation(f"{pretty} = {given} \\approx {ctx.tex(lin)},",
                                   label=f"out:{name}"))
        amp = sol.amplitudes[name]
        if single:
            L, N = sol.output_harmonics[name][0]
            text = (rf"{with_subscript(pretty, MAX)} = "
                    rf"\sqrt{{L_{{{pretty}}}^{{2}} + N_{{{pretty}}}^{{2}}}} = "
                    rf"\sqrt{{({number_latex(L)})^{{2}} + ({number_latex(N)})^{{2}}}} = "
                    f"{number_latex(amp)}{si.get(name, '')}")
            phase = sol.phases.get(name)
            if phase is not None:
                text += rf", \quad \delta_{{{pretty}}} = {number_latex(phase)}\ \text{{rad}}"
        else:
            text = rf"\max_{{t}} \left|{pretty}(t)\right| = {number_latex(amp)}"
        blocks.append(ctx.equation(text + ".", label=f"X:{name}"))
    phase_unit = units.phase if units is not None else RAD
    header = (cell("quantity"), cell("amplitude"), cell(f"phase δ [{phase_unit.text}]"))
    table_rows = []
    for name in [*coords, *outputs]:
        phase = sol.phases.get(name)
        label = (r"\Delta " + ctx.namer(name)) if name in shifted else ctx.namer(name)
        shown = units.unit(name) if units is not None else NO_UNIT
        table_rows.append((cell(_m(label)), cell(_m(number_latex(shown(sol.amplitudes[name]))
                                                    + unit_latex(shown.text))),
                           cell(_m(number_latex(phase_unit(phase)))) if phase is not None
                           else cell("")))
    blocks.append(paragraph("Summary of the stationary response:"))
    blocks.append(Table(header, tuple(table_rows)))
    return blocks


# -- natural frequencies, modes, stability ---------------------------------------------------

#: above this many operations the characteristic polynomial is not expanded in the report
MAX_CHARACTERISTIC_OPS = 300


def _small_determinant(matrix: sympy.Matrix) -> sympy.Expr | None:
    """The determinant of a 1x1 or 2x2 matrix by its formula, or None where expanding it
    would not help a reader: entries with radicals (sympy's ``det`` and ``expand`` took
    minutes on the elastic pendulum's sqrt((L0 + g*m/k)^2)) or too many operations."""
    if matrix.shape == (1, 1):
        det = matrix[0, 0]
    else:
        det = matrix[0, 0] * matrix[1, 1] - matrix[0, 1] * matrix[1, 0]
    radical = any(not power.exp.is_Integer for power in det.atoms(sympy.Pow))
    if radical or sympy.count_ops(det) > MAX_CHARACTERISTIC_OPS:
        return None
    return det


def _characteristic(ctx: Context) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = []
    w = sympy.Symbol("omega_n", positive=True)
    det = _small_determinant(eom.K - w**2 * eom.M) \
        if ctx.n <= 2 and ctx.model.matrices is None else None
    if det is not None:
        det = sympy.collect(sympy.expand(det), w)
        # factored where that is shorter (uncoupled or symmetric systems): the roots show
        factored = sympy.factor(det)
        if isinstance(factored, sympy.Mul) and sympy.count_ops(factored) < sympy.count_ops(det):
            det = factored
        names = dict(ctx.names)
        names[w] = r"\omega_{n}"
        blocks.append(paragraph("The undamped natural frequencies are the roots of the "
                                "characteristic equation"))
        blocks.append(ctx.equation(r"\det\left(\mathbf{K} - \omega_{n}^{2}\mathbf{M}\right) = "
                                   + sympy_latex(det, names) + " = 0,", label="char"))
    else:
        blocks.append(paragraph("The undamped natural frequencies follow from ",
                                _m(r"\det\left(\mathbf{K} - \omega_{n}^{2}\mathbf{M}\right) = 0"),
                                ":"))
    return blocks


def natural_frequencies(ctx: Context, with_modes: bool = False) -> list[Block]:
    sol = ctx.solution
    heading = ("Task 2: free vibration — natural frequencies and mode shapes" if with_modes
               else "Natural frequencies and stability")
    blocks: list[Block] = [Heading(heading, 2 if with_modes else 2)]
    blocks.extend(_characteristic(ctx))
    freqs = sol.natural_frequencies
    if freqs.size:
        text = r", \quad ".join(
            rf"\omega_{{{i + 1}}} = {number_latex(w)}\ \text{{rad/s}}\ "
            rf"(f_{{{i + 1}}} = {number_latex(w / (2 * math.pi))}\ \text{{Hz}})"
            for i, w in enumerate(freqs))
        blocks.append(ctx.equation(text + ".", label="omega-n"))
    else:
        blocks.append(paragraph("There is no positive eigenvalue: no natural frequency."))
    if ctx.n <= MAX_MATRIX and freqs.size:
        blocks.extend(_modes(ctx))
        blocks.extend(_modal_damping(ctx))
    blocks.extend(_stability(ctx))
    return blocks


def _modal_damping(ctx: Context) -> list[Block]:
    """Modal damping ratios (proportional damping) or those of the complex modes."""
    num = ctx.solution.eom
    if not np.any(num.C):
        return []
    analysis = modes(num)
    zetas = analysis.damping_ratios
    if not zetas.size:
        return []
    how = ("The damping is proportional (the undamped modes decouple it); the modal "
           "damping ratios are" if analysis.proportional_damping else
           "The damping is not proportional; from the complex eigenvalues s of the state "
           "matrix, the damping ratios -Re s/|s| are")
    text = r", \quad ".join(rf"\zeta_{{{i + 1}}} = {number_latex(z)}"
                            for i, z in enumerate(zetas))
    return [paragraph(how), ctx.equation(text + ".", label="zeta")]


def _modes(ctx: Context) -> list[Block]:
    num = ctx.solution.eom
    lam, vectors = undamped_eigen(num.M, num.K)
    blocks: list[Block] = [paragraph("The mode shapes solve ",
                                     _m(r"\left(\mathbf{K} - \omega_{i}^{2}\mathbf{M}\right)"
                                        r"\mathbf{u}_{i} = \mathbf{0}"),
                                     "; normalized so that the largest component is +1 they "
                                     "are")]
    shapes = []
    for i in range(vectors.shape[1]):
        v = np.real(vectors[:, i])
        big = v[int(np.argmax(np.abs(v)))]
        v = v / big if big != 0 else v
        v = np.where(np.abs(v) < 1e-12, 0.0, v)
        shapes.append(rf"\mathbf{{u}}_{{{i + 1}}} = {vector_latex(v)}")
    blocks.append(ctx.equation(r", \quad ".join(shapes) + ".", label="modes"))
    return blocks


def _stability(ctx: Context) -> list[Block]:
    sol = ctx.solution
    eig = sol.eigenvalues
    blocks: list[Block] = []
    if eig.size and ctx.n <= MAX_MATRIX:
        shown = []
        for value in sorted(eig, key=lambda z: (round(z.real, 12), z.imag)):
            re, im = float(value.real), float(value.imag)
            if abs(re) < 1e-9 * max(1.0, abs(value)):
                re = 0.0  # rounding noise of an undamped mode
            if abs(im) < 1e-12 * max(1.0, abs(value)):
                shown.append(number_latex(re))
            elif re == 0:
                shown.append(f"{'-' if im < 0 else ''}{number_latex(abs(im))}\\,i")
            else:
                sign = "+" if im >= 0 else "-"
                shown.append(f"{number_latex(re)} {sign} {number_latex(abs(im))}\\,i")
        blocks.append(paragraph("The eigenvalues of the state matrix ",
                                _m(r"\begin{bmatrix} \mathbf{0} & \mathbf{I} \\ -\mathbf{M}^{-1}"
                                   r"\mathbf{K} & -\mathbf{M}^{-1}\mathbf{C} \end{bmatrix}"),
                                " are"))
        blocks.append(ctx.equation(r"\lambda = " + r",\ ".join(shown) + ","))
    reason = {"asymptotically stable": "every eigenvalue has a negative real part",
              "marginally stable": "no eigenvalue has a positive real part and some lie on "
                                   "the imaginary axis: some modes are undamped",
              "unstable": "an eigenvalue has a positive real part"}.get(sol.stability, "")
    blocks.append(paragraph(f"so the equilibrium is {sol.stability}"
                            + (f" ({reason})." if reason else ".")))
    return blocks


def plots(ctx: Context) -> list[Block]:
    if not ctx.plots:
        return []

    sol = ctx.solution
    if not sol.available or not sol.harmonics:
        return []
    frf = frequency_response(ctx.eom, sol)
    history = time_history(sol)
    if frf is None and history is None:
        return []
    blocks: list[Block] = [Heading("Frequency response and time history")]
    if frf is not None:
        how = (f"the excitation frequency {frf.parameter} is swept and the excitation "
               "amplitudes follow it" if frf.parameter else
               "the excitation amplitudes are held at their operating values")
        what = "coordinates and outputs" if len(frf.amplitudes) > ctx.n else "coordinates"
        blocks.append(ctx.figure(frf, f"Amplitudes of the {what} against the excitation "
                                 f"frequency ({how}); dots: the operating point, dashed: the "
                                 "excitation frequency, dotted: the natural frequencies."))
    if history is not None:
        several = len([h for h in ctx.solution.harmonics if h.omega > 0]) > 1
        what = ("two periods of the excitation" if not several else
                f"two common periods (T = {history.period:.4g} s) of the excitation's "
                "frequencies" if history.periodic else
                "two periods of the slowest excitation frequency (the frequencies are "
                "incommensurate: the excitation is not periodic)")
        blocks.append(ctx.figure(history, f"The stationary solution over {what}."))
    return blocks


def warnings(ctx: Context) -> list[Block]:
    if not ctx.solution.warnings:
        return []
    blocks: list[Block] = [Heading("Warnings")]
    blocks.extend(Note((w,)) for w in ctx.solution.warnings)
    return blocks


# -- matrix models ---------------------------------------------------------------------------

def given_matrices(ctx: Context) -> list[Block]:
    eom = ctx.eom
    blocks: list[Block] = [Heading("Task 1: the equation of motion")]
    if ctx.model.matrices is not None:
        blocks.append(paragraph("The model gives the matrices of the linearized equation of "
                                "motion directly:"))
    else:  # a large energy model: the energies, then the matrices Lagrange's equations give
        blocks.append(paragraph("The model gives its energies:"))
        for key, label in (("T", "T"), ("D", r"\mathcal{D}"), ("U", "U")):
            if key in ctx.model.energy:
                blocks.append(ctx.equation(
                    f"{label} = {expression_latex(ctx.model.energy[key], ctx.namer)}",
                    label=key))
        blocks.append(paragraph(
            f"With {ctx.n} coordinates the element-by-element derivation is left out; "
            "Lagrange's equations of the second kind at the reference state give"))
    blocks.append(ctx.equation(r"\mathbf{M}\ddot{\mathbf{q}}(t) + \mathbf{C}\dot{\mathbf{q}}(t)"
                               r" + \mathbf{K}\mathbf{q}(t) = \mathbf{Q}(t),", label="eom"))
    blocks.extend(coordinates(ctx, "Generalized coordinates"))
    if ctx.n <= MAX_MATRIX:
        symbolic = any(not e.is_Number for e in [*eom.M, *eom.C, *eom.K])
        for label in ("M", "C", "K"):
            mat = getattr(eom, label)
            if label == "C" and _is_zero(mat):
                continue
            text = rf"\mathbf{{{label}}} = "
            if symbolic:
                text += ctx.tex(mat) + " = "
            text += matrix_latex(getattr(ctx.solution.eom, label))
            blocks.append(ctx.equation(text + ",", label=label))
        if _is_zero(eom.C):
            blocks.append(paragraph("There is no damping: ", _m(r"\mathbf{C} = \mathbf{0}"), "."))
    else:
        blocks.append(paragraph(f"M, C and K are {ctx.n} x {ctx.n} matrices (not shown)."))
    blocks.append(Heading("Excitation", 3))
    if ctx.solution.eom.harmonics:
        blocks.extend(harmonic_split(ctx))
    else:
        blocks.append(paragraph("There is no excitation: the system vibrates freely."))
    return blocks


# -- the order of the steps ------------------------------------------------------------------

Step = Callable[[Context], list[Block]]


def step_order(ctx: Context) -> list[Step]:
    """The steps for this model, in the exercise's order."""
    free = not ctx.eom.excitation
    if ctx.model.matrices is not None or ctx.derivation is None:
        steps: list[Step] = [title, data, given_matrices]
    elif ctx.model.parts is not None:  # the energies derived part by part (report/parts.py)
        steps = [title, data, method, coordinates, part_steps.kinetic, kinetic,
                 part_steps.after_heading(dissipation, part_steps.dissipation),
                 part_steps.after_heading(potential, part_steps.potential), forces,
                 equation_of_motion]
    else:
        steps = [title, data, method, coordinates, kinetic, dissipation, potential, forces,
                 equation_of_motion]
    if ctx.model.parts is not None:
        steps.insert(1, part_steps.figure)  # "In Fig. 1 ...": the figure first, as the exercise
    if free:
        steps.append(lambda c: natural_frequencies(c, with_modes=True))
    else:
        steps.extend([stationary, excursions, natural_frequencies, plots])
    steps.append(warnings)
    return steps


__all__ = ["Context", "step_order"]
