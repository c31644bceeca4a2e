"""A planar mechanism described by its parts (the contract: docs/parts.md).

``gravity``, ``[[point]]``, ``[[body]]``, ``[[spring]]``, ``[[damper]]`` and
``[[torque]]`` are read here into frozen types; :mod:`resonant.model.part_energies`
turns them into T, U, D (the :class:`DerivedEnergies` stored on the model as
``model.parts``).  Every problem is collected with file, section and key, the
section naming the part (``spring "k"`` or ``spring 2``).

Examples
--------
>>> problems = []
>>> parts = read_parts({"body": [{"name": "cart", "mass": "m", "position": ["x", "0"]}]},
...                    params=["m"], allowed=["m", "x"], source="m.toml", problems=problems)
>>> parts.bodies[0].name, parts.bodies[0].position[0].text, problems
('cart', 'x', [])
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ..errors import Problem
from ..expressions import Expression, ExpressionError, parse, validate_name

#: the part sections of a model file (besides the top-level key ``gravity``)
PART_SECTIONS = ("point", "body", "spring", "damper", "torque")
#: how the elongation of a spring or damper is given
ELONGATION_KEYS = ("length", "along", "elongation")
#: the drawing hint ``shape`` of a body (``resonant draw``; not part of the energies)
SHAPES = ("block", "disc", "bar", "point", "none")

Vector = tuple[Expression, Expression]


@dataclass(frozen=True)
class FixedPoint:
    """A ``[[point]]``: a point of the fixed frame, moving if its position holds a signal."""

    name: str
    position: Vector


@dataclass(frozen=True)
class Body:
    """A ``[[body]]``: origin at ``position`` or at the ``pin`` point, turned by ``angle``."""

    name: str
    mass: Expression
    inertia: Expression | None = None
    position: Vector | None = None
    pin: str | None = None
    angle: Expression | None = None
    centre: Vector | None = None
    points: Mapping[str, Vector] = field(default_factory=dict)
    #: drawing hints (an extension, docs/parts.md; used by ``resonant draw`` only):
    #: ``shape`` one of :data:`SHAPES`, ``size`` one or two constants (width [, height]
    #: of a block; radius of a disc or point mass; width of a bar)
    shape: str | None = None
    size: tuple[Expression, ...] = ()


@dataclass(frozen=True)
class Link:
    """A ``[[spring]]`` or ``[[damper]]`` between two points.

    ``mode`` is ``"length"`` (exact geometry, free length ``length``), ``"along"``
    (the change of (B - A) . e), ``"elongation"`` (the given expression) or
    ``"free"`` (exact geometry, free length = the distance at the reference state).
    """

    kind: str
    name: str
    between: tuple[str, str]
    coefficient: Expression
    mode: str
    length: Expression | None = None
    along: Vector | None = None
    elongation: Expression | None = None


@dataclass(frozen=True)
class Torque:
    """A ``[[torque]]``: a moment acting on a body (on its angle)."""

    name: str
    body: str
    moment: Expression


@dataclass(frozen=True)
class Parts:
    """Everything a model file says about its parts, validated for structure."""

    gravity: Expression | None = None
    points: tuple[FixedPoint, ...] = ()
    bodies: tuple[Body, ...] = ()
    springs: tuple[Link, ...] = ()
    dampers: tuple[Link, ...] = ()
    torques: tuple[Torque, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.points or self.bodies or self.springs or self.dampers
                    or self.torques or self.gravity is not None)

    def point_names(self) -> list[str]:
        """Every name that may be used as a point: points, bodies, ``body.P``."""
        names = [p.name for p in self.points] + [b.name for b in self.bodies]
        names += [f"{b.name}.{p}" for b in self.bodies for p in b.points]
        return names


@dataclass(frozen=True)
class Contribution:
    """One part's share of T, U or D (``energy``), as model-language text."""

    kind: str
    name: str
    energy: str
    text: str


