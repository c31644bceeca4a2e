"""The full (not linearized) Lagrange equations of an energy model.

Used to find an equilibrium near a reference state that is not one, and by
the nonlinear time simulation.  Coordinates and their derivatives are plain
symbols ``x``, ``x'``, ``x''``; signals are symbols ``r``, ``r'``, ... that a
caller replaces by the signal functions.  Explicit time enters only through
signals, so the total time derivative is a sum over these symbols.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import sympy

from ..expressions import Expression, compilable
from ..expressions.functions import SYMPY as SYMPY_FUNCTIONS
from ..model import Model, symbol


def derivative_symbol(name: str, order: int) -> sympy.Symbol:
    """The symbol of the order-th time derivative of a coordinate or signal.

    Parameters
    ----------
    name : str
        The coordinate or signal.
    order : int
        The order of the derivative (0: the quantity itself).

    Returns
    -------
    sympy.Symbol
        ``x``, ``x'``, ``x''`` ...

    Examples
    --------
    >>> derivative_symbol("x", 2)
    x''
    """
    return symbol(name + "'" * order)


class SympyOps:
    """Folds a parsed expression into a full sympy expression."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.coordinates = set(model.coordinates)
        self.signals = set(model.signals)
        self.definitions: dict[tuple[str, int], sympy.Expr] = {}
        self.registry: dict[sympy.Symbol, tuple[str, int]] = {}

    def expr(self, expression: Expression) -> sympy.Expr:
        return expression.fold(self)

    def num(self, text: str) -> sympy.Expr:
        return sympy.Rational(text)

    def pi(self) -> sympy.Expr:
        return sympy.pi

    def dvar(self, name: str, order: int) -> sympy.Symbol:
        s = derivative_symbol(name, order)
        self.registry[s] = (name, order)
        return s

    def name(self, name: str, primes: int) -> sympy.Expr:
        if name in self.coordinates or name in self.signals:
            return self.dvar(name, primes)
        if name in self.model.parameters:
            return symbol(name) if primes == 0 else sympy.Integer(0)
        key = (name, primes)
        if key not in self.definitions:
            self.definitions[key] = (self.expr(self.model.definitions[name]) if primes == 0
                                     else self.dt(self.name(name, primes - 1)))
        return self.definitions[key]

    def dt(self, e: sympy.Expr) -> sympy.Expr:
        """Total time derivative (explicit time only through the signals)."""
        out = sympy.Integer(0)
        for s in list(e.free_symbols):
            if s in self.registry:
                name, order = self.registry[s]
                out += sympy.diff(e, s) * self.dvar(name, order + 1)
        return out

    add = staticmethod(lambda a, b: a + b)
    sub = staticmethod(lambda a, b: a - b)
    mul = staticmethod(lambda a, b: a * b)
    div = staticmethod(lambda a, b: a / b)
    pow = staticmethod(lambda a, b: a ** b)
    neg = staticmethod(lambda a: -a)

    def call(self, func: str, args: list[sympy.Expr]) -> sympy.Expr:
        return SYMPY_FUNCTIONS[func](*args)


@dataclass(frozen=True)
class NonlinearEquations:
    """E_k = d/dt dT/dq'_k - dT/dq_k + dD/dq'_k + dU/dq_k - Q_k = 0 in full.

    ``mass`` is the matrix of the accelerations and ``rest`` the remainder, so
    that the equations read ``mass * q'' + rest = 0``; ``dissipation`` is the
    part ``dD/dq'_k`` of ``rest`` (zero for a model without D), so that the
    undamped equations are ``mass * q'' + rest - dissipation = 0``.

    Parameters
    ----------
    model : Model
        The model the equations are of.
    mass : sympy.Matrix
        The matrix of the accelerations.
    rest : sympy.Matrix
        Everything else.
    ops : SympyOps
        The fold that built them (its registry of derivative symbols).
    dissipation : sympy.Matrix, optional
        The part dD/dq' of ``rest``.

    Examples
    --------
    See :func:`nonlinear_equations`.
    """

    model: Model
    mass: sympy.Matrix
    rest: sympy.Matrix
    ops: SympyOps
    dissipation: sympy.Matrix | None = None

    @property
    def q(self) -> list[sympy.Symbol]:
        return [derivative_symbol(c, 0) for c in self.model.coordinates]

    @property
    def qd(self) -> list[sympy.Symbol]:
        return [derivative_symbol(c, 1) for c in self.model.coordinates]

    @property
    def qdd(self) -> list[sympy.Symbol]:
        return [derivative_symbol(c, 2) for c in self.model.coordinates]

    @cached_property
    def signal_symbols(self) -> dict[sympy.Symbol, tuple[str, int]]:
        free = self.mass.free_symbols | self.rest.free_symbols
        return {s: v for s, v in self.ops.registry.items()
                if s in free and v[0] in self.model.signals}


