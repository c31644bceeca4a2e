"""The figure of a mechanism as data: what ``resonant draw`` shows, computed, not drawn.

:func:`sketch` evaluates the geometry of a model's parts (``model.parts``, the
:class:`~resonant.model.parts.DerivedEnergies`: positions of the named points,
centres of gravity and angles) at the reference state -- the ``[equilibrium]``
values, every signal zero -- with the parameter values, and lays out a
textbook figure: a block for a translating body, a bar for a pinned one, a disc
where a body has a radius, pins, springs and dampers between their points,
hatched supports (a moving one names its signal), forces and torques, and an
arrow (or a curved arrow) for every generalized coordinate.  Lengths are to
scale; a part too small to see is drawn at a minimum size, and a spring whose
elongation is measured ``along`` a direction (so its length at the reference
state does not matter) is drawn long enough to be seen.  The optional drawing
hints ``shape`` and ``size`` of a ``[[body]]`` override the guesses.

:mod:`resonant.views.drawing` draws a :class:`Sketch` with matplotlib.

Examples
--------
>>> from resonant.model import loads
>>> m = loads('''
... gravity = "g"
... [parameters]
... m = 1
... l = 2
... g = 9.81
... [coordinates]
... phi = ""
... [[point]]
... name = "O"
... position = ["0", "0"]
... [[body]]
... name = "rod"
... mass = "m"
... inertia = "m*l^2/12"
... pin = "O"
... angle = "phi"
... centre = ["0", "-l/2"]
... points = { E = ["0", "-l"] }
... ''')
>>> s = sketch(m)
>>> [(b.name, b.shape) for b in s.bodies], s.points["rod.E"]
([('rod', 'bar')], (0.0, -2.0))
>>> [(type(c).__name__, c.label.text) for c in s.coordinates]
[('Arc', '\\\\varphi')]
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import sympy

from ..errors import ModelError, Problem, printable
from ..expressions import Expression, Name, parse
from ..expressions.notation import name_latex
from ..model import Model
from ..model.parts import Body, DerivedEnergies, Link, Parts

Point = tuple[float, float]

#: a label longer than this is cut (a figure is not the place for a paragraph)
MAX_LABEL = 40
#: the smallest drawn size of a part, as a fraction of the figure's scale
MIN_SIZE = 0.04
#: the largest coordinate of a point that is drawn: beyond it the figure's arithmetic
#: (distances, squares of lengths) overflows double precision
DRAWABLE = 1e100
#: the drawn length of an ``along`` spring or damper, at least, as a fraction of the scale
MIN_LINK = 0.8


@dataclass(frozen=True)
class Label:
    """Text of the figure: ``math`` labels are LaTeX of validated names (mathtext),
    the others plain text from the model file (drawn without math parsing)."""

    text: str
    math: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {"text": self.text, "math": self.math}


@dataclass(frozen=True)
class BodyShape:
    """A body as drawn: ``shape`` block | disc | bar | point | none.

    ``centre`` is the middle of a block or disc (the body's origin) or the centre of
    gravity; a bar runs from ``start`` (its pin) to ``end``; ``bob`` is the radius of a
    point mass at the centre of gravity of a bar (0 for none).
    """

    name: str
    shape: str
    centre: Point
    angle: float = 0.0
    width: float = 0.0
    height: float = 0.0
    radius: float = 0.0
    start: Point = (0.0, 0.0)
    end: Point = (0.0, 0.0)
    gravity_centre: Point | None = None
    bob: float = 0.0
    label: Label = Label("")
    #: the radius of the dashed circle a body carried by signals runs on (an unbalance)
    path: float = 0.0
    path_centre: Point | None = None


@dataclass(frozen=True)
class LinkShape:
    """A spring (zig-zag) or damper (dash-pot) from ``start`` to ``end`` (visible part).

    A ``torsion`` spring (its elongation a turn of bodies, not a change of distance) is
    drawn as a coil about the shaft from ``start`` to ``end``.
    """

    kind: str
    name: str
    start: Point
    end: Point
    label: Label
    #: where the label goes (beside the middle, outward for springs side by side)
    label_at: Point = (0.0, 0.0)
    torsion: bool = False


@dataclass(frozen=True)
class Support:
    """Hatched ground at ``position``; the hatch is on the side opposite ``normal``.

    A moving support names its ``signals`` and the direction ``motion`` it moves in.
    """

    name: str
    position: Point
    normal: Point
    width: float
    signals: tuple[str, ...] = ()
    motion: Point | None = None
    label: Label = Label("")
    #: a post from this point of the frame to the ground (an axle behind a disc)
    post: Point | None = None


@dataclass(frozen=True)
class Arrow:
    """A straight arrow (force or coordinate) from ``start`` along ``vector``."""

    kind: str
    start: Point
    vector: Point
    label: Label


@dataclass(frozen=True)
class Arc:
    """A curved arrow (torque or rotational coordinate) about ``centre``, from angle
    ``start`` to ``stop`` (radians; the head at ``stop``)."""

    kind: str
    centre: Point
    radius: float
    start: float
    stop: float
    label: Label


@dataclass(frozen=True)
class Sketch:
    """Everything :func:`resonant.views.drawing.draw_mechanism` draws, in model units."""

    title: str
    scale: float
    bodies: tuple[BodyShape, ...]
    links: tuple[LinkShape, ...]
    supports: tuple[Support, ...]
    pins: tuple[Point, ...]
    points: Mapping[str, Point]
    forces: tuple[Arrow | Arc, ...]
    coordinates: tuple[Arrow | Arc, ...]
    #: coordinates that move no drawn point (given only in [energy]): not drawn
    undrawn: tuple[str, ...] = ()
    ground_lines: tuple[tuple[Point, Point], ...] = field(default=())

    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` of everything drawn, without labels."""
        xs: list[float] = []
        ys: list[float] = []

        def add(p: Point, r: float = 0.0) -> None:
            xs.extend((p[0] - r, p[0] + r))
            ys.extend((p[1] - r, p[1] + r))

        for b in self.bodies:
            add(b.centre, max(b.width, b.height) / 2 + b.radius)
            if b.shape == "bar":
                add(b.start)
                add(b.end, b.bob)
        for link in self.links:
            add(link.start)
            add(link.end)
        for s in self.supports:
            t = (-s.normal[1], s.normal[0])
            for side in (-1, 1):
                edge = _add(s.position, t, side * s.width / 2)
                add(edge)
                add(_add(edge, s.normal, -(0.35 if s.signals else 0.08) * self.scale))
        for p in self.points.values():
            add(p)
        for item in (*self.forces, *self.coordinates):
            if isinstance(item, Arrow):
                add(item.start)
                add((item.start[0] + item.vector[0], item.start[1] + item.vector[1]))
            else:
                for k in range(9):
                    a = item.start + (item.stop - item.start) * k / 8
                    add((item.centre[0] + item.radius * math.cos(a),
                         item.centre[1] + item.radius * math.sin(a)))
        if not xs:
            return (-1.0, 1.0, -1.0, 1.0)
        return (min(xs), max(xs), min(ys), max(ys))

    def to_dict(self) -> dict[str, Any]:
        """The sketch as plain data (JSON-ready)."""
        def items(seq: Sequence[Any]) -> list[dict[str, Any]]:
            out = []
            for item in seq:
                data = {k: (v.to_dict() if isinstance(v, Label) else v)
                        for k, v in item.__dict__.items()}
                data["type"] = type(item).__name__
                out.append(data)
            return out

        return {"title": self.title, "scale": self.scale, "bodies": items(self.bodies),
                "links": items(self.links), "supports": items(self.supports),
                "pins": list(self.pins), "points": dict(self.points),
                "forces": items(self.forces), "coordinates": items(self.coordinates),
                "undrawn": list(self.undrawn)}


# -- labels ----------------------------------------------------------------------------------

def plain(text: str) -> Label:
    """A label of model text: control characters escaped, at most :data:`MAX_LABEL`."""
    return Label(printable(text, limit=MAX_LABEL))


def name_label(name: str, signal: bool = False) -> Label:
    """The label of a model name (a validated identifier) as math: ``x1`` -> ``x_{1}``."""
    return Label(name_latex(name) + ("(t)" if signal else ""), math=True)


def expression_label(expression: Expression, signals: Sequence[str]) -> Label:
    """A bare name as math (``k`` -> k, ``F`` -> F(t)), anything else as its plain text."""
    if isinstance(expression.root, Name) and expression.root.primes == 0 \
            and expression.root.name != "pi":
        return name_label(expression.root.name, expression.root.name in signals)
    return plain(expression.text)


# -- geometry at the reference state ---------------------------------------------------------

class _Geometry:
    """sympy expressions of the model's names (definitions inlined) and their values at
    the reference state."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.names = [*model.parameters, *model.coordinates, *model.signals,
                      *model.definitions]
        self.definitions: dict[str, sympy.Expr] = {}
        for name, expression in model.definitions.items():
            self.definitions[name] = expression.to_sympy(self._resolve)
        reference: dict[Any, Any] = {sympy.Symbol(s): sympy.Integer(0) for s in model.signals}
        for q in model.coordinates:
            value = model.equilibrium.get(q)
            reference[sympy.Symbol(q)] = value.to_sympy(self._resolve) \
                if value is not None else sympy.Integer(0)
        self.reference = reference
        self.values = {sympy.Symbol(p): v for p, v in model.exact_values.items()}

    def _resolve(self, name: str, primes: int) -> sympy.Expr:
        if primes:
            return sympy.Integer(0)
        if name in self.definitions:
            return self.definitions[name]
        return sympy.Symbol(name)

    def expr(self, item: str | Expression) -> sympy.Expr:
        expression = item if isinstance(item, Expression) else \
            parse(item, allowed=self.names)
        return expression.to_sympy(self._resolve)

    def value(self, expr: sympy.Expr, what: str = "") -> float:
        number = expr.xreplace(self.reference).xreplace(self.values)
        try:
            result = complex(number.evalf(20))
        except (TypeError, ValueError, ArithmeticError):
            result = complex(math.nan)
        if not math.isfinite(result.real):
            raise ModelError(Problem(f"cannot draw: {what or 'a position'} has no finite "
                                     "value at the reference state", self.model.source,
                                     "body"))
        return result.real

    def derivative(self, expr: sympy.Expr, name: str, order: int = 1) -> float:
        return self.value(sympy.diff(expr, sympy.Symbol(name), order))

    def point(self, texts: tuple[str, str]) -> tuple[sympy.Expr, sympy.Expr]:
        return self.expr(texts[0]), self.expr(texts[1])


def _norm(v: Point) -> float:
    return math.hypot(v[0], v[1])


def _unit(v: Point) -> Point:
    n = _norm(v)
    return (v[0] / n, v[1] / n) if n > 0 else (0.0, 0.0)


def _add(a: Point, b: Point, s: float = 1.0) -> Point:
    return (a[0] + s * b[0], a[1] + s * b[1])


def _sub(a: Point, b: Point) -> Point:
    return (a[0] - b[0], a[1] - b[1])


def _perp(v: Point) -> Point:
    return (-v[1], v[0])


# -- the layout ------------------------------------------------------------------------------

class _Layout:
    def __init__(self, model: Model, parts: DerivedEnergies) -> None:
        self.model, self.derived, self.parts = model, parts, parts.parts
        self.geo = _Geometry(model)
        self.bodies = {b.name: b for b in self.parts.bodies}
        self.fixed = {p.name for p in self.parts.points}
        self.signals = list(model.signals)
        self.exprs = {name: self.geo.point(texts) for name, texts in parts.positions.items()}
        self.actual = {name: (self.geo.value(x, f"the position of {name}"),
                              self.geo.value(y, f"the position of {name}"))
                       for name, (x, y) in self.exprs.items()}
        self.centre_exprs = {name: self.geo.point(texts)
                             for name, texts in parts.centres.items()}
        self.centres = {name: (self.geo.value(x), self.geo.value(y))
                        for name, (x, y) in self.centre_exprs.items()}
        self.angle_exprs = {name: self.geo.expr(text) for name, text in parts.angles.items()}
        self.angles = {name: self.geo.value(a, f"the angle of {name}")
                       for name, a in self.angle_exprs.items()}
        self.masses = {b.name: max(0.0, self.geo.value(self.geo.expr(b.mass)))
                       for b in self.parts.bodies}
        self.inertias = {b.name: max(0.0, self.geo.value(self.geo.expr(b.inertia)))
                         if b.inertia is not None else 0.0 for b in self.parts.bodies}
        self._check_drawable()
        self.scale = self._scale()
        self.shift: dict[str, Point] = {}

    def _check_drawable(self) -> None:
        """Refuse positions too large to draw, naming the part (not an overflow later)."""
        problems = []
        for name, (x, y) in {**self.actual, **self.centres}.items():
            if all(math.isfinite(v) and abs(v) <= DRAWABLE for v in (x, y)):
                continue
            owner = self.owner(name)
            kind = "point" if owner in self.fixed else "body"
            problems.append(Problem(
                f"{name} is at ({x:.3g}, {y:.3g}) at the reference state: too far out to "
                f"draw (each coordinate of a point is drawn up to {DRAWABLE:.0e}); check "
                "the position's units and values", self.model.source,
                f'{kind} "{printable(owner, limit=60)}"', "position"))
            if len(problems) >= 5:
                break
        if problems:
            raise ModelError(problems)

    # -- sizes -------------------------------------------------------------------------
    def _scale(self) -> float:
        points = [*self.actual.values(), *self.centres.values()]
        xs = [p[0] for p in points]
        ys = [p[1] for p in points]
        extent = max(max(xs) - min(xs), max(ys) - min(ys)) if points else 0.0
        if extent > 1e-12:
            # not larger than the shortest spring allows (a chain of many blocks)
            spans = [_norm(_sub(self.actual[a], self.actual[b]))
                     for link in (*self.parts.springs, *self.parts.dampers)
                     for a, b in [link.between]]
            spans = [d for d in spans if d > 1e-6 * extent]
            return min(extent, 1.5 * min(spans)) if spans else extent
        sizes = [self.size(e) for b in self.parts.bodies for e in b.size]
        sizes += [math.sqrt(2 * self.inertias[b]) / math.sqrt(self.masses[b])
                  for b in self.bodies if self.masses[b] > 0 and self.inertias[b] > 0]
        sizes = [abs(s) * 4 for s in sizes if math.isfinite(s) and s > 0]
        return max(sizes) if sizes else 1.0

    def size(self, text: str | Expression) -> float:
        """A size of the model, bounded: at most :data:`DRAWABLE` (the square of a radius of
        1e300 is out of the range of a float; the figure is scaled to the bounded size)."""
        return min(abs(self.geo.value(self.geo.expr(text))), DRAWABLE)

    def factor(self, body: str) -> float:
        """Relative size of a body from its mass (cube root), between 0.55 and 1."""
        heaviest = max(self.masses.values(), default=0.0)
        if heaviest <= 0 or self.masses[body] <= 0:
            return 0.7
        return min(1.0, max(0.55, (self.masses[body] / heaviest) ** (1 / 3)))

    def at_least(self, value: float) -> float:
        return max(value, MIN_SIZE * self.scale)

    # -- which body carries which point; drawing shifts -----------------------------------
    def owner(self, point: str) -> str:
        return point if point in self.fixed else point.split(".", 1)[0]

    def root(self, point: str) -> str:
        name = self.owner(point)
        seen = set()
        while name in self.bodies and self.bodies[name].pin is not None and name not in seen:
            seen.add(name)
            name = self.owner(self.bodies[name].pin or "")
        return name

    def at(self, point: str) -> Point:
        """Where a named point is drawn (its position plus the drawing shift of its root)."""
        return _add(self.actual[point], self.shift.get(self.root(point), (0.0, 0.0)))

    def spread(self) -> None:
        """Draw ``along`` springs and dampers long enough to be seen: move one end's
        group of bodies (a support first) along the spring's direction."""
        placed: set[str] = set()
        wanted = MIN_LINK * self.scale
        for link in (*self.parts.springs, *self.parts.dampers):
            if link.mode != "along" or link.along is None:
                continue
            e = _unit((self.geo.value(self.geo.expr(link.along[0])),
                       self.geo.value(self.geo.expr(link.along[1]))))
            a, b = link.between
            ra, rb = self.root(a), self.root(b)
            if ra == rb or e == (0.0, 0.0):
                continue
            d = _sub(self.at(b), self.at(a))
            gap = d[0] * e[0] + d[1] * e[1]
            if gap < wanted and not (ra in placed and rb in placed):
                if rb in placed or (ra not in placed and ra in self.fixed
                                    and rb not in self.fixed):
                    self.shift[ra] = _add(self.shift.get(ra, (0.0, 0.0)), e, gap - wanted)
                else:
                    self.shift[rb] = _add(self.shift.get(rb, (0.0, 0.0)), e, wanted - gap)
            placed.update((ra, rb))

    # -- bodies ------------------------------------------------------------------------
    def body_shape(self, body: Body) -> BodyShape:
        name = body.name
        origin = self.at(name)
        centre = _add(self.centres[name], self.shift.get(self.root(name), (0.0, 0.0)))
        angle = self.angles[name]
        sizes = [self.size(e) for e in body.size]
        shape = body.shape or self.guess_shape(body)
        f = self.factor(name)
        label = plain(name)
        if shape == "bar":
            ends = [centre] + [self.at(f"{name}.{p}") for p in body.points]
            end = max(ends, key=lambda p: _norm(_sub(p, origin)))
            if end == centre and self.inertias[name] > 0:  # a uniform rod: twice as long
                end = _add(origin, _sub(centre, origin), 2.0)
            if _norm(_sub(end, origin)) < 1e-12:
                end = _add(origin, (0.0, -0.3 * self.scale))
            point_mass = self.masses[name] > 0 and self.inertias[name] == 0 and \
                _norm(_sub(centre, origin)) > 1e-12
            # a massless rod carrying a point mass is thin
            width = self.at_least(sizes[0]) if sizes else \
                (0.012 if point_mass else 0.035) * self.scale
            bob = self.at_least(0.06 * self.scale * f) if point_mass else 0.0
            return BodyShape(name, "bar", centre, angle, width=width, start=origin, end=end,
                             gravity_centre=None if point_mass else centre, bob=bob,
                             label=label)
        if shape == "disc":
            rim = [_norm(_sub(self.at(f"{name}.{p}"), origin)) for p in body.points]
            radius = sizes[0] if sizes else max(rim) if rim and max(rim) > 0 else \
                self.disc_radius(name, f)
            return BodyShape(name, "disc", origin, angle, radius=self.at_least(radius),
                             label=label)
        if shape == "point":
            radius = sizes[0] if sizes else 0.05 * self.scale * f
            path = self.signal_path(name)
            if path is not None:  # an unbalance: on its circle, where it is at t = 0
                offset, reach = path
                drawn = max(reach, 0.1 * self.scale)  # a circle too small to see: larger
                offset = (offset[0] * drawn / reach, offset[1] * drawn / reach)
                return BodyShape(name, "point", _add(centre, offset), angle,
                                 radius=max(min(radius, 0.35 * drawn), 0.02 * self.scale),
                                 label=label, path=drawn, path_centre=centre)
            return BodyShape(name, "point", centre, angle, radius=self.at_least(radius),
                             label=label)
        if shape == "block":
            width = sizes[0] if sizes else 0.45 * self.scale * f
            height = sizes[1] if len(sizes) > 1 else (0.65 * width if sizes
                                                      else 0.3 * self.scale * f)
            return BodyShape(name, "block", origin, angle, width=self.at_least(width),
                             height=self.at_least(height), label=label)
        return BodyShape(name, "none", origin, angle, label=label)

    def signal_path(self, name: str) -> tuple[Point, float] | None:
        """A body carried around by its signals in both directions (a rotating unbalance):
        its offset from the reference position at t = 0 and the largest distance from it,
        sampled over 10 s; None for any other body."""
        x, y = self.centre_exprs[name]
        used = [s for s in self.signals
                if sympy.Symbol(s) in (x.free_symbols | y.free_symbols)]
        if not used:
            return None
        t = sympy.Symbol("t")
        timed = {sympy.Symbol(s): self.geo.expr(self.model.signals[s]) for s in used}
        fixed = {**{k: v for k, v in self.geo.reference.items() if k not in timed},
                 **self.geo.values}
        try:
            fx, fy = (sympy.lambdify(t, e.xreplace(timed).xreplace(fixed).xreplace(fixed),
                                     "math") for e in (x, y))
            x0, y0 = self.geo.value(x), self.geo.value(y)
            samples = [(float(fx(k / 200)) - x0, float(fy(k / 200)) - y0)
                       for k in range(2001)]
        except (TypeError, ValueError, ArithmeticError, NameError):
            return None
        spread_x = max(p[0] for p in samples) - min(p[0] for p in samples)
        spread_y = max(p[1] for p in samples) - min(p[1] for p in samples)
        reach = max(_norm(p) for p in samples)
        if not (math.isfinite(reach) and reach > 0 and spread_x > 0.5 * reach
                and spread_y > 0.5 * reach):
            return None
        return samples[0], reach

    def guess_shape(self, body: Body) -> str:
        name = body.name
        if body.pin is not None:
            reach = [_norm(_sub(self.centres[name], self.actual[name]))] + \
                [_norm(_sub(self.actual[f"{name}.{p}"], self.actual[name]))
                 for p in body.points]
            if reach[0] < 1e-12 and self.inertias[name] > 0:
                return "disc"  # turning about its centre of gravity: a pulley, a rotor
            if max(reach) > 1e-12:
                return "bar"
            return "point"
        moving = {s.name for s in self.geo.expr(self.derived.positions[name][0]).free_symbols
                  | self.geo.expr(self.derived.positions[name][1]).free_symbols}
        if moving & set(self.signals):
            return "point"
        x, y = self.exprs[name]
        for q in self.model.coordinates:  # a body on a curved path swings: a point mass
            if self.geo.derivative(x, q, 2) or self.geo.derivative(y, q, 2):
                return "point"
        if self.inertias[name] > 0:
            return "disc"
        if self.masses[name] == 0:
            return "bar" if body.points else "point"
        return "block"

    def disc_radius(self, name: str, f: float) -> float:
        m, inertia = self.masses[name], self.inertias[name]
        if m > 0 and inertia > 0:
            return math.sqrt(2 * inertia / m)  # a uniform disc: I = m r^2 / 2
        return 0.15 * self.scale * f


def _clip(a: Point, b: Point, body: BodyShape | None) -> Point:
    """Where the segment from ``a`` to ``b`` enters ``body`` (b itself for no body)."""
    if body is None or body.shape in ("bar", "none"):
        return b
    d = _sub(b, a)
    length = _norm(d)
    if length == 0:
        return b
    if body.shape in ("disc", "point"):
        # |a + t d - c| = r, the smaller root
        f = _sub(a, body.centre)
        qa, qb = d[0] ** 2 + d[1] ** 2, 2 * (f[0] * d[0] + f[1] * d[1])
        qc = f[0] ** 2 + f[1] ** 2 - body.radius ** 2
        disc = qb * qb - 4 * qa * qc
        if disc < 0:
            return b
        t = (-qb - math.sqrt(disc)) / (2 * qa)
        return _add(a, d, min(1.0, max(0.0, t)))
    # a block: slab method in the block's frame
    c, s = math.cos(body.angle), math.sin(body.angle)
    rel = _sub(a, body.centre)
    p = (c * rel[0] + s * rel[1], -s * rel[0] + c * rel[1])
    v = (c * d[0] + s * d[1], -s * d[0] + c * d[1])
    t_in = 0.0
    for k, half in ((0, body.width / 2), (1, body.height / 2)):
        if abs(v[k]) < 1e-15:
            continue
        t1, t2 = (-half - p[k]) / v[k], (half - p[k]) / v[k]
        t_in = max(t_in, min(t1, t2))
    return _add(a, d, min(1.0, t_in))


def _snap(v: Point) -> Point:
    """The axis direction nearest to ``v`` (walls and floors, as in a textbook)."""
    if v == (0.0, 0.0):
        return (0.0, 1.0)
    if abs(v[0]) > abs(v[1]):
        return (math.copysign(1.0, v[0]), 0.0)
    return (0.0, math.copysign(1.0, v[1]))


def sketch(model: Model) -> Sketch:
    """The figure of a model's parts at its reference state, as data.

    Parameters
    ----------
    model : Model
        A model with parts (``model.parts`` is not None).

    Returns
    -------
    Sketch
        Bodies, springs and dampers, supports, pins, named points, forces and
        torques, and the generalized coordinates, in the model's length unit.

    Raises
    ------
    ModelError
        If the model has no parts, or a position has no finite value at the
        reference state.
    """
    return _sketch(model)[0]


def _sketch(model: Model) -> tuple[Sketch, _Layout, list[str]]:
    """The sketch, its layout and the owner (body or point) of each force, in order."""
    derived = model.parts
    if derived is None or not derived.parts.bodies and not derived.parts.points:
        raise ModelError(Problem("the model has no parts to draw ([[body]], [[point]], "
                                 "[[spring]], ...); resonant draws a mechanism described by "
                                 "its parts (docs/parts.md)", model.source))
    layout = _Layout(model, derived)
    layout.spread()
    u = layout.scale
    bodies = tuple(layout.body_shape(b) for b in derived.parts.bodies)
    by_name = {b.name: b for b in bodies}

    # springs and dampers: side by side when they join the same two points
    links: list[LinkShape] = []
    for group in _link_groups(derived.parts):
        for i, link in enumerate(group):
            a, b = layout.at(link.between[0]), layout.at(link.between[1])
            along = _unit(_sub(b, a))
            if along == (0.0, 0.0):
                continue
            offset = (i - (len(group) - 1) / 2) * 0.16 * u
            a2, b2 = _add(a, _perp(along), offset), _add(b, _perp(along), offset)
            start = _clip(b2, a2, by_name.get(link.between[0]))
            end = _clip(a2, b2, by_name.get(link.between[1]))
            side = 1.0 if offset >= 0 else -1.0
            middle = ((start[0] + end[0]) / 2, (start[1] + end[1]) / 2)
            label_at = _add(middle, _perp(along), side * 0.11 * u)
            links.append(LinkShape(link.kind, link.name, start, end,
                                   expression_label(link.coefficient, layout.signals),
                                   label_at, torsional(derived.parts, link)))

    supports = _supports(layout, bodies, links)
    supports += _rolling_grounds(layout, bodies)
    pins = tuple(layout.at(b.pin) for b in derived.parts.bodies if b.pin is not None)
    points = {name: layout.at(name) for name in derived.positions if "." in name}
    force_owners: list[str] = []
    forces = _forces(layout, by_name, force_owners)
    obstacles = [(link.start, link.end) for link in links] + \
        [(b.start, b.end) for b in bodies if b.shape == "bar"] + \
        [(f.start, _add(f.start, f.vector)) for f in forces if isinstance(f, Arrow)]
    coordinates, undrawn = _coordinates(layout, by_name, obstacles)
    return Sketch(model.title, u, bodies, tuple(links), tuple(supports), pins, points,
                  tuple(forces), tuple(coordinates), tuple(undrawn)), layout, force_owners


def _supports(layout: _Layout, bodies: Sequence[BodyShape], links: Sequence[LinkShape]
              ) -> list[Support]:
    u = layout.scale
    out = []
    for point in layout.parts.points:
        here = layout.at(point.name)
        directions: list[Point] = []
        spread = 0.0
        for link in (*layout.parts.springs, *layout.parts.dampers):
            if point.name in link.between:
                other = link.between[1] if link.between[0] == point.name else link.between[0]
                directions.append(_unit(_sub(layout.at(other), here)))
        for shape in links:
            for end in (shape.start, shape.end):
                if _norm(_sub(end, here)) < 0.3 * u:
                    spread = max(spread, _norm(_sub(end, here)))
        axle = 0.0
        for body in bodies:
            if layout.bodies[body.name].pin == point.name:
                target = body.end if body.shape == "bar" else body.centre
                if _norm(_sub(target, here)) < 1e-12:  # turning about its centre
                    axle = max(axle, body.radius)
                    continue
                directions.append(_unit(_sub(target, here)))
        mean = (sum(d[0] for d in directions), sum(d[1] for d in directions))
        normal = _snap(mean)
        post = None
        if axle and not directions:  # a disc on an axle: a post down to the ground
            post, normal = here, (0.0, 1.0)
            here = (here[0], here[1] - axle - 0.12 * u)
        x, y = (layout.geo.expr(e) for e in point.position)
        signals = tuple(s for s in layout.signals
                        if sympy.Symbol(s) in (x.free_symbols | y.free_symbols))
        motion = None
        if signals:
            s = signals[0]
            motion = _unit((layout.geo.derivative(x, s), layout.geo.derivative(y, s)))
            motion = motion if motion != (0.0, 0.0) else None
        label = Label(", ".join(name_latex(s) + "(t)" for s in signals), math=True) \
            if signals else Label("")
        width = 0.25 * u if post is not None else max(0.3 * u, 2 * spread + 0.12 * u)
        out.append(Support(point.name, here, normal, width, signals, motion, label, post))
    return out


def _rolling_grounds(layout: _Layout, bodies: Sequence[BodyShape]) -> list[Support]:
    """A floor under a disc that rolls on it (its angle turns with -x/r)."""
    out = []
    for shape in bodies:
        if shape.shape != "disc":
            continue
        x, _ = layout.exprs[shape.name]
        angle = layout.angle_exprs[shape.name]
        for q in layout.model.coordinates:
            dx, da = layout.geo.derivative(x, q), layout.geo.derivative(angle, q)
            if dx != 0 and abs(da * shape.radius + dx) < 1e-9 * abs(dx):
                floor = _add(shape.centre, (0.0, -shape.radius))
                out.append(Support("", floor, (0.0, 1.0), 3 * shape.radius))
                break
    return out


def _label_of_vector(vector: Sequence[Expression], direction: Point, name: str,
                     signals: Sequence[str]) -> Label:
    used = [e for e, d in zip(vector, direction) if abs(d) > 1e-12]
    if len(used) == 1:
        label = expression_label(used[0], signals)
        if label.math:
            return label
    return plain(name)


def _direction(layout: _Layout, exprs: Sequence[sympy.Expr]) -> list[float]:
    """The direction a signal-driven vector points in: its value plus its change with
    every signal (a force F(t) is zero at the reference state)."""
    out = []
    for e in exprs:
        value = layout.geo.value(e)
        value += sum(layout.geo.derivative(e, s) for s in layout.signals)
        out.append(value)
    return out


def _forces(layout: _Layout, bodies: Mapping[str, BodyShape], owners: list[str]
            ) -> list[Arrow | Arc]:
    """The forces' arrows and the torques' arcs; ``owners`` gets the body or point each
    is drawn on ("" where none)."""
    u = layout.scale
    out: list[Arrow | Arc] = []
    torque_names = {t.name for t in layout.parts.torques} | \
        {f"torque {t.name}" for t in layout.parts.torques}
    for force in layout.model.forces:
        if force.generalized or len(force.vector) != 2 or force.name in torque_names:
            continue
        if force.name in layout.derived.force_points:
            at = layout.at(layout.derived.force_points[force.name])
        else:
            at = (layout.geo.value(layout.geo.expr(force.point[0])),
                  layout.geo.value(layout.geo.expr(force.point[1])))
        direction = _unit(tuple(_direction(layout, [layout.geo.expr(e)  # type: ignore[arg-type]
                                                     for e in force.vector])))
        if direction == (0.0, 0.0):
            continue
        label = _label_of_vector(force.vector, direction, force.name, layout.signals)
        shape = bodies.get(layout.derived.force_points.get(force.name, ""))
        if shape is not None and shape.shape in ("block", "disc", "point"):
            # from the body's outline, not across its middle and name
            at = _clip(_add(at, direction, 10 * u), at, shape)
        out.append(Arrow("force", at, (0.3 * u * direction[0], 0.3 * u * direction[1]),
                         label))
        owners.append(layout.owner(layout.derived.force_points[force.name])
                      if force.name in layout.derived.force_points else "")
    for torque in layout.parts.torques:
        shape = bodies.get(torque.body)
        if shape is not None and shape.shape == "bar":
            # about the middle of the bar, on the side away from the coordinates' arcs
            centre = ((shape.start[0] + shape.end[0]) / 2, (shape.start[1] + shape.end[1]) / 2)
            base = math.atan2(shape.end[1] - shape.start[1], shape.end[0] - shape.start[0]) \
                - math.pi / 2
            radius = 0.1 * u
        else:
            centre = layout.at(torque.body)
            radius = shape.radius * 1.5 if shape is not None and shape.radius else 0.12 * u
            base = math.pi / 2
        sign = _direction(layout, [layout.geo.expr(torque.moment)])[0]
        start, stop = (base - 0.9, base + 0.9) if sign >= 0 else (base + 0.9, base - 0.9)
        label = expression_label(torque.moment, layout.signals)
        if not label.math and not torque.name.isdigit():
            label = plain(torque.name)
        out.append(Arc("torque", centre, radius, start, stop, label))
        owners.append(torque.body)
    return out


def _angle_arc(layout: _Layout, bodies: Mapping[str, BodyShape],
               obstacles: list[tuple[Point, Point]], q: str, label: Label
               ) -> tuple[Arc, str] | None:
    """A curved arrow about a pin (or centre) if ``q`` is, one to one, a body's angle."""
    symbol = sympy.Symbol(q)
    for body in layout.parts.bodies:
        if symbol not in layout.angle_exprs[body.name].free_symbols:
            continue
        rate = layout.geo.derivative(layout.angle_exprs[body.name], q)
        if abs(abs(rate) - 1) >= 1e-9:
            continue
        shape = bodies[body.name]
        if shape.shape == "bar":
            centre = shape.start
            radius = 0.35 * _norm(_sub(shape.end, shape.start))
            heading = math.atan2(shape.end[1] - shape.start[1], shape.end[0] - shape.start[0])
        else:
            centre = shape.centre
            radius = 1.35 * shape.radius if shape.radius else 0.12 * layout.scale

            def room(h: float, c: Point = centre, r: float = radius) -> float:
                a = (c[0] + r * math.cos(h), c[1] + r * math.sin(h))
                b = (c[0] + r * math.cos(h + 0.8), c[1] + r * math.sin(h + 0.8))
                return _clearance(a, b, obstacles)

            heading = max((-math.pi / 2, math.pi / 2, -math.pi / 4, math.pi * 3 / 4), key=room)
        return Arc("coordinate", centre, radius, heading + 0.12 * rate, heading + 0.9 * rate,
                   label), body.name
    return None


_Move = tuple[str, sympy.Expr, sympy.Expr, Point]  # point, its x and y, d(x, y)/dq


def _moves(layout: _Layout, q: str) -> list[_Move]:
    """The points (positioned bodies, named points, centres) that ``q`` moves."""
    symbol = sympy.Symbol(q)
    positioned = [b.name for b in layout.parts.bodies if b.position is not None]
    named = [n for n in layout.exprs if "." in n]
    candidates = [(n, layout.exprs[n]) for n in positioned + named] + \
        [(f"{n} (centre)", layout.centre_exprs[n]) for n in layout.centre_exprs]
    moved = []
    for name, (x, y) in candidates:
        if symbol not in x.free_symbols and symbol not in y.free_symbols:
            continue
        g = (layout.geo.derivative(x, q), layout.geo.derivative(y, q))
        if _norm(g) > 1e-12:
            moved.append((name, x, y, g))
    return moved


def _turning_arc(layout: _Layout, moved: Sequence[_Move], q: str, label: Label
                 ) -> tuple[Arc, str] | None:
    """A curved arrow about the centre ``q`` turns a point about (|d²P/dq²| = |dP/dq|,
    perpendicular), if there is one."""
    geo = layout.geo
    for name, x, y, g in moved:
        h = (geo.derivative(x, q, 2), geo.derivative(y, q, 2))
        if abs(_norm(h) - _norm(g)) < 1e-9 * _norm(g) and \
                abs(g[0] * h[0] + g[1] * h[1]) < 1e-9 * _norm(g) ** 2:
            centre = _add(_point_at(layout, name), h)
            heading = math.atan2(-h[1], -h[0])
            sign = 1.0 if h[1] * g[0] - h[0] * g[1] > 0 else -1.0  # (P - O) x g
            return Arc("coordinate", centre, 0.3 * _norm(h), heading + 0.12 * sign,
                       heading + 0.9 * sign, label), name
    return None


def _reach(carrier: BodyShape | None, normal: Point) -> float:
    """How far a body's outline reaches from its centre along ``normal``."""
    if carrier is not None and carrier.shape == "block":
        c, s = math.cos(carrier.angle), math.sin(carrier.angle)
        return abs(normal[0] * c + normal[1] * s) * carrier.width / 2 + \
            abs(-normal[0] * s + normal[1] * c) * carrier.height / 2
    return carrier.radius if carrier is not None else 0.0


def _straight_arrow(layout: _Layout, bodies: Mapping[str, BodyShape],
                    obstacles: list[tuple[Point, Point]], name: str, g: Point, label: Label
                    ) -> Arrow:
    """A straight arrow along ``g`` beside point ``name``, on the side where it crosses
    nothing (a spring on top of a block, a force)."""
    u = layout.scale
    direction = _unit(g)
    point = _point_at(layout, name)
    carrier = bodies.get(name.removesuffix(" (centre)")) if "." not in name else None
    normal = _perp(direction)
    reach = _reach(carrier, normal)
    vector = (0.22 * u * direction[0], 0.22 * u * direction[1])
    sides = [_add(point, normal, side * (reach + 0.08 * u)) for side in (1.0, -1.0)]
    start = max(sides, key=lambda p: _clearance(p, _add(p, vector), obstacles))
    obstacles.append((start, _add(start, vector)))
    return Arrow("coordinate", start, vector, label)


def _coordinates(layout: _Layout, bodies: Mapping[str, BodyShape],
                 obstacles: list[tuple[Point, Point]]) -> tuple[list[Arrow | Arc], list[str]]:
    """An arrow for each generalized coordinate where it moves the figure most plainly:
    a curved arrow about a pin if it is a body's angle, a straight arrow at a point it
    moves one to one, else about the centre it turns a point about, else at the point it
    moves most."""
    out: list[Arrow | Arc] = []
    undrawn = []
    used: set[str] = set()
    for q in layout.model.coordinates:
        label = name_label(q)
        moved = _moves(layout, q)
        unit_moves = [m for m in moved if abs(_norm(m[3]) - 1) < 1e-9]
        arc = _angle_arc(layout, bodies, obstacles, q, label) or \
            (None if unit_moves else _turning_arc(layout, moved, q, label))
        if arc is not None:
            out.append(arc[0])
            used.add(arc[1])
            continue
        if not moved:
            undrawn.append(q)
            continue
        choice = next((m for m in unit_moves if m[0] not in used), unit_moves[0]) \
            if unit_moves else max(moved, key=lambda m: _norm(m[3]))
        used.add(choice[0])
        out.append(_straight_arrow(layout, bodies, obstacles, choice[0], choice[3], label))
    return out, undrawn


def _segment_distance(p: Point, a: Point, b: Point) -> float:
    d = _sub(b, a)
    n = d[0] ** 2 + d[1] ** 2
    t = 0.0 if n == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / n))
    return _norm(_sub(p, _add(a, d, t)))


