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
>>> from resonant.api import loads
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

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from types import MappingProxyType
from typing import Any

import numpy as np
import sympy

from ..deadline import NO_DEADLINE, Deadline, DeadlineExceeded
from ..errors import AnalysisError, ModelError, Problem
from ..expressions import Expression, numeric_value
from ..expressions.functions import MATH
from ..model import TIME, Model, symbol
from ..model.loader import definition_chain
from .jet import FLOAT, SYMPY, Backend, Coefficient, Jet, NotDifferentiable, Var, backend
from .nonlinear import derivative_symbol, find_equilibrium
from .residual import Sized, is_zero

#: the symbol of a signal's derivative, e.g. ``r'`` (the same as a coordinate's)
signal_symbol = derivative_symbol



@dataclass(frozen=True)
class LinearMap:
    """A linearized quantity: value + sum over small quantities of coefficient * quantity.

    Parameters
    ----------
    value : sympy.Expr
        The value at the reference state.
    terms : mapping
        ``(name, order)`` (coordinate or signal and derivative order) -> its
        symbolic coefficient.

    Examples
    --------
    >>> import sympy
    >>> LinearMap(sympy.Integer(0), {("x", 0): sympy.Symbol("k")}).terms[("x", 0)]
    k
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
    model : Model
        The model derived.
    coordinates : tuple of str
        The generalized coordinates, in order.

    Examples
    --------
    >>> from resonant.model import loads
    >>> lin = linearize(loads('[parameters]\\nk = 4\\n[coordinates]\\nx = ""\\n'
    ...                       '[energy]\\nT = "x\\'^2/2"\\nU = "k*x^2/2"'))
    >>> lin.M, lin.K
    (Matrix([[1]]), Matrix([[k]]))
    """

    model: Model
    coordinates: tuple[str, ...]
    M: sympy.ImmutableMatrix
    C: sympy.ImmutableMatrix
    K: sympy.ImmutableMatrix
    excitation: Mapping[Var, sympy.ImmutableMatrix]
    residual: sympy.ImmutableMatrix
    outputs: Mapping[str, LinearMap] = field(default_factory=dict)


@dataclass(frozen=True)
class NumericLinearization:
    """The linearized equation of motion at one parameter point, as numbers.

    What :func:`linearize_numeric` gives: the same quantities as a
    :class:`Linearization` evaluated at the parameter values, without any
    symbolic expression.

    Attributes
    ----------
    coordinates : tuple of str
    M, C, K : ndarray
        (n, n) float arrays.
    excitation : mapping
        ``(signal, order) -> column`` (n,) float array, the nonzero columns only.
    outputs : mapping
        name -> (value, {variable: coefficient}).
    parameters : frozenset of str
        The parameters the numbers depend on (the others may change freely).
    """

    coordinates: tuple[str, ...]
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    excitation: Mapping[Var, np.ndarray]
    outputs: Mapping[str, tuple[float, Mapping[Var, float]]]
    parameters: frozenset[str]


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


#: in the numeric path, a quantity divided by (or the argument of a function at its
#: singular point) smaller than this is not trusted: its exact value may be zero, which
#: only the symbolic derivation can tell (it is then used instead)
SINGULAR_GUARD = 1e-10


class _Inexact(Exception):
    """The numeric path cannot decide exactly; the symbolic derivation must."""


