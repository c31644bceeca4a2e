"""Parts -> energies: what the part sections mean (docs/parts.md, "Meaning").

The positions of the body origins (pin chains resolved), of the centres of
gravity and of the named points are built as sympy expressions in the model's
own names -- coordinates, signals and definitions as functions of time, the
parameters as symbols -- differentiated with sympy, and printed back as text of
the model language (``x1'`` for a rate), which is parsed again like any
``[energy]``.  So everything after the model layer (jets, equilibrium check,
linearization, nonlinear equations, report) is unchanged.

    T = sum over bodies  m/2 (xS'^2 + yS'^2) + inertia/2 angle'^2
    U = sum over springs k/2 e^2 + sum over bodies m g yS   (with gravity)
    D = sum over dampers c/2 (e')^2

Examples
--------
>>> from resonant.model import loads
>>> m = loads('''
... [parameters]
... m = 1
... k = 4
... [coordinates]
... x = ""
... [[point]]
... name = "wall"
... position = ["0", "0"]
... [[body]]
... name = "block"
... mass = "m"
... position = ["x", "0"]
... [[spring]]
... between = ["wall", "block"]
... stiffness = "k"
... along = ["1", "0"]
... ''')
>>> m.parts.derived["T"], m.parts.derived["U"]
("m/2*x'^2", 'k/2*x^2')
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping, Sequence
from types import MappingProxyType
from typing import Any

import sympy
from sympy.core.function import AppliedUndef
from sympy.printing.str import StrPrinter

from ..errors import ModelError, Problem
from ..expressions import BinOp, Expression, ExpressionError, parse
from .parts import Body, Contribution, DerivedEnergies, Link, Parts
from .types import TIME, Force

_T = TIME  # never a model name (reserved): the time of the functions


class _Printer(StrPrinter):
    """sympy -> text of the model language (``**`` powers, ``x'`` rates)."""

    def _print_Derivative(self, expr: sympy.Derivative) -> str:
        function, *variables = expr.args
        order = sum(int(count) for _, count in variables)
        return f"{function.func.__name__}{chr(39) * order}"

    def _print_Function(self, expr: sympy.Function) -> str:
        if isinstance(expr, AppliedUndef):
            return str(expr.func.__name__)
        return str(super()._print_Function(expr))

    def _print_Exp1(self, expr: sympy.Expr) -> str:
        return "exp(1)"

    def _print_Float(self, expr: sympy.Float) -> str:
        return repr(float(expr))


def to_text(expr: sympy.Expr) -> str:
    """The model-language text of a sympy expression built by :class:`Mechanism`."""
    return str(_Printer({"order": "none"}).doprint(expr)).replace("**", "^")


class Mechanism:
    """The geometry of the parts in sympy: positions, centres, angles, elongations."""

    def __init__(self, parts: Parts, parameters: Collection[str], coordinates: Sequence[str],
                 signals: Collection[str], definitions: Mapping[str, Expression],
                 equilibrium: Mapping[str, Expression], source: str) -> None:
        self.parts, self.source = parts, source
        self.parameters = set(parameters)
        self.coordinates, self.signals = list(coordinates), set(signals)
        self.definitions = definitions
        self.functions: dict[str, Any] = {}
        self.bodies = {b.name: b for b in parts.bodies}
        self.fixed = {p.name: p for p in parts.points}
        self._origins: dict[str, tuple[sympy.Expr, sympy.Expr]] = {}
        self._angles: dict[str, sympy.Expr] = {}
        # the reference state: coordinates at [equilibrium], signals zero, definitions
        # substituted (in dependency order)
        inlined: dict[Any, sympy.Expr] = {}
        for name, expression in definitions.items():
            inlined[self.function(name)] = self.expr(expression).xreplace(inlined)
        self.inlined = inlined
        reference: dict[Any, sympy.Expr] = {
            self.function(q): (self.expr(equilibrium[q]) if q in equilibrium
                               else sympy.Integer(0)) for q in coordinates}
        reference.update({self.function(s): sympy.Integer(0) for s in signals})
        self.reference_values = reference

    # -- names -----------------------------------------------------------------------
    def function(self, name: str) -> Any:
        if name not in self.functions:
            self.functions[name] = sympy.Function(name)(_T)
        return self.functions[name]

    def resolve(self, name: str, primes: int) -> sympy.Expr:
        if name in self.parameters:
            return sympy.Symbol(name) if primes == 0 else sympy.Integer(0)
        value = self.function(name)
        return sympy.diff(value, _T, primes) if primes else value

    def expr(self, expression: Expression) -> sympy.Expr:
        return expression.to_sympy(self.resolve)

    def at_reference(self, expr: sympy.Expr) -> sympy.Expr:
        """``expr`` at the reference state (no rates may appear in it)."""
        return expr.xreplace(self.inlined).xreplace(self.reference_values)

    # -- geometry --------------------------------------------------------------------
    def angle(self, body: Body) -> sympy.Expr:
        if body.name not in self._angles:
            self._angles[body.name] = self.expr(body.angle) if body.angle is not None \
                else sympy.Integer(0)
        return self._angles[body.name]

    def origin(self, body: Body) -> tuple[sympy.Expr, sympy.Expr]:
        if body.name not in self._origins:
            if body.position is not None:
                self._origins[body.name] = (self.expr(body.position[0]),
                                            self.expr(body.position[1]))
            else:
                assert body.pin is not None  # read_parts guarantees one of them
                self._origins[body.name] = self.point(body.pin)
        return self._origins[body.name]

    def in_body(self, body: Body, local: tuple[Expression, Expression] | None
                ) -> tuple[sympy.Expr, sympy.Expr]:
        """A body-fixed point (given in the body's frame) in the fixed frame."""
        x0, y0 = self.origin(body)
        if local is None:
            return x0, y0
        u, v = self.expr(local[0]), self.expr(local[1])
        a = self.angle(body)
        return (x0 + u * sympy.cos(a) - v * sympy.sin(a),
                y0 + u * sympy.sin(a) + v * sympy.cos(a))

    def point(self, name: str) -> tuple[sympy.Expr, sympy.Expr]:
        """A named point: a ``[[point]]``, a body (its origin) or ``body.P``."""
        if name in self.fixed:
            position = self.fixed[name].position
            return self.expr(position[0]), self.expr(position[1])
        owner, _, local = name.partition(".")
        body = self.bodies[owner]
        return self.in_body(body, body.points[local] if local else None)

    def centre(self, body: Body) -> tuple[sympy.Expr, sympy.Expr]:
        return self.in_body(body, body.centre)

    def elongation(self, link: Link) -> sympy.Expr:
        (xa, ya), (xb, yb) = self.point(link.between[0]), self.point(link.between[1])
        dx, dy = xb - xa, yb - ya
        if link.mode == "elongation":
            assert link.elongation is not None
            return self.expr(link.elongation)
        if link.mode == "along":
            assert link.along is not None
            ex, ey = self.expr(link.along[0]), self.expr(link.along[1])
            norm = sympy.sqrt(ex**2 + ey**2)
            ex, ey = (ex, ey) if norm == 1 else (ex / norm, ey / norm)
            change = dx * ex + dy * ey
            return change - self.at_reference(change)
        # not evaluated: sympy's sqrt of a square of functions of time asks its
        # assumptions about them, which is slow and gives nothing here
        distance = sympy.Pow(_square(dx) + _square(dy), sympy.Rational(1, 2), evaluate=False)
        if link.mode == "length":
            assert link.length is not None
            return distance - self.expr(link.length)
        return distance - self.reference_distance(link)

    def reference_distance(self, link: Link) -> sympy.Expr:
        """|AB| at the reference state (exact, in the parameters)."""
        (xa, ya), (xb, yb) = self.point(link.between[0]), self.point(link.between[1])
        return sympy.sqrt(self.at_reference(xb - xa)**2 + self.at_reference(yb - ya)**2)


def _factor(expr: sympy.Expr) -> str:
    """The text of a factor of a product, in parentheses if it is a sum."""
    text = to_text(expr)
    return f"({text})" if expr.is_Add or text.startswith("-") else text


def _base(expr: sympy.Expr) -> str:
    """The text of the base of a power: in parentheses unless a name or a rate."""
    text = to_text(expr)
    simple = expr.is_Symbol or isinstance(expr, (AppliedUndef, sympy.Derivative)) or \
        (expr.is_Integer and expr >= 0)
    return text if simple else f"({text})"


def _half_squares(coefficient: sympy.Expr, rates: Sequence[sympy.Expr]) -> str:
    """``c/2*(a^2 + b^2)`` as text ('' when zero), composed as text: a sympy product
    of squares of sums of functions of time is slow to build and gains nothing."""
    squares = [f"{_base(rate)}^2" for rate in rates if rate != 0]
    if coefficient == 0 or not squares:
        return ""
    body = squares[0] if len(squares) == 1 else f"({' + '.join(squares)})"
    half = coefficient / 2
    return f"{_factor(half)}*{body}"


def _product(coefficient: sympy.Expr, expr: sympy.Expr) -> str:
    """``c*e`` as text ('' when zero)."""
    if coefficient == 0 or expr == 0:
        return ""
    return f"{_factor(coefficient)}*{_factor(expr)}"


def _square(expr: sympy.Expr) -> sympy.Expr:
    """expr^2, not evaluated when expr is a sum: sympy would ask its assumptions about every
    term (functions of time), which is slow and changes nothing."""
    return sympy.Pow(expr, 2, evaluate=False) if expr.is_Add else expr**2


def _section(kind: str, name: str, index: int) -> str:
    return f'{kind} "{name}"' if name != str(index) else f"{kind} {index}"


def _value(expr: sympy.Expr, values: Mapping[str, sympy.Expr]) -> float | None:
    try:
        number = complex(expr.evalf(30, subs={sympy.Symbol(n): v for n, v in values.items()}))
    except (TypeError, ValueError, ArithmeticError):
        return None
    return number.real if math.isfinite(number.real) else None


def derive_energies(mechanism: Mechanism, written: Mapping[str, Expression],
                    exact_values: Mapping[str, sympy.Expr], allowed: Collection[str],
                    force_points: Mapping[str, str] | None = None
                    ) -> tuple[DerivedEnergies, dict[str, Expression], list[Force]]:
    """The parts' energies, the totals (written + derived) and the torques as forces.

    Raises
    ------
    ModelError
        A negative mass or inertia, a spring or damper of zero length at the
        reference state whose elongation is taken from the geometry, a derived
        energy beyond the expression limits.
    """
    parts, source = mechanism.parts, mechanism.source
    problems: list[Problem] = []
    contributions = [*_body_energies(mechanism, exact_values, problems),
                     *_link_energies(mechanism, exact_values, problems)]
    forces = [Force(f"torque {torque.name}" if torque.name.isdigit() else torque.name,
                    vector=(torque.moment,),
                    point=(_parse(to_text(mechanism.angle(mechanism.bodies[torque.body])),
                                  allowed, source, _section("torque", torque.name, i),
                                  "body", problems),), kind="torque")
              for i, torque in enumerate(parts.torques, start=1)]
    if problems:
        raise ModelError(problems)
    texts: dict[str, list[str]] = {"T": [], "U": [], "D": []}
    for contribution in contributions:
        texts[contribution.energy].append(contribution.text)
    derived = {key: " + ".join(f"({text})" for text in items) if len(items) > 1 else items[0]
               for key, items in texts.items() if items}
    totals = _totals(written, texts, allowed, source, problems)
    if problems:
        raise ModelError(problems)
    positions = {name: tuple(to_text(c) for c in mechanism.point(name))
                 for name in parts.point_names()}
    centres = {b.name: tuple(to_text(c) for c in mechanism.centre(b)) for b in parts.bodies}
    angles = {b.name: to_text(mechanism.angle(b)) for b in parts.bodies}
    result = DerivedEnergies(
        parts=parts, contributions=tuple(contributions),
        derived=MappingProxyType(derived), written=MappingProxyType(dict(written)),
        positions=MappingProxyType(positions),  # type: ignore[arg-type]
        centres=MappingProxyType(centres),  # type: ignore[arg-type]
        angles=MappingProxyType(angles),
        force_points=MappingProxyType(dict(force_points or {})))
    return result, totals, [f for f in forces if f.point[0] is not None]


def _body_energies(mechanism: Mechanism, exact_values: Mapping[str, sympy.Expr],
                   problems: list[Problem]) -> list[Contribution]:
    """Each body's kinetic energy (translation and rotation) and potential energy in
    gravity; a negative mass or inertia is a problem naming the body and the key."""
    parts, source = mechanism.parts, mechanism.source
    gravity = mechanism.expr(parts.gravity) if parts.gravity is not None else None
    out: list[Contribution] = []
    for index, body in enumerate(parts.bodies, start=1):
        section = _section("body", body.name, index)
        for key, expression in (("mass", body.mass), ("inertia", body.inertia)):
            if expression is None:
                continue
            value = _value(mechanism.expr(expression), exact_values)
            if value is not None and value < 0:
                problems.append(Problem(f"the {key} is negative ({value:.6g}); a {key} is "
                                        "at least 0", source, section, key))
        mass = mechanism.expr(body.mass)
        xs, ys = mechanism.centre(body)
        kinetic = [_half_squares(mass, [sympy.diff(xs, _T), sympy.diff(ys, _T)])]
        if body.inertia is not None:
            kinetic.append(_half_squares(mechanism.expr(body.inertia),
                                         [sympy.diff(mechanism.angle(body), _T)]))
        text = " + ".join(k for k in kinetic if k)
        if text:
            out.append(Contribution("body", body.name, "T", text))
        if gravity is not None:
            text = _product(mass * gravity, ys)
            if text:
                out.append(Contribution("body", body.name, "U", text))
    return out


def _link_energies(mechanism: Mechanism, exact_values: Mapping[str, sympy.Expr],
                   problems: list[Problem]) -> list[Contribution]:
    """Each spring's potential energy and each damper's dissipation function, from the
    elongation; a link of zero length whose elongation comes from the geometry is a
    problem (not differentiable there)."""
    parts, source = mechanism.parts, mechanism.source
    out: list[Contribution] = []
    for kind, links, energy in (("spring", parts.springs, "U"), ("damper", parts.dampers, "D")):
        for index, link in enumerate(links, start=1):
            section = _section(kind, link.name, index)
            if link.mode in ("free", "length"):
                distance = _value(mechanism.reference_distance(link), exact_values)
                if distance is not None and abs(distance) < 1e-12:
                    problems.append(Problem(
                        f"the {kind} between {link.between[0]} and {link.between[1]} has "
                        "zero length at the reference state, so its elongation is not "
                        "differentiable there; give along = [ex, ey] (the direction it "
                        "stays parallel to) or elongation = \"...\"", source, section,
                        "length" if link.mode == "length" else "between"))
                    continue
            stretch = mechanism.elongation(link)
            rate = stretch if energy == "U" else sympy.diff(stretch, _T)
            text = _half_squares(mechanism.expr(link.coefficient), [rate])
            if text:
                out.append(Contribution(kind, link.name, energy, text))
    return out


def _totals(written: Mapping[str, Expression], texts: Mapping[str, list[str]],
            allowed: Collection[str], source: str, problems: list[Problem]
            ) -> dict[str, Expression]:
    """The energies as written plus the parts' contributions, one expression each.

    Each part is parsed on its own (each within the parser's limits) and the sum is
    built from their trees, so a mechanism of many parts is not one huge text.
    """
    totals: dict[str, Expression] = dict(written)
    for key, items in texts.items():
        if not items:
            continue
        pieces = ([written[key]] if key in written else []) + \
            [_parse(text, allowed, source, "energy", key, problems) for text in items]
        if any(piece is None for piece in pieces):
            continue
        root = pieces[0].root
        for piece in pieces[1:]:
            root = BinOp("+", root, piece.root)
        totals[key] = Expression(" + ".join(f"({piece.text})" for piece in pieces), root,
                                 (source, "energy", key))
    return totals


def _parse(text: str, allowed: Collection[str], source: str, section: str, key: str,
           problems: list[Problem]) -> Any:
    try:
        return parse(text, allowed=allowed, file=source, section=section, key=key)
    except ExpressionError as exc:
        reason = exc.reason.splitlines()[0]
        problems.append(Problem(f"the energy derived from the parts cannot be used: {reason}",
                                source, section, key))
        return None


def point_expressions(mechanism: Mechanism, name: str, allowed: Collection[str],
                      source: str, section: str, problems: list[Problem]
                      ) -> tuple[Expression, Expression] | None:
    """The fixed-frame position of a named point as two parsed expressions."""
    x, y = (_parse(to_text(c), allowed, source, section, "point", problems)
            for c in mechanism.point(name))
    return (x, y) if x is not None and y is not None else None


__all__ = ["Mechanism", "derive_energies", "point_expressions", "to_text", "TIME"]
