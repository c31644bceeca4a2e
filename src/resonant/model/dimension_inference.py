"""The dimensions of bare numbers, inferred from how they are used.

In a model with units a parameter given as a bare number (``z = 0.7``) is SI of an
unknown dimension.  Its uses often fix it, as a type checker infers a type: D must be a
power, so in ``D = "c*x'^2/2"`` the damping ``c`` is N·s/m, so in ``c = "2*z*sqrt(k*m)"``
the ratio ``z`` is dimensionless.  Every expression of the model's physics — parameter
definitions, signals, definitions, the energies (T and U energies, D a power), the forces
(a force times its displacement is a work), the reference state — is read as a monomial:
a known dimension times powers of the unknown ones.  Each constraint (the terms of a sum
alike, a function's argument dimensionless, an energy an energy ...) is a linear equation
in the exponents of the unknowns' dimensions, one system per SI base unit, solved exactly
with fractions.  An unknown that the equations pin down gets its dimension; the others
stay undetermined (and are named in the model's note).  Outputs are not evidence: they
are checked with the result, so that an output adding N to N·s is an error.

Examples
--------
>>> from resonant.expressions import parse
>>> from resonant.model.units import Dimension
>>> newton = Dimension.of(kg=1, m=1, s=-2)
>>> found = infer_dimensions({"k": newton / Dimension.of(m=1), "x": Dimension.of(m=1)},
...                          ["z"], [("parameters", "c", parse("2*z*k"))],
...                          [(parse("c*x'^2/2"), newton * Dimension.of(m=1, s=-1))])
>>> found["z"].text()  # c = 2 z k is N*s/m, so z is in s
's'
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

from ..expressions import Expression
from ..expressions.parser import BinOp, Call, Name, Neg, Node, Num
from .units import DIMENSIONLESS, Dimension

TIME = Dimension.of(s=1)


@dataclass(frozen=True)
class Monomial:
    """A known dimension times powers of unknown ones: ``known * prod(u_i ** e_i)``."""

    known: Dimension
    unknown: Mapping[str, Fraction] = field(default_factory=dict)

    def __mul__(self, other: Monomial) -> Monomial:
        powers = dict(self.unknown)
        for name, e in other.unknown.items():
            powers[name] = powers.get(name, Fraction(0)) + e
        return Monomial(self.known * other.known, {n: e for n, e in powers.items() if e})

    def __pow__(self, power: Fraction) -> Monomial:
        return Monomial(self.known ** power, {n: e * power for n, e in self.unknown.items()
                                              if e * power})

    def inverse(self) -> Monomial:
        return self ** Fraction(-1)


ONE = Monomial(DIMENSIONLESS)


class _Opaque(Exception):
    """A part of an expression whose dimension cannot be written as a monomial."""


def _constant(node: Node) -> Fraction | None:
    if isinstance(node, Num):
        return Fraction(node.value)
    if isinstance(node, Neg):
        inner = _constant(node.operand)
        return None if inner is None else -inner
    if isinstance(node, BinOp) and node.op in "*/":
        left, right = _constant(node.left), _constant(node.right)
        if left is None or right is None or (node.op == "/" and right == 0):
            return None
        return left * right if node.op == "*" else left / right
    return None


class _Equations:
    """Monomials of expressions, and the equations their uses impose."""

    def __init__(self, known: Mapping[str, Dimension | None], unknowns: Iterable[str]) -> None:
        self.names: dict[str, Monomial | None] = {
            name: Monomial(dim) if dim is not None else None for name, dim in known.items()}
        for name in unknowns:
            self.names[name] = Monomial(DIMENSIONLESS, {name: Fraction(1)})
        self.equations: list[tuple[Monomial, Dimension]] = []

    def equal(self, monomial: Monomial, target: Dimension) -> None:
        if monomial.unknown:
            self.equations.append((monomial, target))

    def alike(self, a: Monomial, b: Monomial) -> None:
        self.equal(a * b.inverse(), DIMENSIONLESS)

    def of(self, node: Node) -> Monomial:
        if isinstance(node, Num):
            return ONE
        if isinstance(node, Name):
            return self._name(node)
        if isinstance(node, Neg):
            return self.of(node.operand)
        if isinstance(node, Call):
            return self._call(node)
        if node.op in "+-":
            terms = [self._try(term) for term in (node.left, node.right)
                     if _constant(term) != 0]  # a literal 0 fits any unit
            known = [t for t in terms if t is not None]
            for other in known[1:]:
                self.alike(known[0], other)
            if not known:
                raise _Opaque
            return known[0]
        if node.op in "*/":
            left, right = self.of(node.left), self.of(node.right)
            return left * (right if node.op == "*" else right.inverse())
        return self._power(node)

    def _try(self, node: Node) -> Monomial | None:
        try:
            return self.of(node)
        except _Opaque:
            return None

    def _name(self, node: Name) -> Monomial:
        if node.name == "pi":
            return ONE
        base = Monomial(TIME) if node.name == "t" else self.names.get(node.name)
        if base is None:
            raise _Opaque
        return base * Monomial(TIME ** -node.primes) if node.primes else base

    def _call(self, node: Call) -> Monomial:
        args = [self._try(a) for a in node.args]
        if node.func == "sqrt":
            if args[0] is None:
                raise _Opaque
            return args[0] ** Fraction(1, 2)
        if node.func == "abs":
            if args[0] is None:
                raise _Opaque
            return args[0]
        if node.func == "atan2":
            if args[0] is not None and args[1] is not None:
                self.alike(args[0], args[1])
            return ONE
        for arg in args:
            if arg is not None:
                self.equal(arg, DIMENSIONLESS)
        return ONE

    def _power(self, node: BinOp) -> Monomial:
        base, exponent = self._try(node.left), self._try(node.right)
        if exponent is not None:
            self.equal(exponent, DIMENSIONLESS)
        power = _constant(node.right)
        if base is None or power is None:
            if base is not None and power is None:
                self.equal(base, DIMENSIONLESS)  # x^y with y not a number: x is a ratio
            raise _Opaque
        return base ** power


def _components(equations: Sequence[tuple[Monomial, Dimension]]
                ) -> list[list[tuple[Monomial, Dimension]]]:
    """The equations grouped by the unknowns they link (connected components), so that uses
    contradicting each other leave open only the unknowns they involve."""
    parent: dict[str, str] = {}

    def root(name: str) -> str:
        while parent.setdefault(name, name) != name:
            name = parent[name]
        return name

    for monomial, _ in equations:
        first, *rest = monomial.unknown
        for name in rest:
            parent[root(name)] = root(first)
    groups: dict[str, list[tuple[Monomial, Dimension]]] = {}
    for equation in equations:
        groups.setdefault(root(next(iter(equation[0].unknown))), []).append(equation)
    return list(groups.values())


def _solve(equations: Sequence[tuple[Monomial, Dimension]], unknowns: Sequence[str]
           ) -> dict[str, Dimension | None]:
    """The unknowns the equations determine: Gauss-Jordan elimination with fractions on
    the exponent matrix, one right-hand side per SI base unit (one linked group of
    unknowns at a time)."""
    if len(_components(equations)) > 1:
        merged: dict[str, Dimension | None] = {}
        for group in _components(equations):
            merged.update(_solve(group, unknowns))
        return merged
    rows = [[m.unknown.get(u, Fraction(0)) for u in unknowns]
            + [Fraction(e) for e in (target / m.known).exponents]
            for m, target in equations]
    width = len(unknowns)
    pivots: list[int] = []
    r = 0
    for column in range(width):
        pivot = next((i for i in range(r, len(rows)) if rows[i][column] != 0), None)
        if pivot is None:
            continue
        rows[r], rows[pivot] = rows[pivot], rows[r]
        lead = rows[r][column]
        rows[r] = [v / lead for v in rows[r]]
        for i in range(len(rows)):
            if i != r and rows[i][column] != 0:
                factor = rows[i][column]
                rows[i] = [a - factor * b for a, b in zip(rows[i], rows[r])]
        pivots.append(column)
        r += 1
    if any(not any(row[:width]) and any(row[width:]) for row in rows):
        # contradictory uses: decide nothing of the unknowns they link (None: contradicted)
        return {u: None for m, _ in equations for u in m.unknown}
    found: dict[str, Dimension | None] = {}
    for i, column in enumerate(pivots):
        if not any(rows[i][c] for c in range(width) if c != column):
            found[unknowns[column]] = Dimension(tuple(_integral(v) for v in rows[i][width:]))
    return found


def _integral(value: Fraction) -> int | Fraction:
    return value.numerator if value.denominator == 1 else value


def infer_dimensions(known: Mapping[str, Dimension | None], unknowns: Sequence[str],
                     definitions: Sequence[tuple[str, str, Expression]],
                     constraints: Sequence[tuple[Expression, Dimension]]
                     ) -> dict[str, Dimension | None]:
    """The dimensions of ``unknowns`` that their uses determine.

    Parameters
    ----------
    known : mapping
        name -> its dimension, or None where it is unknown and not to be inferred.
    unknowns : sequence of str
        The bare-number parameters whose dimension is sought.
    definitions : sequence
        ``(section, name, expression)``: names defined by expressions (parameters,
        signals, definitions), in order.
    constraints : sequence
        ``(expression, dimension)`` it must have (an energy, a power, a work ...).

    Returns
    -------
    dict
        name -> dimension, for the unknowns the uses determine; name -> None for those whose
        uses contradict each other (no one dimension fits them all).  The equations are
        solved one linked group of unknowns at a time, so a contradiction leaves open only
        the unknowns it links.
    """
    if not unknowns:
        return {}
    system = _Equations(known, unknowns)
    for _, name, expression in definitions:
        system.names[name] = system._try(expression.root)
    for expression, dimension in constraints:
        monomial = system._try(expression.root)
        if monomial is not None:
            system.equal(monomial, dimension)
    return _solve(system.equations, list(unknowns))


__all__ = ["infer_dimensions", "Monomial"]
