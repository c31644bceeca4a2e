"""Stage 2: the linearized equation of motion M q'' + C q' + K q = Q(t).

Lagrange's equations of the second kind are formed from the second-order
Taylor expansions (:class:`~resonant.jet.Jet`) of T, D, U and of the power of
each force about the reference state.  Small of first order are the
coordinate deviations, their derivatives, the signals and their derivatives,
so a T, U or D that depends on time through a signal (moving support,
rotating unbalance) contributes to Q(t) exactly as in the reference
exercise, Eqs. (5)-(6) and (22)-(25).

Examples
--------
>>> from resonant.model import loads
>>> eom = loads('''
... [parameters]
... m = 1
... k = 4
... c = 0.1
... [coordinates]
... x = "displacement"
... [signals]
... y = "sin(2*t)"
... [energy]
... T = "m*x'^2/2"
... U = "k*(x - y)^2/2"
... D = "c*x'^2/2"
... ''').linearize()
>>> eom.M, eom.C, eom.K
(Matrix([[m]]), Matrix([[c]]), Matrix([[k]]))
>>> eom.Q
Matrix([[k*sin(2*t)]])
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from types import MappingProxyType
from typing import Any

import sympy

from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem
from ..expressions import Expression
from ..model import TIME, Model, symbol
from ..model.loader import definition_chain
from .jet import SYMPY, Backend, Jet, NotDifferentiable, Var, backend
from .nonlinear import find_equilibrium
from .residual import is_zero


@dataclass(frozen=True)
class LinearMap:
    """A linearized quantity: value + sum over small quantities of coefficient * quantity.

    ``terms`` maps ``(name, order)`` (coordinate or signal and derivative order)
    to its symbolic coefficient.
    """

    value: sympy.Expr
    terms: Mapping[Var, sympy.Expr]


@dataclass(frozen=True)
class Linearization:
    """What Lagrange's equations give at the reference state (read by :mod:`resonant.system`).

    Attributes
    ----------
    M, C, K : sympy.ImmutableMatrix
        Mass, damping and stiffness matrices in the model's own symbols.
    excitation : mapping
        ``(signal, order) -> column`` such that
        Q(t) = sum of column * d^order signal / dt^order.
    residual : sympy.ImmutableMatrix
        The generalized forces left at the reference state with all signals
        zero (zero at an equilibrium).
    outputs : mapping
        Each output as a :class:`LinearMap`.
    """

    model: Model
    coordinates: tuple[str, ...]
    M: sympy.ImmutableMatrix
    C: sympy.ImmutableMatrix
    K: sympy.ImmutableMatrix
    excitation: Mapping[Var, sympy.ImmutableMatrix]
    residual: sympy.ImmutableMatrix
    outputs: Mapping[str, LinearMap] = field(default_factory=dict)


def signal_symbol(name: str, order: int) -> sympy.Symbol:
    """The symbol used for the order-th derivative of a signal, e.g. ``r'``."""
    return symbol(name + "'" * order)