def _clearance(a: Point, b: Point, obstacles: Sequence[tuple[Point, Point]]) -> float:
    """The least distance between the segment ab and the obstacles (sampled)."""
    best = math.inf
    for k in range(11):
        p = _add(a, _sub(b, a), k / 10)
        for s0, s1 in obstacles:
            best = min(best, _segment_distance(p, s0, s1))
    return best


def _point_at(layout: _Layout, candidate: str) -> Point:
    if candidate.endswith(" (centre)"):
        body = candidate[: -len(" (centre)")]
        return _add(layout.centres[body], layout.shift.get(layout.root(body), (0.0, 0.0)))
    return layout.at(candidate)


@dataclass(frozen=True)
class SketchMotion:
    """How the drawing of a mechanism moves: what carries each drawn item, and where.

    Every moving item of a :class:`Sketch` is carried by an *owner*, a body (moving
    rigidly: its origin and angle) or a fixed point (moving with its signals, a support).
    The owners' positions are sympy expressions of the parameters, coordinates and
    signals (definitions inlined); an item is drawn at its place in the sketch moved as
    its owner moves from its reference position.

    Parameters
    ----------
    sketch : Sketch
        The figure at the reference state.
    owners : tuple of str
        Body and point names, in order.
    positions : tuple of tuple
        Per owner ``(x, y, angle)`` as sympy expressions (angle 0 for a point).
    shifts : tuple of tuple
        Per owner the drawing's shift of it (an ``along`` spring drawn longer moves a
        group of parts): the owner is drawn at its position plus its shift.
    bodies, supports, pins, forces : tuple of int
        The owner (index into ``owners``, -1 for none) of each item of the sketch's
        lists of the same name.
    links : tuple of tuple of int
        The owners of the two ends of each spring or damper.
    points : mapping
        Named point -> its owner.

    Examples
    --------
    >>> import pathlib, resonant
    >>> path = pathlib.Path(resonant.__file__).parents[2] / "examples/parts/pendulum.toml"
    >>> motion = sketch_motion(resonant.load(path))
    >>> motion.owners, motion.positions[1][2]
    (('pivot', 'bob'), theta)
    """

    sketch: Sketch
    owners: tuple[str, ...]
    positions: tuple[tuple[sympy.Expr, sympy.Expr, sympy.Expr], ...]
    shifts: tuple[Point, ...]
    bodies: tuple[int, ...]
    links: tuple[tuple[int, int], ...]
    supports: tuple[int, ...]
    pins: tuple[int, ...]
    forces: tuple[int, ...]
    points: Mapping[str, int]