def nonlinear_equations(model: Model) -> NonlinearEquations:
    """Form the full Lagrange equations of an energy model.

    Parameters
    ----------
    model : Model
        A model given by its energies.

    Returns
    -------
    NonlinearEquations
        ``mass * q'' + rest = 0`` in full.

    Examples
    --------
    >>> from resonant.model import loads
    >>> eq = nonlinear_equations(loads('''
    ... [parameters]
    ... m = 1
    ... l = 2
    ... g = 9.81
    ... [coordinates]
    ... th = "angle"
    ... [energy]
    ... T = "m*l^2*th'^2/2"
    ... U = "-m*g*l*cos(th)"
    ... '''))
    >>> eq.mass, eq.rest
    (Matrix([[l**2*m]]), Matrix([[g*l*m*sin(th)]]))
    """
    ops = SympyOps(model)
    zero = sympy.Integer(0)
    T = ops.expr(model.energy["T"]) if "T" in model.energy else zero
    U = ops.expr(model.energy["U"]) if "U" in model.energy else zero
    D = ops.expr(model.energy["D"]) if "D" in model.energy else zero
    coords = model.coordinates
    q = [ops.dvar(c, 0) for c in coords]
    qd = [ops.dvar(c, 1) for c in coords]
    qdd = [ops.dvar(c, 2) for c in coords]
    forces = [zero] * len(coords)
    for force in model.forces:
        if force.generalized:
            for k, c in enumerate(coords):
                if c in force.generalized:
                    forces[k] += ops.expr(force.generalized[c])
            continue
        vector = [ops.expr(v) for v in force.vector]
        point = [ops.expr(p) for p in force.point]
        for k in range(len(coords)):
            forces[k] += sum((f * sympy.diff(p, q[k]) for f, p in zip(vector, point)), zero)
    equations = []
    dissipation = [sympy.diff(D, qd[k]) for k in range(len(coords))]
    for k in range(len(coords)):
        equations.append(ops.dt(sympy.diff(T, qd[k])) - sympy.diff(T, q[k])
                         + dissipation[k] + sympy.diff(U, q[k]) - forces[k])
    E = sympy.Matrix(equations)
    mass = E.jacobian(qdd)
    rest = E.subs({a: 0 for a in qdd})
    return NonlinearEquations(model, mass, rest, ops, sympy.Matrix(dissipation))


def linearized_matrices(eq: NonlinearEquations) -> tuple[sympy.Matrix, sympy.Matrix,
                                                         sympy.Matrix]:
    """M, C, K as the Jacobians of the full equations at the reference state.

    The derivatives of ``mass * q'' + rest`` with respect to q'', q' and q at
    the reference state (``[equilibrium]``, velocities and signals zero): an
    independent route to the matrices :func:`resonant.derivation.lagrange.linearize`
    derives from second-order jets, used to cross-check the two.

    Examples
    --------
    >>> from resonant.model import loads
    >>> eq = nonlinear_equations(loads('''
    ... [parameters]
    ... m = 1
    ... l = 2
    ... g = 9.81
    ... [coordinates]
    ... th = "angle"
    ... [energy]
    ... T = "m*l^2*th'^2/2"
    ... U = "-m*g*l*cos(th)"
    ... '''))
    >>> linearized_matrices(eq)
    (Matrix([[l**2*m]]), Matrix([[0]]), Matrix([[g*l*m]]))
    """
    model = eq.model
    equations = eq.mass * sympy.Matrix(eq.qdd) + eq.rest
    at_rest: dict[sympy.Symbol, sympy.Expr] = {}
    for s, (name, order) in eq.ops.registry.items():
        if name in model.signals or order > 0:
            at_rest[s] = sympy.Integer(0)
    for q, name in zip(eq.q, model.coordinates):
        at_rest[q] = (model.equilibrium[name].to_sympy(
            lambda n, p: symbol(n) if p == 0 else sympy.Integer(0))
            if name in model.equilibrium else sympy.Integer(0))

    def jacobian(variables: list[sympy.Symbol]) -> sympy.Matrix:
        return equations.jacobian(variables).xreplace(at_rest).applyfunc(sympy.simplify)

    return jacobian(eq.qdd), jacobian(eq.qd), jacobian(eq.q)


def find_equilibrium(model: Model) -> dict[str, float] | None:
    """An equilibrium near the reference state with all signals zero, or None.

    Parameters
    ----------
    model : Model
        A model given by its energies.

    Returns
    -------
    dict or None
        coordinate -> value of an equilibrium found by Newton's method from the
        reference state, or None where none is found.

    Examples
    --------
    >>> from resonant.model import loads
    >>> find_equilibrium(loads('[parameters]\\nk = 4\\n[coordinates]\\nx = ""\\n'
    ...     '[equilibrium]\\nx = 0.1\\n[energy]\\nT = "x\\'^2/2"\\nU = "k*(x - 1)^2/2"'))
    {'x': 1.0}
    """
    import scipy.optimize

    eq = nonlinear_equations(model)
    rest_state = {s: 0 for s in eq.ops.registry if eq.ops.registry[s][1] > 0
                  or eq.ops.registry[s][0] in model.signals}
    params = {symbol(n): v for n, v in model.parameter_values.items()}
    static = eq.rest.subs(rest_state).subs(params)
    if any(e.has(sympy.zoo, sympy.oo, sympy.nan) for e in static):
        return None  # not finite at the reference state (log(0), 1/0 ...): no Newton start
    fn = sympy.lambdify([eq.q], [compilable(e) for e in static], modules="numpy")
    start = np.array([float(model.equilibrium[c].to_sympy(
        lambda n, p: sympy.Float(model.parameter_values[n])))
        if c in model.equilibrium else 0.0 for c in model.coordinates])
    with np.errstate(all="ignore"):
        result = scipy.optimize.root(lambda x: np.asarray(fn(x), dtype=float), start)
    if not result.success or not np.all(np.isfinite(result.x)):
        return None
    return {c: float(v) for c, v in zip(model.coordinates, result.x)}


__all__ = ["NonlinearEquations", "nonlinear_equations", "find_equilibrium", "derivative_symbol",
           "linearized_matrices"]