@dataclass(frozen=True)
class DerivedEnergies:
    """Parts -> energies: the stage object stored on the model as ``model.parts``.

    Attributes
    ----------
    parts : Parts
        The parts as read.
    contributions : tuple of Contribution
        Each part's T, U or D, in the model's own symbols (``x'`` for a rate).
    derived : mapping
        ``"T"``/``"U"``/``"D"`` -> the sum of the parts' contributions (text).
    written : mapping
        What ``[energy]`` gives (parsed); ``model.energy`` holds the totals.
    positions : mapping
        Every named point -> its ``(x, y)`` in the fixed frame (text).
    centres : mapping
        Every body -> the ``(x, y)`` of its centre of gravity (text).
    angles : mapping
        Every body -> its absolute angle (text).
    force_points : mapping
        ``[[force]]`` name -> the named point it acts on.
    """

    parts: Parts
    contributions: tuple[Contribution, ...]
    derived: Mapping[str, str]
    written: Mapping[str, Expression]
    positions: Mapping[str, tuple[str, str]] = field(default_factory=dict)
    centres: Mapping[str, tuple[str, str]] = field(default_factory=dict)
    angles: Mapping[str, str] = field(default_factory=dict)
    force_points: Mapping[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """``{"T", "U", "D", "parts": [{"kind", "name", "T"|"U"|"D"}]}`` (the derived ones)."""
        return {**{key: self.derived.get(key, "0") for key in ("T", "U", "D")},
                "parts": [{"kind": c.kind, "name": c.name, c.energy: c.text}
                          for c in self.contributions]}


# -- reading -------------------------------------------------------------------------------

_KEYS = {
    "point": ("name", "position"),
    "body": ("name", "mass", "inertia", "position", "pin", "angle", "centre", "points",
             "shape", "size"),
    "spring": ("name", "between", "stiffness", *ELONGATION_KEYS),
    "damper": ("name", "between", "damping", *ELONGATION_KEYS),
    "torque": ("name", "body", "moment"),
}


class _Reader:
    def __init__(self, params: Collection[str], allowed: Collection[str], source: str,
                 problems: list[Problem]) -> None:
        self.params, self.allowed = list(params), list(allowed)
        self.source, self.problems = source, problems

    def problem(self, message: str, section: str, key: str = "") -> None:
        self.problems.append(Problem(message, self.source, section, key))

    def expression(self, value: object, section: str, key: str, constant: bool = False,
                   position: bool = False) -> Expression | None:
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            self.problem(f"expected a number or an expression string, got "
                         f"{type(value).__name__}", section, key)
            return None
        try:
            expression = parse(value, allowed=self.allowed, file=self.source, section=section,
                               key=key)
        except ExpressionError as exc:
            self.problems.extend(exc.problems)
            return None
        varying = sorted(n for n, _ in expression.names() if n not in self.params)
        if constant and varying:
            self.problem(f"{key or section} must be a constant: it may use parameters only, "
                         f"not '{varying[0]}'", section, key)
            return None
        primed = sorted(n + "'" * p for n, p in expression.names() if p)
        if (constant or position) and primed:
            what = "a position (or angle)" if position else key
            self.problem(f"{what} may not depend on a rate ({primed[0]}): it is a "
                         "function of the coordinates and signals only", section, key)
            return None
        return expression

    def vector(self, value: object, section: str, key: str, position: bool = True
               ) -> Vector | None:
        if not isinstance(value, list) or len(value) != 2:
            self.problem(f"{key} must be a list of two expressions [x, y] (the plane)",
                         section, key)
            return None
        x = self.expression(value[0], section, f"{key}[0]", position=position)
        y = self.expression(value[1], section, f"{key}[1]", position=position)
        return (x, y) if x is not None and y is not None else None

    def entries(self, data: Mapping[str, Any], kind: str) -> list[tuple[str, dict]]:
        raw = data.get(kind, [])
        if isinstance(raw, dict):
            raw = [raw]
        if not isinstance(raw, list):
            self.problem(f"[[{kind}]] entries must be tables", kind)
            return []
        out = []
        for i, entry in enumerate(raw, start=1):
            if not isinstance(entry, dict):
                self.problem(f"each [[{kind}]] must be a table", f"{kind} {i}")
                continue
            name = entry.get("name", f"{i}")
            if not isinstance(name, str) or not name:
                self.problem("name must be a non-empty string", f"{kind} {i}", "name")
                name = f"{i}"
            section = f"{kind} {i}" if "name" not in entry else f'{kind} "{name}"'
            for key in entry:
                if key not in _KEYS[kind]:
                    close = difflib.get_close_matches(key, _KEYS[kind], n=1)
                    hint = f"did you mean '{close[0]}'?" if close else \
                        f"a {kind} has {', '.join(_KEYS[kind])}"
                    self.problem(f"unknown key '{key}'; {hint}", section, key)
            out.append((section, {**entry, "name": name}))
        return out


def check_values(parts: Parts, exact_values: Mapping[str, Any], source: str) -> list[Problem]:
    """Masses and inertias that are negative at these parameter values (as problems naming
    the body and the key); used again when parameters are replaced
    (:meth:`resonant.model.Model.with_parameters`).

    Examples
    --------
    >>> from resonant.expressions import parse
    >>> body = Body("cart", parse("m"), position=(parse("x"), parse("0")))
    >>> [p.message for p in check_values(Parts(bodies=(body,)), {"m": -2}, "m.toml")]
    ['the mass is negative (-2); a mass is at least 0']
    """
    import sympy  # noqa: PLC0415 - a third-party library, loaded only when checking

    problems = []
    values = {name: sympy.sympify(value) for name, value in exact_values.items()}
    for index, body in enumerate(parts.bodies, start=1):
        section = f'body "{body.name}"' if body.name != str(index) else f"body {index}"
        for key, expression in (("mass", body.mass), ("inertia", body.inertia)):
            if expression is None:
                continue
            try:
                value = complex(expression.to_sympy(
                    lambda name, primes: values[name] if not primes else 0).evalf(30))
            except (KeyError, TypeError, ValueError, ArithmeticError, ExpressionError):
                continue
            if math.isfinite(value.real) and value.real < 0:
                article = "an" if key[0] in "aeiou" else "a"
                problems.append(Problem(f"the {key} is negative ({value.real:.6g}); {article} "
                                        f"{key} is at least 0", source, section, key))
    return problems


def _hints(reader: _Reader, entry: Mapping[str, Any], section: str
           ) -> tuple[str | None, tuple[Expression, ...]]:
    """The drawing hints ``shape`` and ``size`` of a body (checked, never required)."""
    shape = entry.get("shape")
    if shape is not None and shape not in SHAPES:
        reader.problem(f"shape must be one of {', '.join(SHAPES)} (a drawing hint)", section,
                       "shape")
        shape = None
    raw = entry.get("size")
    if raw is None:
        return shape, ()
    values = raw if isinstance(raw, list) else [raw]
    if not 1 <= len(values) <= 2:
        reader.problem("size is one constant (or [width, height] of a block; a drawing "
                       "hint)", section, "size")
        return shape, ()
    size = tuple(reader.expression(v, section, "size", constant=True) for v in values)
    return shape, tuple(e for e in size if e is not None) if None not in size else ()


class _Names:
    """The names of points and bodies declared so far, each unique and new to the model."""

    def __init__(self, reader: _Reader, model_names: Collection[str]) -> None:
        self.reader, self.model_names = reader, set(model_names)
        self.sections: dict[str, str] = {}  # point or body name -> section

    def declare(self, name: str, section: str) -> bool:
        """Record ``name`` for ``section``; a problem (and False) if it cannot be one."""
        problem = self._refusal(name, section)
        if problem:
            self.reader.problem(problem, section, "name")
            return False
        self.sections[name] = section
        return True

    def _refusal(self, name: str, section: str) -> str | None:
        if section.split()[1:] == [name]:  # no name = "..." given: the section is "body 2"
            return ("a point or body needs a name (name = \"...\"): other parts refer to it "
                    "by name")
        reason = validate_name(name)
        if reason:
            return f"'{name}' cannot be used as a name: {reason}"
        if name in self.model_names:
            return (f"'{name}' is already a name of the model (a parameter, coordinate, "
                    "signal or definition); a point or body needs a name of its own")
        if name in self.sections:
            kind, label = self.sections[name].split(" ", 1)
            return (f"'{name}' is already the name of [[{kind}]] {label}; points and bodies "
                    "need unique names")
        return None


def _read_points(reader: _Reader, names: _Names, data: Mapping[str, Any]) -> list[FixedPoint]:
    points = []
    for section, entry in reader.entries(data, "point"):
        if not names.declare(entry["name"], section):
            continue
        if "position" not in entry:
            reader.problem("a point needs a position = [x, y]", section, "position")
            continue
        position = reader.vector(entry["position"], section, "position")
        if position is not None:
            points.append(FixedPoint(entry["name"], position))
    return points


def _body_points(reader: _Reader, entry: Mapping[str, Any], section: str
                 ) -> dict[str, Vector]:
    """A body's own points ``{ P = ["x", "y"] }`` in its frame."""
    raw_points = entry.get("points", {})
    if not isinstance(raw_points, dict):
        reader.problem("points must be a table { P = [\"x\", \"y\"] } in the body's frame",
                       section, "points")
        return {}
    body_points: dict[str, Vector] = {}
    for pname, value in raw_points.items():
        reason = validate_name(pname)
        if reason:
            reader.problem(f"'{pname}' cannot be used as a point name: {reason}", section,
                           f"points.{pname}")
            continue
        vector = reader.vector(value, section, f"points.{pname}")
        if vector is not None:
            body_points[pname] = vector
    return body_points


def _placement_ok(reader: _Reader, entry: Mapping[str, Any], section: str) -> bool:
    """Exactly one of ``position`` and ``pin``, a pin naming a point by a string."""
    has_position, has_pin = "position" in entry, "pin" in entry
    if has_position == has_pin:
        reader.problem("a body has exactly one of position (a body that translates) and "
                       "pin (a body turning about a point of another)" if has_pin else
                       "a body needs position = [x, y] or pin = \"point\"", section,
                       "pin" if has_pin else "position")
        return False
    if has_pin and not isinstance(entry["pin"], str):
        reader.problem("pin must name a point: \"body\", \"body.P\" or a [[point]]",
                       section, "pin")
        return False
    return True


def _read_body(reader: _Reader, names: _Names, section: str, entry: Mapping[str, Any]
               ) -> Body | None:
    """One ``[[body]]``, or None (its problems recorded) if it cannot be one."""
    ok = names.declare(entry["name"], section)
    if "mass" not in entry:
        reader.problem("a body needs a mass (0 for a massless link)", section, "mass")
    mass = reader.expression(entry.get("mass", 0), section, "mass", constant=True)
    inertia = reader.expression(entry["inertia"], section, "inertia", constant=True) \
        if "inertia" in entry else None
    placed = _placement_ok(reader, entry, section)
    position = reader.vector(entry["position"], section, "position") \
        if "position" in entry else None
    angle = reader.expression(entry["angle"], section, "angle", position=True) \
        if "angle" in entry else None
    centre = reader.vector(entry["centre"], section, "centre") if "centre" in entry else None
    body_points = _body_points(reader, entry, section)
    shape, size = _hints(reader, entry, section)
    complete = ok and placed \
        and (position is not None or "pin" in entry) \
        and ("inertia" not in entry or inertia is not None) \
        and ("angle" not in entry or angle is not None) \
        and ("centre" not in entry or centre is not None)
    if not complete or mass is None:
        return None
    return Body(entry["name"], mass, inertia, position, entry.get("pin"), angle, centre,
                MappingProxyType(body_points), shape, size)


class _PointCheck:
    """Whether a name is a point of the mechanism, with a hint if it is not."""

    def __init__(self, reader: _Reader, points: Sequence[FixedPoint], bodies: Sequence[Body]
                 ) -> None:
        self.reader = reader
        self.fixed = {p.name for p in points}
        self.bodies = {b.name: b for b in bodies}
        self.known = set(Parts(points=tuple(points), bodies=tuple(bodies)).point_names())

    def __call__(self, name: object, section: str, key: str) -> bool:
        if not isinstance(name, str):
            self.reader.problem(f"{key} must name a point (a string)", section, key)
            return False
        if name in self.known:
            return True
        self.reader.problem(f"unknown point '{name}'{self._hint(name)}", section, key)
        return False

    def _hint(self, name: str) -> str:
        owner, _, point = name.partition(".")
        if point and owner in self.bodies and owner not in self.fixed:
            own = self.bodies[owner].points
            return f"; body '{owner}' has no point '{point}'" + \
                (f" (its points: {', '.join(sorted(own))})" if own else "")
        close = difflib.get_close_matches(name, sorted(self.known), n=1)
        return f"; did you mean '{close[0]}'?" if close else \
            f"; known points: {', '.join(sorted(self.known)) or 'none'}"


def _pin_cycles(reader: _Reader, names: _Names, bodies: Sequence[Body]) -> set[str]:
    """The bodies pinned to each other in a cycle (one problem per cycle)."""
    by_name = {b.name: b for b in bodies}
    in_cycle: set[str] = set()
    for body in bodies:
        chain, link = [body.name], body
        while link.pin is not None:
            owner = link.pin.split(".", 1)[0]
            if owner not in by_name:
                break
            if owner in chain:
                cycle = chain[chain.index(owner):] + [owner]
                if not in_cycle.intersection(cycle):
                    reader.problem("bodies are pinned to each other in a cycle: "
                                   + " -> ".join(cycle) + "; one of them needs a position",
                                   names.sections.get(body.name, body.name), "pin")
                in_cycle.update(cycle)
                break
            chain.append(owner)
            link = by_name[owner]
    return in_cycle


def _between(entry: Mapping[str, Any], section: str, reader: _Reader,
             is_point: _PointCheck) -> tuple[str, str] | None:
    between = entry.get("between")
    if not isinstance(between, list) or len(between) != 2:
        reader.problem("between must name two points: between = [\"A\", \"B\"]",
                       section, "between")
        return None
    if not all([is_point(between[0], section, "between[0]"),
                is_point(between[1], section, "between[1]")]):
        return None
    return between[0], between[1]


def _read_link(reader: _Reader, is_point: _PointCheck, kind: str, coefficient_key: str,
               section: str, entry: Mapping[str, Any]) -> Link | None:
    """One ``[[spring]]`` or ``[[damper]]``, or None if it cannot be one."""
    between = _between(entry, section, reader, is_point)
    if coefficient_key not in entry:
        reader.problem(f"a {kind} needs its {coefficient_key}", section, coefficient_key)
    coefficient = reader.expression(entry.get(coefficient_key, 0), section, coefficient_key)
    given = [key for key in ELONGATION_KEYS if key in entry]
    if len(given) > 1:
        reader.problem(f"give at most one of length, along and elongation, not "
                       f"{' and '.join(given)}", section, given[1])
        return None
    mode = given[0] if given else "free"
    length = along = elongation = None
    if mode == "length":
        length = reader.expression(entry["length"], section, "length")
    elif mode == "along":
        along = reader.vector(entry["along"], section, "along", position=False)
    elif mode == "elongation":
        elongation = reader.expression(entry["elongation"], section, "elongation",
                                       position=True)
    if between is None or coefficient is None or \
            (mode != "free" and length is None and along is None and elongation is None):
        return None
    return Link(kind, entry["name"], between, coefficient, mode, length, along, elongation)


def _read_torques(reader: _Reader, data: Mapping[str, Any], known: Collection[str]
                  ) -> list[Torque]:
    torques = []
    for section, entry in reader.entries(data, "torque"):
        body_name = entry.get("body")
        if not isinstance(body_name, str) or body_name not in known:
            reader.problem(f"unknown body {body_name!r}; a torque acts on a [[body]] "
                           f"({', '.join(sorted(known)) or 'none declared'})",
                           section, "body")
            continue
        if "moment" not in entry:
            reader.problem("a torque needs its moment", section, "moment")
            continue
        moment = reader.expression(entry["moment"], section, "moment")
        if moment is not None:
            torques.append(Torque(entry["name"], body_name, moment))
    return torques


def read_parts(data: Mapping[str, Any], params: Collection[str], allowed: Collection[str],
               source: str, problems: list[Problem]) -> Parts:
    """Read and validate the parts of a model file's TOML data.

    ``params`` are the names a constant (mass, inertia, gravity) may use, ``allowed``
    those of any other expression (as for ``[energy]``).  Problems are appended to
    ``problems``; the parts that could be read are returned.
    """
    reader = _Reader(params, allowed, source, problems)
    gravity = reader.expression(data["gravity"], "gravity", "", constant=True) \
        if "gravity" in data else None
    names = _Names(reader, {*params, *allowed})
    points = _read_points(reader, names, data)
    read = [(section, _read_body(reader, names, section, entry))
            for section, entry in reader.entries(data, "body")]
    bodies = [body for _, body in read if body is not None]
    is_point = _PointCheck(reader, points, bodies)
    bodies = [b for b in bodies if b.pin is None
              or is_point(b.pin, names.sections.get(b.name, f'body "{b.name}"'), "pin")]
    in_cycle = _pin_cycles(reader, names, bodies)
    bodies = [b for b in bodies if b.name not in in_cycle]
    links = {kind: tuple(link for section, entry in reader.entries(data, kind)
                         if (link := _read_link(reader, is_point, kind, key, section, entry)))
             for kind, key in (("spring", "stiffness"), ("damper", "damping"))}
    torques = _read_torques(reader, data, is_point.bodies)
    return Parts(gravity, tuple(points), tuple(bodies), links["spring"], links["damper"],
                 tuple(torques))


__all__ = ["PART_SECTIONS", "ELONGATION_KEYS", "SHAPES", "FixedPoint", "Body", "Link", "Torque",
           "Parts", "Contribution", "DerivedEnergies", "read_parts"]