def _strings(matrix: sympy.MatrixBase) -> list[list[str]]:
    return [[str(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)]


def signal_derivatives(model: Model, needed: set[Var]) -> dict[Var, sympy.Expr]:
    params = {name: symbol(name) for name in model.parameters}
    out: dict[Var, sympy.Expr] = {}
    base: dict[str, sympy.Expr] = {}
    for name, order in sorted(needed):
        if name not in base:
            base[name] = model.signals[name].to_sympy(
                lambda n, p: TIME if n == "t" else params[n])
        out[(name, order)] = sympy.diff(base[name], TIME, order) if order else base[name]
    return out


# -- jet evaluation of the model's expressions -------------------------------------------

#: from this many coordinates on, jets compute with symengine (sympy below: no extra import)
SYMENGINE_MIN_COORDINATES = 4


def choose_backend(model: Model) -> Backend:
    """sympy for textbook-sized models, symengine for larger ones."""
    return backend("symengine") if len(model.coordinates) >= SYMENGINE_MIN_COORDINATES \
        else SYMPY


class _JetOps:
    """Folds a parsed expression into its second-order jet."""

    def __init__(self, model: Model, cas: Backend | None = None,
                 deadline: Deadline = NO_DEADLINE) -> None:
        self.model = model
        self.deadline = deadline
        self.cas = cas or choose_backend(model)
        self.params = {name: Jet(self.cas.symbol(name)) for name in model.parameters}
        self.equilibrium = {
            q: (self.cas.from_sympy(model.equilibrium[q].to_sympy(
                lambda n, p: symbol(n) if p == 0 else sympy.Integer(0)))
                if q in model.equilibrium else 0)
            for q in model.coordinates}
        self.converted: dict = {}  # symengine -> sympy conversions, shared across entries
        self.coordinates = set(model.coordinates)
        self.definition_jets: dict[tuple[str, int], Jet] = {}
        self.where = ("", "")

    def jet(self, expression: Expression, section: str, key: str) -> Jet:
        self.where = (section, key)
        try:
            return self.whole(expression.fold(self))
        except NotDifferentiable as exc:
            raise ModelError(Problem(f"{exc} (in '{_short(expression.text)}')",
                                     self.model.source, section, key)) from None
        except ZeroDivisionError:
            raise ModelError(Problem(f"division by zero in '{_short(expression.text)}'",
                                     self.model.source, section, key)) from None

    # fold operations
    def num(self, text: str) -> Jet:
        value = Fraction(text)
        return Jet(self.cas.rational(value.numerator, value.denominator))

    def pi(self) -> Jet:
        return Jet(self.cas.pi)

    def to_sympy(self, value: Any) -> sympy.Expr:
        return self.cas.to_sympy(value, self.converted)

    def name(self, name: str, primes: int) -> Jet:
        if name in self.coordinates:
            return Jet.variable((name, primes), self.equilibrium[name] if primes == 0 else 0)
        if name in self.model.signals:
            return Jet.variable((name, primes))
        if name in self.params:
            return self.params[name] if primes == 0 else Jet()
        return self.definition(name, primes)

    def definition(self, name: str, primes: int) -> Jet:
        key = (name, primes)
        if key not in self.definition_jets:
            if primes == 0:
                saved = self.where
                self.definition_jets[key] = self.jet(self.model.definitions[name],
                                                     "definitions", name)
                self.where = saved
            else:
                self.definition_jets[key] = self.definition(name, primes - 1).dt()
        return self.definition_jets[key]

    # Sums are collected lazily (a list of terms) and built once when used: a sum of
    # N jets then costs O(N) per coefficient instead of O(N^2) for pairwise sums.
    def whole(self, value: Jet | _Terms) -> Jet:
        return Jet.sum(value.jets, self.cas) if isinstance(value, _Terms) else value

    def add(self, a: Jet | _Terms, b: Jet | _Terms) -> _Terms:
        # each fold value is used by exactly one parent, so a term list may grow in place
        terms = a if isinstance(a, _Terms) else _Terms([a])
        terms.jets.extend(b.jets if isinstance(b, _Terms) else [b])
        return terms

    def sub(self, a: Jet | _Terms, b: Jet | _Terms) -> _Terms:
        return self.add(a, -self.whole(b))

    def tick(self) -> None:
        """The deadline, checked every few products (the costly operations)."""
        section, key = self.where
        self.deadline.every(16, f"while expanding '{key}'" if key else "during the derivation",
                            section, key)

    def mul(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        self.tick()
        return self.whole(a) * self.whole(b)

    def div(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        return self.whole(a) / self.whole(b)

    def pow(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        a, b = self.whole(a), self.whole(b)
        if not b.is_constant():  # a^b = exp(b log a)
            return (b * a.apply("log", self.cas)).apply("exp", self.cas)
        return a ** b

    def neg(self, a: Jet | _Terms) -> Jet:
        return -self.whole(a)

    def call(self, func: str, args: list) -> Jet:
        self.tick()
        args = [self.whole(a) for a in args]
        if func == "atan2":
            return args[0].atan2(args[1], self.cas)
        return args[0].apply(func, self.cas)


class _Terms:
    """A sum of jets not yet built (see ``_JetOps.whole``)."""

    __slots__ = ("jets",)

    def __init__(self, jets: list[Jet]) -> None:
        self.jets = jets


def _short(text: str, limit: int = 60) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."


def linearize(model: Model, cas: str | None = None, deadline: Deadline = NO_DEADLINE
              ) -> Linearization:
    """Derive the linearized equation of motion of a model given by its energies.

    Parameters
    ----------
    model : Model
        A validated model (see :func:`resonant.load`) with ``[energy]``.
    cas : {"sympy", "symengine"}, optional
        The algebra system of the jets; by default chosen by the model's size.
    deadline : Deadline, optional
        Checked between the operations of the derivation.

    Returns
    -------
    Linearization

    Raises
    ------
    ModelError
        If an expression cannot be expanded at the reference state, an energy
        depends on accelerations, the reference state is not an equilibrium
        (the message gives the residual per coordinate and, where one is found
        nearby, the equilibrium to put in ``[equilibrium]``), the derivation
        overflows, nests too deeply or exceeds the deadline.
    """
    ops = _JetOps(model, backend(cas) if cas else None, deadline)
    try:
        return _linearize(model, ops)
    except RecursionError:
        raise ModelError(Problem(
            "the derivation nests too deeply" + definition_chain(model.definitions)
            + "; use fewer levels of definitions that refer to each other",
            model.source, "definitions")) from None
    except OverflowError:
        section, key = ops.where
        what = f" while expanding '{key}'" if key else ""
        raise ModelError(Problem(
            f"a number overflowed{what}: the model's numbers (or functions such as "
            "exp of large values) exceed the floating-point range; rescale the "
            "parameters or simplify the expression", model.source, section, key)) from None


def _linearize(model: Model, ops: _JetOps) -> Linearization:
    coords = model.coordinates
    energies = {key: ops.jet(model.energy[key], "energy", key) if key in model.energy else Jet()
                for key in ("T", "U", "D")}
    for key, jet in energies.items():
        too_high = sorted({v for v in jet.variables() if v[0] in ops.coordinates and
                           v[1] > (0 if key == "U" else 1)})
        if too_high:
            name, order = too_high[0]
            what = "velocities" if key == "U" else "accelerations"
            raise ModelError(Problem(
                f"{key} depends on {name}{chr(39) * order}; {key} may not depend on {what}",
                model.source, "energy", key))
    T, U, D = energies["T"], energies["U"], energies["D"]
    equations = [T.diff((q, 1)).dt() - T.diff((q, 0)) + D.diff((q, 1)) + U.diff((q, 0))
                 for q in coords]
    for k, force in enumerate(_generalized_forces(model, ops)):
        equations[k] = equations[k] - force

    n = len(coords)
    index = {q: i for i, q in enumerate(coords)}
    mats = {order: sympy.zeros(n, n) for order in (0, 1, 2)}
    excitation: dict[Var, sympy.Matrix] = {}
    for k, eq in enumerate(equations):
        for (name, order), coef in eq.lin.items():
            if name in index:
                if order > 2:
                    raise ModelError(Problem(
                        f"the equations contain {name}{chr(39) * order}: forces may depend on "
                        "coordinates and their first two derivatives only", model.source,
                        "force"))
                mats[order][k, index[name]] += ops.to_sympy(coef)
            else:
                excitation.setdefault((name, order), sympy.zeros(n, 1))[k] -= ops.to_sympy(coef)
    residual = sympy.ImmutableMatrix([ops.to_sympy(eq.const) for eq in equations])
    ops.where = ("equilibrium", "")
    ops.deadline.check("while checking that the reference state is an equilibrium",
                       "equilibrium")
    _check_equilibrium(model, residual)
    outputs = {}
    for name, expression in model.outputs.items():
        jet = ops.jet(expression, "outputs", name)
        outputs[name] = LinearMap(ops.to_sympy(jet.const), MappingProxyType(
            {v: ops.to_sympy(c) for v, c in jet.lin.items()}))
    return Linearization(
        model=model, coordinates=coords,
        M=clean(mats[2]), C=clean(mats[1]), K=clean(mats[0]),
        excitation=MappingProxyType({v: sympy.ImmutableMatrix(clean(c))
                                     for v, c in sorted(excitation.items())
                                     if any(e != 0 for e in c)}),
        residual=residual, outputs=MappingProxyType(outputs))


def clean(matrix: sympy.MatrixBase) -> sympy.ImmutableMatrix:
    """The immutable form of an assembled matrix.

    No simplification pass: sympy's automatic evaluation already combines the
    jets' terms (``m2/4 + m2/12`` is ``m2/3``), and a pass such as ``cancel``
    would expand powers like ``(a + b)^50`` term by term.
    """
    return sympy.ImmutableMatrix(matrix)


def _generalized_forces(model: Model, ops: _JetOps) -> list[Jet]:
    """Q_k = F . d(point)/d(q_k), to first order (the force is not differentiated)."""
    coords = model.coordinates
    total = [Jet() for _ in coords]
    for force in model.forces:
        section = f"force '{force.name}'"
        if force.generalized:
            for k, q in enumerate(coords):
                if q in force.generalized:
                    total[k] = total[k] + ops.jet(force.generalized[q], section,
                                                  f"generalized.{q}").truncate(1)
            continue
        vector = [ops.jet(v, section, f"vector[{j}]").truncate(1)
                  for j, v in enumerate(force.vector)]
        point = [ops.jet(p, section, f"point[{j}]") for j, p in enumerate(force.point)]
        for p in point:
            rates = {v for v in p.variables() if v[0] in ops.coordinates and v[1] > 0}
            if rates:
                raise ModelError(Problem(
                    f"the point depends on a velocity ({rates.pop()[0]}'); a point is a "
                    "position", model.source, section, "point"))
        for k, q in enumerate(coords):
            for f, p in zip(vector, point):
                total[k] = total[k] + (f * p.diff((q, 0))).truncate(1)
    return total


def _check_equilibrium(model: Model, residual: sympy.ImmutableMatrix) -> None:
    subs = {symbol(n): v for n, v in model.exact_values.items()}
    bad = []
    for k, expr in enumerate(residual):
        if expr == 0:
            continue
        # judged against the size of every term that forms it, at every level of the
        # tree (never expanded: expansion can explode); see derivation.residual
        zero, value = is_zero(expr, subs)
        if not zero:
            bad.append((model.coordinates[k], expr, value.real))
    if not bad:
        return
    lines = ["the reference state is not an equilibrium: with all signals zero the "
             "generalized forces do not balance"]
    for name, expr, value in bad:
        lines.append(f"  residual in the equation of {name}: {expr} = {value:.6g}")
    nearby = _nearby_equilibrium(model)
    if nearby:
        lines.append("  a nearby equilibrium: " + ", ".join(
            f"{q} = {v:.10g}" for q, v in nearby.items())
            + " -- put it in [equilibrium]")
    else:
        lines.append("  set the reference state in [equilibrium] (coordinate = value)")
    raise ModelError(Problem("\n".join(lines), model.source, "equilibrium"))


def _nearby_equilibrium(model: Model) -> dict[str, float] | None:
    try:
        return find_equilibrium(model)
    except (AnalysisError, ModelError, ArithmeticError, ValueError, TypeError):
        return None


__all__ = ["Linearization", "LinearMap", "linearize", "signal_symbol", "signal_derivatives",
           "clean"]
