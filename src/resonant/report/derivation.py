"""The derivation steps of the linearized equation of motion, source by source.

The report explains where each entry of M, C, K and Q(t) comes from, as in
the reference exercise (Eqs. (2)-(6), (15)-(31)).  Everything here is
computed from the *full* nonlinear expressions of T, D, U and of the
generalized forces (:class:`resonant.derivation.nonlinear.SympyOps`), independently of
the jet arithmetic of :mod:`resonant.derivation.lagrange`, and then checked against the
:class:`~resonant.system.LinearEOM`: the report can only show numbers that
the solver also uses.

Examples
--------
>>> from resonant.api import loads
>>> model = loads('''
... [parameters]
... m = 1
... k = 4
... [coordinates]
... x = "displacement"
... [signals]
... y = "sin(2*t)"
... [energy]
... T = "m*x'^2/2"
... U = "k*(x - y)^2/2"
... ''')
>>> d = derive(model.linearize())
>>> d.first["U"], d.parts["U"].K, d.parts["U"].Q
([k*x - k*y], Matrix([[k]]), {('y', 0): Matrix([[k]])})
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import sympy

from ..derivation.jet import Var
from ..derivation.lagrange import clean as _clean
from ..derivation.nonlinear import SympyOps as _SympyOps
from ..derivation.nonlinear import derivative_symbol
from ..model import Model, symbol

if TYPE_CHECKING:  # pragma: no cover
    from ..system.latex import SymbolicEquations

ENERGIES = ("T", "D", "U")


@dataclass(frozen=True)
class SourceTerms:
    """One source's first-order terms on the left of Lagrange's equations.

    The source contributes ``M q'' + C q' + K q - Q`` where
    ``Q = sum of column * signal derivative`` (the part that goes to the right).
    """

    M: sympy.ImmutableMatrix
    C: sympy.ImmutableMatrix
    K: sympy.ImmutableMatrix
    Q: dict[Var, sympy.ImmutableMatrix]

    @property
    def signals(self) -> list[str]:
        return sorted({name for name, _ in self.Q})

    def Q_vector(self, n: int) -> sympy.ImmutableMatrix:
        """Q written with signal symbols (``r``, ``r'``, ...)."""
        total = sympy.zeros(n, 1)
        for (name, order), column in self.Q.items():
            total += column * derivative_symbol(name, order)
        return sympy.ImmutableMatrix(total)


@dataclass(frozen=True)
class ForceTerms:
    """A ``[[force]]``: its power and generalized forces, in full and linearized."""

    name: str
    vector: tuple[sympy.Expr, ...]
    velocity: tuple[sympy.Expr, ...]
    power: sympy.Expr | None
    generalized: tuple[sympy.Expr, ...]
    #: contribution to the left side (the negated generalized force, linearized)
    part: SourceTerms
    given: bool = False


@dataclass(frozen=True)
class Derivation:
    """Full expressions, their derivatives and linear parts for one energy model."""

    model: Model
    q: tuple[sympy.Symbol, ...]
    qd: tuple[sympy.Symbol, ...]
    energies: dict[str, sympy.Expr]
    first: dict[str, list[sympy.Expr]]
    second: dict[str, dict[tuple[int, int], tuple[sympy.Expr, sympy.Expr]]]
    lagrange: dict[str, list[sympy.Expr]]
    parts: dict[str, SourceTerms]
    forces: tuple[ForceTerms, ...]
    reference: dict[sympy.Symbol, sympy.Expr]
    symbols: set[sympy.Symbol] = field(default_factory=set)

    def time_dependent(self, key: str) -> bool:
        """True when the energy ``key`` depends explicitly on time (through signals)."""
        signals = set(self.model.signals)
        expr = self.energies.get(key, sympy.Integer(0))
        return any(s.name.rstrip("'") in signals for s in expr.free_symbols
                   if isinstance(s, sympy.Symbol))

    @property
    def at_zero(self) -> bool:
        return all(self.reference[s] == 0 for s in self.q)


def _tidy(e: sympy.Expr) -> sympy.Expr:
    """A compact form for display: expanded when that is not longer."""
    if e == 0 or e.is_Atom or sympy.count_ops(e) > 80:
        return e
    expanded = sympy.expand(e)
    return expanded if sympy.count_ops(expanded) <= sympy.count_ops(e) + 2 else e


def derive(eom: SymbolicEquations) -> Derivation:
    """Differentiate T, D, U and the forces of ``eom.model`` and check against ``eom``.

    Raises
    ------
    RuntimeError
        If the derivation disagrees with the linearized equation of motion
        (a bug in resonant, never expected).
    """
    model = eom.model
    ops = _SympyOps(model)
    coords = model.coordinates
    n = len(coords)
    q = tuple(ops.dvar(c, 0) for c in coords)
    qd = tuple(ops.dvar(c, 1) for c in coords)
    energies = {key: ops.expr(model.energy[key]) for key in ENERGIES if key in model.energy}
    zero = sympy.Integer(0)
    T, D, U = (energies.get(key, zero) for key in ENERGIES)
    first = {"T": [_tidy(sympy.diff(T, v)) for v in qd],
             "D": [_tidy(sympy.diff(D, v)) for v in qd],
             "U": [_tidy(sympy.diff(U, v)) for v in q]}
    lagrange = {"T": [ops.dt(sympy.diff(T, qd[k])) - sympy.diff(T, q[k]) for k in range(n)],
                "D": [sympy.diff(D, v) for v in qd],
                "U": [sympy.diff(U, v) for v in q]}
    raw_forces = tuple(_force_terms(model, ops, force, q) for force in model.forces)
    reference = _reference(model, ops)
    second = {}
    for key, variables in (("T", qd), ("D", qd), ("U", q)):
        entries = {}
        for i in range(n):
            for j in range(i, n):
                full = sympy.diff(first[key][i], variables[j])
                if full != 0:
                    entries[(i, j)] = (_tidy(full), _clean(sympy.Matrix([full.subs(reference)]))[0])
        second[key] = entries
    parts = {key: _linear_part(lagrange[key], ops, reference, coords, sign=1)
             for key in ENERGIES}
    forces = tuple(
        ForceTerms(f.name, f.vector, f.velocity, f.power, f.generalized,
                   _linear_part(list(f.generalized), ops, reference, coords, sign=-1), f.given)
        for f in raw_forces)
    derivation = Derivation(model, q, qd, energies, first, second, lagrange, parts, forces,
                            reference, set(ops.registry))
    _check(derivation, eom)
    return derivation


def _reference(model: Model, ops: _SympyOps) -> dict[sympy.Symbol, sympy.Expr]:
    """The reference state: coordinates at the equilibrium, every rate and signal zero."""
    reference: dict[sympy.Symbol, sympy.Expr] = {}
    for c in model.coordinates:
        value = (model.equilibrium[c].to_sympy(lambda n, p: symbol(n) if p == 0 else 0)
                 if c in model.equilibrium else sympy.Integer(0))
        reference[ops.dvar(c, 0)] = value
        for order in (1, 2, 3):
            reference[ops.dvar(c, order)] = sympy.Integer(0)
    for s, (name, _order) in ops.registry.items():
        if name in model.signals:
            reference[s] = sympy.Integer(0)
    return reference


@dataclass(frozen=True)
class _RawForce:
    name: str
    vector: tuple[sympy.Expr, ...]
    velocity: tuple[sympy.Expr, ...]
    power: sympy.Expr | None
    generalized: tuple[sympy.Expr, ...]
    given: bool


def _force_terms(model: Model, ops: _SympyOps, force, q) -> _RawForce:
    coords = model.coordinates
    if force.generalized:
        generalized = tuple(ops.expr(force.generalized[c]) if c in force.generalized
                            else sympy.Integer(0) for c in coords)
        return _RawForce(force.name, (), (), None, generalized, True)
    vector = tuple(ops.expr(v) for v in force.vector)
    point = [ops.expr(p) for p in force.point]
    velocity = tuple(_tidy(ops.dt(p)) for p in point)
    power = _tidy(sum((f * v for f, v in zip(vector, velocity)), sympy.Integer(0)))
    generalized = tuple(_tidy(sum((f * sympy.diff(p, qk) for f, p in zip(vector, point)),
                                  sympy.Integer(0))) for qk in q)
    return _RawForce(force.name, vector, velocity, power, generalized, False)


def _linear_part(expressions: list[sympy.Expr], ops: _SympyOps,
                 reference: dict[sympy.Symbol, sympy.Expr], coords: tuple[str, ...],
                 sign: int) -> SourceTerms:
    """First-order Taylor coefficients of ``sign * expressions`` at the reference state."""
    n = len(coords)
    index = {c: i for i, c in enumerate(coords)}
    mats = {order: sympy.zeros(n, n) for order in (0, 1, 2)}
    columns: dict[Var, sympy.Matrix] = {}
    for k, expr in enumerate(expressions):
        for s in expr.free_symbols:
            if s not in ops.registry:
                continue
            name, order = ops.registry[s]
            coef = sign * sympy.diff(expr, s).subs(reference)
            if coef == 0:
                continue
            if name in index:
                mats[min(order, 2)][k, index[name]] += coef
            else:
                columns.setdefault((name, order), sympy.zeros(n, 1))[k] -= coef
    return SourceTerms(_clean(mats[2]), _clean(mats[1]), _clean(mats[0]),
                      {v: _clean(c) for v, c in sorted(columns.items())
                       if any(e != 0 for e in c)})


# -- agreement with the linearized equation of motion ---------------------------------

def _equal(a: sympy.Expr, b: sympy.Expr, model: Model) -> bool:
    difference = sympy.expand(a - b)
    if difference == 0:
        return True
    params = [symbol(n) for n in model.parameters]
    exact = {symbol(n): v for n, v in model.exact_values.items()}
    rng = random.Random(4)
    trials = [exact, {p: exact[p] * sympy.Rational(rng.randint(110, 190), 100) for p in params}]
    for values in trials:
        number = complex(difference.evalf(30, subs=values))
        scale = max(abs(complex(a.evalf(30, subs=values))),
                    abs(complex(b.evalf(30, subs=values))), 1e-300)
        if number != number or abs(number) == float("inf"):
            continue
        if abs(number) > 1e-9 * scale:
            return False
    return True


def _check(d: Derivation, eom: SymbolicEquations) -> None:
    n = len(eom.coordinates)
    parts = [*d.parts.values(), *(f.part for f in d.forces)]
    totals = {label: sum((getattr(p, label) for p in parts), sympy.zeros(n, n))
              for label in ("M", "C", "K")}
    columns: dict[Var, sympy.Matrix] = {}
    for p in parts:
        for var, column in p.Q.items():
            columns[var] = columns.get(var, sympy.zeros(n, 1)) + column
    problems = []
    for label in ("M", "C", "K"):
        expected = getattr(eom, label)
        for i in range(n):
            for j in range(n):
                if not _equal(totals[label][i, j], expected[i, j], d.model):
                    problems.append(f"{label}[{i + 1},{j + 1}]: {totals[label][i, j]} != "
                                    f"{expected[i, j]}")
    for var in set(columns) | set(eom.excitation):
        got = columns.get(var, sympy.zeros(n, 1))
        expected = eom.excitation.get(var, sympy.zeros(n, 1))
        for k in range(n):
            if not _equal(got[k], expected[k], d.model):
                problems.append(f"Q column of {var}: {got[k]} != {expected[k]}")
    for (i, j), (_, value) in d.second["T"].items():
        if not _equal(value, eom.M[i, j], d.model):
            problems.append(f"m_{i + 1}{j + 1} = {value} != {eom.M[i, j]}")
    if problems:
        raise RuntimeError("the report's derivation disagrees with the linearized equation "
                           "of motion: " + "; ".join(problems[:5]))


__all__ = ["Derivation", "SourceTerms", "ForceTerms", "derive"]