class _JetOps:
    """Folds a parsed expression into its second-order jet.

    With ``values`` (name -> float for every parameter) the coefficients are numbers at
    that point (the float backend); without, symbols of the chosen algebra system.
    """

    def __init__(self, model: Model, cas: Backend | None = None,
                 deadline: Deadline = NO_DEADLINE,
                 values: Mapping[str, float] | None = None) -> None:
        self.model = model
        self.deadline = deadline
        self.numeric = values is not None
        self.used: set[str] = set()  # the parameters the jets read
        self.cas: Backend
        self.equilibrium: dict[str, Any]
        if values is not None:
            self.cas = FLOAT
            self.params = {name: Jet(float(values[name])) for name in model.parameters}
            self.equilibrium = {q: 0 for q in model.coordinates}
            for q, expression in model.equilibrium.items():
                self.used |= {name for name, _ in expression.names()}
                self.equilibrium[q] = float(numeric_value(expression, values))
        else:
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

    def to_sympy(self, value: Coefficient) -> sympy.Expr:
        return self.cas.to_sympy(value, self.converted)

    def name(self, name: str, primes: int) -> Jet:
        if name in self.coordinates:
            return Jet.variable((name, primes), self.equilibrium[name] if primes == 0 else 0)
        if name in self.model.signals:
            return Jet.variable((name, primes))
        if name in self.params:
            self.used.add(name)
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
        if not isinstance(value, _Terms):
            return value
        if len(value.jets) > 16:  # a long sum is costly too
            self.tick(every=1)
        return Jet.sum(value.jets, self.cas)

    def add(self, a: Jet | _Terms, b: Jet | _Terms) -> _Terms:
        # each fold value is used by exactly one parent, so a term list may grow in place
        terms = a if isinstance(a, _Terms) else _Terms([a])
        terms.jets.extend(b.jets if isinstance(b, _Terms) else [b])
        return terms

    def sub(self, a: Jet | _Terms, b: Jet | _Terms) -> _Terms:
        return self.add(a, -self.whole(b))

    def tick(self, every: int = 16) -> None:
        """The deadline, checked every few products (the costly operations)."""
        section, key = self.where
        self.deadline.every(every, f"while expanding '{key}'" if key else
                            "during the derivation", section, key)

    def mul(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        self.tick()
        return self.whole(a) * self.whole(b)

    def guard(self, value: Coefficient) -> None:
        """In the numeric path: a near-zero where an exact zero changes the result."""
        if self.numeric and abs(value) < SINGULAR_GUARD:
            raise _Inexact

    def div(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        b = self.whole(b)
        self.guard(b.const)
        return self.whole(a) / b

    def pow(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        a, b = self.whole(a), self.whole(b)
        if not b.is_constant():  # a^b = exp(b log a)
            self.guard(a.const)
            return (b * a.apply("log", self.cas)).apply("exp", self.cas)
        if self.numeric:
            exponent = b.const
            if a.is_constant():  # in floats: never a huge exact integer, never complex
                value = float(a.const) ** exponent
                if not isinstance(value, float):
                    raise _Inexact
                return Jet(value)
            if not isinstance(exponent, int) or exponent < 0:
                self.guard(a.const)
        return a ** b

    def neg(self, a: Jet | _Terms) -> Jet:
        return -self.whole(a)

    def call(self, func: str, args: list) -> Jet:
        self.tick()
        args = [self.whole(a) for a in args]
        if func == "atan2":
            if self.numeric and not (args[0].is_constant() and args[1].is_constant()):
                self.guard(math.hypot(args[0].const, args[1].const))
            return args[0].atan2(args[1], self.cas)
        if self.numeric and not args[0].is_constant():
            c = args[0].const
            singular = {"sqrt": c, "log": c, "asin": 1 - abs(c), "acos": 1 - abs(c),
                        "tan": math.cos(c)}
            if func in singular:
                self.guard(singular[func])
        return args[0].apply(func, self.cas)


class _SizedBackend(Backend):
    """Coefficients as :class:`~resonant.derivation.residual.Sized` numbers (value and
    the size of the terms that formed it), for :class:`_FirstOrderOps`."""

    def rational(self, numerator: int, denominator: int) -> Any:
        return Sized(numerator / denominator)

    @property
    def pi(self) -> Any:
        return Sized(math.pi)

    def add(self, terms: list[Any]) -> Any:
        return terms[0] if len(terms) == 1 else Sized(
            math.fsum(t.value for t in map(Sized.of, terms)),
            math.fsum(t.size for t in map(Sized.of, terms)))

    def value(self, func: str, x: Sized) -> tuple[Sized, Sized]:
        """(f(x), f'(x)) with their sizes (the slope times the size of the argument)."""
        f0 = MATH[func](x.value)
        f1, f2 = FLOAT.slopes(func, x.value, True)
        if not all(isinstance(v, float) and math.isfinite(v) for v in (f0, f1, f2)):
            raise _Inexact
        return (Sized(f0, abs(f0) + abs(f1) * x.size),
                Sized(f1, abs(f1) + abs(f2) * x.size))


_SIZED = _SizedBackend("sized", math, MATH, float)


class _FirstOrderOps(_JetOps):
    """The jets to first order only, with :class:`Sized` coefficients: the residual at
    the reference state and the size of the terms forming it, at a parameter point.

    Degree one is all the residual needs (it is the constant part of Lagrange's
    equations, formed by the linear parts of T, U, D and the forces), and costs
    O(N^2) where the full jets cost O(N^3).
    """

    def __init__(self, model: Model, values: Mapping[str, float], deadline: Deadline) -> None:
        super().__init__(model, deadline=deadline, values=values)
        self.cas = _SIZED
        self.params = {name: Jet(Sized(float(values[name]))) for name in model.parameters}
        self.equilibrium = {q: Sized(float(v)) for q, v in self.equilibrium.items()}

    @staticmethod
    def _linear(const: Sized | float, slope: Sized | float, jet: Jet) -> Jet:
        """const + slope * (jet - its constant)."""
        return Jet(const, {k: slope * v for k, v in jet.lin.items()})

    def mul(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        self.tick()
        a, b = self.whole(a), self.whole(b)
        lin = {k: v * b.const for k, v in a.lin.items()}
        for k, v in b.lin.items():
            lin[k] = lin[k] + a.const * v if k in lin else a.const * v
        return Jet(a.const * b.const, lin)

    def div(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        b = self.whole(b)
        self.guard(b.const)
        return self.mul(a, self._linear(1 / b.const, -1 / (b.const * b.const), b))

    def pow(self, a: Jet | _Terms, b: Jet | _Terms) -> Jet:
        a, b = self.whole(a), self.whole(b)
        if not b.is_constant():  # a^b = exp(b log a)
            self.guard(a.const)
            return self.call("exp", [self.mul(b, self.call("log", [a]))])
        e = b.const
        if a.is_constant():
            return Jet(Sized.of(a.const) ** e)
        c = Sized.of(a.const)
        if float(e) == 1:
            return a
        if c.value == 0:
            if float(e) > 1:
                return Jet(Sized(0.0, 0.0))
            raise _Inexact
        return self._linear(c ** e, e * c ** (float(e) - 1), a)

    def call(self, func: str, args: list) -> Jet:
        self.tick()
        args = [self.whole(a) for a in args]
        if func == "atan2":
            y, x = args
            y0, x0 = Sized.of(y.const), Sized.of(x.const)
            r2 = x0 * x0 + y0 * y0
            self.guard(math.sqrt(r2.value))
            angle = math.atan2(y0.value, x0.value)
            const = Sized(angle, abs(angle) + (abs(x0.value) * y0.size + abs(y0.value) * x0.size)
                          / r2.value)
            lin = {k: v * x0 / r2 for k, v in y.lin.items()}
            for k, v in x.lin.items():
                term = -(v * y0) / r2
                lin[k] = lin[k] + term if k in lin else term
            return Jet(const, lin)
        x = args[0]
        c = Sized.of(x.const)
        if not x.is_constant():
            singular = {"sqrt": c.value, "log": c.value, "asin": 1 - abs(c.value),
                        "acos": 1 - abs(c.value), "tan": math.cos(c.value)}
            if func in singular:
                self.guard(singular[func])
        f0, f1 = _SIZED.value(func, c)
        return self._linear(f0, f1, x)


def _residual_is_zero(model: Model, values: Mapping[str, float], deadline: Deadline
                      ) -> bool | None:
    """Whether the residual at the reference state is zero at ``values``, judged against
    the size of its terms (see :class:`_FirstOrderOps`); None when the numbers cannot tell.
    """
    ops = _FirstOrderOps(model, values, deadline)
    try:
        equations = _equations(model, ops)
        return all(Sized.of(eq.const).is_zero() for eq in equations)
    except DeadlineExceeded:
        raise
    except (ModelError, _Inexact, ArithmeticError, ValueError, TypeError, RecursionError):
        return None


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
        M, C, K, the excitation and the outputs at the reference state.

    Raises
    ------
    ModelError
        If an expression cannot be expanded at the reference state, an energy
        depends on accelerations, the reference state is not an equilibrium
        (the message gives the residual per coordinate and, where one is found
        nearby, the equilibrium to put in ``[equilibrium]``), the derivation
        overflows, nests too deeply or exceeds the deadline.

    Examples
    --------
    >>> from resonant.model import loads
    >>> lin = linearize(loads('[parameters]\\nm = 2\\nk = 8\\n[coordinates]\\nx = ""\\n'
    ...                       '[energy]\\nT = "m*x\\'^2/2"\\nU = "k*x^2/2"'))
    >>> lin.coordinates, lin.K
    (('x',), Matrix([[k]]))
    """
    return linearize_raw(model, cas, deadline).linearization()


def linearize_raw(model: Model, cas: str | None = None, deadline: Deadline = NO_DEADLINE
                  ) -> RawLinearization:
    """:func:`linearize` without the conversion to sympy (see :class:`RawLinearization`).

    Parameters
    ----------
    model : Model
    cas : {"sympy", "symengine"}, optional
    deadline : Deadline, optional

    Returns
    -------
    RawLinearization

    Raises
    ------
    ModelError
        As :func:`linearize`.
    """
    ops = _JetOps(model, backend(cas) if cas else None, deadline)
    try:
        return _raw(model, ops)
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


def linearize_numeric(model: Model, values: Mapping[str, float],
                      deadline: Deadline = NO_DEADLINE, check_equilibrium: bool = True
                      ) -> NumericLinearization | None:
    """The linearized equation of motion at one parameter point, without symbols.

    The same jets and Lagrange's equations as :func:`linearize`, with every
    coefficient a float at ``values`` (see :class:`~resonant.derivation.jet.FloatBackend`):
    a 100-coordinate model in a fraction of a second.  Whenever the numbers
    cannot stand in for the exact derivation -- an error in the model (whose
    message the symbolic derivation gives), a division by or a function at a
    quantity within :data:`SINGULAR_GUARD` of zero, a residual at the
    reference state that is not exactly zero, a number that is not finite --
    the answer is None and the caller uses :func:`linearize`.

    Parameters
    ----------
    model : Model
        A validated model with ``[energy]``.
    values : mapping
        name -> float for every parameter.
    deadline : Deadline, optional
        Checked between the operations of the derivation (its timeout is raised).
    check_equilibrium : bool, optional
        Require the residual at the reference state to be zero (the check of
        :func:`linearize` at the model's own values).

    Returns
    -------
    NumericLinearization or None
    """
    ops = _JetOps(model, deadline=deadline, values=values)
    try:
        equations = _equations(model, ops)
        n = len(model.coordinates)
        index = {q: i for i, q in enumerate(model.coordinates)}
        mats = {order: np.zeros((n, n)) for order in (0, 1, 2)}
        excitation: dict[Var, np.ndarray] = {}
        if check_equilibrium and any(eq.const != 0 for eq in equations) and \
                not _residual_is_zero(model, values, ops.deadline):
            return None  # the symbolic check decides, and says why
        for k, eq in enumerate(equations):
            for (name, order), coef in eq.lin.items():
                if name in index:
                    if order > 2:
                        return None
                    mats[order][k, index[name]] += coef
                else:
                    excitation.setdefault((name, order), np.zeros(n))[k] -= coef
        outputs = {}
        for name, expression in model.outputs.items():
            jet = ops.jet(expression, "outputs", name)
            outputs[name] = (float(jet.const),
                             MappingProxyType({v: float(c) for v, c in jet.lin.items()}))
    except DeadlineExceeded:
        raise
    except (ModelError, _Inexact, ArithmeticError, ValueError, TypeError, RecursionError):
        return None
    numbers = [*mats.values(), *excitation.values(),
               np.array([v for value, terms in outputs.values() for v in (value, *terms.values())])]
    if not all(np.all(np.isfinite(a)) for a in numbers):
        return None
    return NumericLinearization(
        coordinates=model.coordinates, M=mats[2], C=mats[1], K=mats[0],
        excitation=MappingProxyType({v: c for v, c in sorted(excitation.items())
                                     if np.any(c != 0)}),
        outputs=MappingProxyType(outputs), parameters=frozenset(ops.used))


def _equations(model: Model, ops: _JetOps) -> list[Jet]:
    """Lagrange's equations (generalized forces included) as jets, one per coordinate."""
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
    rates, positions = {(q, 1) for q in coords}, {(q, 0) for q in coords}
    dT, dD, dU = T.partials(rates | positions), D.partials(rates), U.partials(positions)
    equations = [dT[(q, 1)].dt() - dT[(q, 0)] + dD[(q, 1)] + dU[(q, 0)] for q in coords]
    for k, force in enumerate(_generalized_forces(model, ops)):
        equations[k] = equations[k] - force
    return equations


@dataclass(frozen=True, eq=False)
class RawLinearization:
    """The derivation's result in the coefficients of its algebra system (symengine for
    a large model), before any conversion to sympy.

    What :func:`linearize_raw` gives: numbers can be compiled from it directly, and
    :meth:`linearization` converts it to the :class:`Linearization` that
    :func:`linearize` returns (identical to it).

    Attributes
    ----------
    entries : mapping
        ``order -> {(row, column): coefficient}``: order 2 is M, 1 is C, 0 is K.
    excitation : mapping
        ``(signal, order) -> {row: coefficient}`` of the equations (Q is minus it); the
        signal derivatives with a nonzero coefficient only.
    residual : tuple
        The generalized forces at the reference state.
    outputs : mapping
        name -> (value, {variable: coefficient}).
    """

    model: Model
    ops: _JetOps
    entries: Mapping[int, Mapping[tuple[int, int], Any]]
    excitation: Mapping[Var, Mapping[int, Any]]
    residual: tuple[Any, ...]
    outputs: Mapping[str, tuple[Any, Mapping[Var, Any]]]

    def linearization(self) -> Linearization:
        """The symbolic result in sympy (each coefficient converted once)."""
        to_sympy = self.ops.to_sympy
        n = len(self.model.coordinates)
        mats = {order: sympy.zeros(n, n) for order in (0, 1, 2)}
        for order, entries in self.entries.items():
            for (k, j), coef in entries.items():
                mats[order][k, j] += to_sympy(coef)
        excitation: dict[Var, sympy.Matrix] = {}
        for var, rows in self.excitation.items():
            column = excitation[var] = sympy.zeros(n, 1)
            for k, coef in rows.items():
                column[k] -= to_sympy(coef)
        outputs = {name: LinearMap(to_sympy(value), MappingProxyType(
            {v: to_sympy(c) for v, c in terms.items()}))
            for name, (value, terms) in self.outputs.items()}
        return Linearization(
            model=self.model, coordinates=self.model.coordinates,
            M=clean(mats[2]), C=clean(mats[1]), K=clean(mats[0]),
            excitation=MappingProxyType({v: sympy.ImmutableMatrix(clean(c))
                                         for v, c in sorted(excitation.items())
                                         if any(e != 0 for e in c)}),
            residual=sympy.ImmutableMatrix([to_sympy(r) for r in self.residual]),
            outputs=MappingProxyType(outputs))


def _raw(model: Model, ops: _JetOps) -> RawLinearization:
    coords = model.coordinates
    equations = _equations(model, ops)
    index = {q: i for i, q in enumerate(coords)}
    entries: dict[int, dict[tuple[int, int], Any]] = {0: {}, 1: {}, 2: {}}
    excitation: dict[Var, dict[int, Any]] = {}
    for k, eq in enumerate(equations):
        for (name, order), coef in eq.lin.items():
            if name in index:
                if order > 2:
                    raise ModelError(Problem(
                        f"the equations contain {name}{chr(39) * order}: forces may depend on "
                        "coordinates and their first two derivatives only", model.source,
                        "force"))
                entries[order][(k, index[name])] = coef
            else:
                excitation.setdefault((name, order), {})[k] = coef
    residual = tuple(eq.const for eq in equations)
    ops.where = ("equilibrium", "")
    ops.deadline.check("while checking that the reference state is an equilibrium",
                       "equilibrium")
    _check_equilibrium(model, sympy.ImmutableMatrix([ops.to_sympy(r) for r in residual]))
    outputs = {}
    for name, expression in model.outputs.items():
        jet = ops.jet(expression, "outputs", name)
        outputs[name] = (jet.const, dict(jet.lin))
    return RawLinearization(model, ops, MappingProxyType(entries), MappingProxyType(excitation),
                            residual, MappingProxyType(outputs))


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


__all__ = ["Linearization", "LinearMap", "NumericLinearization", "RawLinearization",
           "linearize", "linearize_numeric", "linearize_raw", "SINGULAR_GUARD", "signal_symbol",
           "signal_derivatives", "clean"]