def sketch_motion(model: Model) -> SketchMotion:
    """The sketch of a model's parts with what moves each item and how.

    Parameters
    ----------
    model : Model
        A model with parts.

    Returns
    -------
    SketchMotion

    Raises
    ------
    ModelError
        As :func:`sketch`.

    Examples
    --------
    >>> import pathlib, resonant
    >>> path = pathlib.Path(resonant.__file__).parents[2] / "examples/parts/cart_pendulum.toml"
    >>> motion = sketch_motion(resonant.load(path))
    >>> motion.owners, motion.links
    (('support', 'cart', 'rod'), ((0, 1),))
    """
    data, layout, force_owners = _sketch(model)
    parts = layout.parts
    owners = (*(p.name for p in parts.points), *(b.name for b in parts.bodies))
    index = {name: i for i, name in enumerate(owners)}
    zero = sympy.Integer(0)
    positions = tuple((*layout.exprs[name], layout.angle_exprs.get(name, zero))
                      for name in owners)

    def of(point: str | None) -> int:
        return index.get(layout.owner(point), -1) if point else -1

    links = tuple((of(link.between[0]), of(link.between[1]))
                  for group in _link_groups(parts) for link in group
                  if _unit(_sub(layout.at(link.between[1]), layout.at(link.between[0])))
                  != (0.0, 0.0))
    shifts = tuple(layout.shift.get(layout.root(name), (0.0, 0.0)) for name in owners)
    return SketchMotion(
        data, owners, positions, shifts, tuple(index[b.name] for b in data.bodies), links,
        tuple(index.get(s.name, -1) if s.name else -1 for s in data.supports),
        tuple(of(b.pin) for b in parts.bodies if b.pin is not None),
        tuple(index.get(o, -1) if o else -1 for o in force_owners),
        {name: of(name) for name in data.points})


def torsional(parts: Parts, link: Link) -> bool:
    """Whether a spring or damper twists rather than stretches: its elongation is made of
    coordinates that turn bodies (their ``angle``) and move none (no ``position``).

    Examples
    --------
    >>> import resonant
    >>> parts = resonant.load("examples/parts/torsional_chain.toml").parts.parts
    >>> [torsional(parts, s) for s in parts.springs]
    [True, True]
    >>> parts = resonant.load("examples/parts/cart_pendulum.toml").parts.parts
    >>> [torsional(parts, s) for s in parts.springs]
    [False]
    """
    if link.mode != "elongation" or link.elongation is None:
        return False
    names = set(link.elongation.names())
    turning: set[tuple[str, int]] = set()  # (name, primes), as Expression.names() gives
    moving: set[tuple[str, int]] = set()
    for body in parts.bodies:
        if body.angle is not None:
            turning |= set(body.angle.names())
        for entry in (*(body.position or ()), *(body.centre or ())):
            moving |= set(entry.names()) if hasattr(entry, "names") else set()
    return bool(names) and names <= turning and not names & moving


def _link_groups(parts: Parts) -> list[list[Link]]:
    """Springs and dampers grouped by the two points they join (the sketch's order)."""
    groups: dict[frozenset[str], list[Link]] = {}
    for link in (*parts.springs, *parts.dampers):
        groups.setdefault(frozenset(link.between), []).append(link)
    return list(groups.values())


__all__ = ["Sketch", "SketchMotion", "sketch_motion", "BodyShape", "LinkShape", "Support",
           "Arrow", "Arc", "Label", "sketch", "plain", "name_label",
           "expression_label", "MIN_SIZE", "MIN_LINK"]
