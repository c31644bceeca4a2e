"""Dimension checks of a model with units, on the parsed expressions.

Every name has a :class:`~resonant.model.units.Dimension`, or none where it is
unknown (a parameter given as a bare number, a coordinate without a unit).  The
checker walks the syntax tree of each expression: a sum must add like to like,
the arguments of sin, cos, exp, ... must be dimensionless (radians are), an
exponent of a quantity with a unit must be a number, and at the top T and U must
be energies, D a power, and a force times the displacement of its point (a
generalized force times its coordinate) a work.  A literal 0 fits any unit.  A term
that holds a name of unknown dimension is not checked; the checker says once which
quantities it could not check.

Examples
--------
>>> from resonant.expressions import parse
>>> from resonant.model.units import parse_unit
>>> dims = {"k": parse_unit("N/m").dimension, "x1": parse_unit("m").dimension,
...         "m2": parse_unit("kg").dimension, "g": parse_unit("m/s^2").dimension,
...         "l": parse_unit("m").dimension}
>>> checker = Checker(dims, "model.toml")
>>> checker.expect(parse("k*x1^2/2 - m2*g"), "energy", "U", ENERGY)
>>> print(checker.problems[0])
model.toml: [energy] U: k*x1^2/2 is J but m2*g is N: the terms of a sum must have the same unit
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from ..errors import Problem, name_list
from ..expressions import BinOp, Call, Expression, Name, Neg, Num
from ..expressions.parser import Node
from .dimension_inference import infer_dimensions
from .units import (
    DIMENSIONLESS,
    ENERGY,
    FORCE,
    FREQUENCY,
    POWER,
    TIME,
    Dimension,
    ModelUnits,
    Unit,
    frozen,
)

#: longest term quoted in a message
_TERM_LIMIT = 60


@dataclass(frozen=True)
class _Value:
    """The dimension of a subexpression: known, unknown (None) or any (a literal 0)."""

    dim: Dimension | None
    any: bool = False


_ZERO = _Value(None, True)
_NUMBER = _Value(DIMENSIONLESS)


class DimensionMismatch(Exception):
    """Two terms disagree, or a term has the wrong unit (the message says which)."""


_PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2, "neg": 3, "^": 4}


def node_text(node: Node, limit: int | None = _TERM_LIMIT) -> str:
    """A subexpression as text (``k*x1^2/2``), shortened to ``limit`` characters.

    Examples
    --------
    >>> from resonant.expressions import parse
    >>> node_text(parse("(a + b)*c^2 - -d").root)
    '(a + b)*c^2 - -d'
    """
    text = _text(node, 0)
    if limit is not None and len(text) > limit:
        text = text[:limit - 3] + "..."
    return text


def _chain(node: Node, ops: str) -> list[tuple[str, Node]]:
    """A left-associated chain ``a + b - c`` as ``[('+', a), ('+', b), ('-', c)]``."""
    items: list[tuple[str, Node]] = []
    while isinstance(node, BinOp) and node.op in ops:
        items.append((node.op, node.right))
        node = node.left
    items.append((ops[0], node))
    return items[::-1]


def _text(node: Node, outer: int) -> str:
    if isinstance(node, Num):
        return node.value
    if isinstance(node, Name):
        return node.name + "'" * node.primes
    if isinstance(node, Call):
        return f"{node.func}({', '.join(_text(a, 0) for a in node.args)})"
    if isinstance(node, Neg):
        text, own = "-" + _text(node.operand, _PRECEDENCE["neg"]), _PRECEDENCE["neg"]
    elif node.op in "+-":
        items = _chain(node, "+-")
        text = _text(items[0][1], 1) + "".join(
            f" {op} {_text(item, 2 if op == '-' else 1)}" for op, item in items[1:])
        own = 1
    elif node.op in "*/":
        items = _chain(node, "*/")
        text = _text(items[0][1], 2) + "".join(
            f"{op}{_text(item, 3 if op == '/' else 2)}" for op, item in items[1:])
        own = 2
    else:
        text = f"{_text(node.left, 5)}^{_text(node.right, 4)}"
        own = 4
    return f"({text})" if own < outer else text


def _constant(node: Node) -> Fraction | None:
    """The value of a constant exponent (``2``, ``-1``, ``1/2``, ``(3)``), else None."""
    if isinstance(node, Num):
        try:
            return Fraction(node.value)
        except (ValueError, OverflowError):
            return None
    if isinstance(node, Neg):
        inner = _constant(node.operand)
        return None if inner is None else -inner
    if isinstance(node, BinOp) and node.op in "*/+-":
        a, b = _constant(node.left), _constant(node.right)
        if a is None or b is None or (node.op == "/" and b == 0):
            return None
        return {"*": a * b, "/": a / b if b else a, "+": a + b, "-": a - b}[node.op]
    return None


def _unit(dim: Dimension) -> str:
    return dim.text()


class Checker:
    """Checks expressions against the dimensions of the names, collecting problems.

    Parameters
    ----------
    dimensions : mapping
        name -> Dimension, or None where unknown.  Grows as signals, definitions and
        outputs are inferred (:meth:`infer`).
    source : str
        The model file, for the problems.
    """

    def __init__(self, dimensions: Mapping[str, Dimension | None], source: str) -> None:
        self.dimensions: dict[str, Dimension | None] = dict(dimensions)
        self.source = source
        self.problems: list[Problem] = []
        #: quantity label -> names of unknown dimension it uses (not fully checked)
        self.unchecked: dict[str, set[str]] = {}
        self._unknown: set[str] = set()
        #: an inferred name of unknown dimension -> the names without unit behind it
        self.roots: dict[str, set[str]] = {}

    # -- walking ----------------------------------------------------------------------
    def value(self, node: Node) -> _Value:
        if isinstance(node, Num):
            return _ZERO if float(node.value) == 0 else _NUMBER
        if isinstance(node, Name):
            if node.name == "pi":
                return _Value(DIMENSIONLESS)
            dim = TIME if node.name == "t" else self.dimensions.get(node.name)
            if dim is None:
                self._unknown.update(self.roots.get(node.name, {node.name}))
                return _Value(None)
            return _Value(dim / TIME ** node.primes if node.primes else dim)
        if isinstance(node, Neg):
            return self.value(node.operand)
        if isinstance(node, Call):
            return self.call(node)
        if node.op in "+-":
            return self.sum([item for _, item in _chain(node, "+-")])
        if node.op in "*/":
            return self.product(_chain(node, "*/"))
        return self.power(node)

    def sum(self, terms: list[Node]) -> _Value:
        first: tuple[Node, Dimension] | None = None
        unknown = False
        for term in terms:
            value = self.value(term)
            if value.any:
                continue
            if value.dim is None:
                unknown = True
                continue
            if first is None:
                first = (term, value.dim)
            elif value.dim != first[1]:
                raise DimensionMismatch(
                    f"{node_text(first[0])} is {_unit(first[1])} but {node_text(term)} is "
                    f"{_unit(value.dim)}: the terms of a sum must have the same unit")
        if first is not None:
            return _Value(first[1])
        return _Value(None) if unknown else _Value(None, True)

    def product(self, items: list[tuple[str, Node]]) -> _Value:
        dim, unknown, zero = DIMENSIONLESS, False, False
        for op, item in items:
            value = self.value(item)
            if value.any and op == "*":
                zero = True
            elif value.dim is None:
                unknown = unknown or not value.any
            else:
                dim = dim * value.dim if op == "*" else dim / value.dim
        if zero:
            return _Value(None, True)
        return _Value(None) if unknown else _Value(dim)

    def power(self, node: BinOp) -> _Value:
        base, exponent = self.value(node.left), self.value(node.right)
        if exponent.dim is not None and not exponent.dim.dimensionless:
            raise DimensionMismatch(
                f"the exponent {node_text(node.right)} is {_unit(exponent.dim)}: an exponent "
                "must be dimensionless")
        if base.any or base.dim is None:
            return base
        if base.dim.dimensionless:
            return base
        power = _constant(node.right)
        if power is None:
            raise DimensionMismatch(
                f"{node_text(node.left)} is {_unit(base.dim)}: a quantity with a unit can "
                f"only be raised to a constant number, not to {node_text(node.right)}")
        return _Value(base.dim ** power)

    def call(self, node: Call) -> _Value:
        values = [self.value(a) for a in node.args]
        if node.func == "sqrt":
            value = values[0]
            return value if value.any or value.dim is None else _Value(value.dim ** Fraction(1, 2))
        if node.func == "atan2":
            self.sum(list(node.args))
            return _Value(DIMENSIONLESS)
        for arg, value in zip(node.args, values):
            if value.dim is not None and not value.dim.dimensionless:
                raise DimensionMismatch(
                    f"the argument of {node.func}() must be dimensionless (an angle in rad) "
                    f"but {node_text(arg)} is {_unit(value.dim)}")
        return _Value(DIMENSIONLESS)

    # -- checks -------------------------------------------------------------------------
    def _run(self, expression: Expression, section: str, key: str, label: str
             ) -> _Value | None:
        self._unknown = set()
        try:
            value = self.value(expression.root)
        except DimensionMismatch as exc:
            self.problems.append(Problem(str(exc), self.source, section, key))
            return None
        except RecursionError:
            return _Value(None)
        if self._unknown:
            self.unchecked.setdefault(label, set()).update(self._unknown)
        return value

    def infer(self, name: str, expression: Expression, section: str) -> Dimension | None:
        """Check ``expression`` and record its dimension as that of ``name``."""
        value = self._run(expression, section, name, f"{name} ([{section}])")
        dim = None if value is None or value.any else value.dim
        self.dimensions[name] = dim
        if dim is None:
            self.roots[name] = set(self._unknown) or {name}
        return dim

    def expect(self, expression: Expression, section: str, key: str, wanted: Dimension,
               what: str = "", label: str = "") -> None:
        """Check ``expression`` and that its dimension is ``wanted``."""
        value = self._run(expression, section, key, label or key)
        if value is None or value.any or value.dim is None or value.dim == wanted:
            return
        kind = what or {ENERGY: "an energy", POWER: "a power",
                        FREQUENCY: "an angular frequency"}.get(wanted, "")
        self.problems.append(Problem(
            f"{node_text(expression.root)} is {_unit(value.dim)} but {key} must be "
            f"{kind} ({wanted.text()})", self.source, section, key))

    def work(self, force: Expression, displacement: Expression, section: str, key: str,
             where: str, label: str) -> None:
        """A force (or torque) component times the displacement it acts along is a work."""
        f = self._run(force, section, key, label)
        d = self._run(displacement, section, key, label)
        if f is None or d is None or f.any or d.any or f.dim is None or d.dim is None:
            return
        if f.dim * d.dim == ENERGY:
            return
        wanted = ENERGY / d.dim
        kind = "a moment" if d.dim.dimensionless else "a force" if wanted == FORCE \
            else "a generalized force"
        self.problems.append(Problem(
            f"{node_text(force.root)} is {f.dim.text(moment=True)} but {where} "
            f"{node_text(displacement.root)} is "
            f"{'an angle (rad)' if d.dim.dimensionless else _unit(d.dim)}: it must be {kind} "
            f"({wanted.text(moment=True)}), since a force times the displacement it acts "
            "along is a work (J)",
            self.source, section, key))

    def note(self) -> str | None:
        """The one note on what could not be checked (None if everything was)."""
        if not self.unchecked:
            return None
        names = sorted(set().union(*self.unchecked.values()))
        return (f"units: could not check {name_list(self.unchecked, limit=8)}: "
                f"{name_list(names, limit=8)} {'has' if len(names) == 1 else 'have'} no "
                "unit (a bare number is taken as SI with an unknown dimension)")


#: the unit of an entry (i, j) of M, C, K times the units of q_i and q_j
_MATRIX_SCALE = {"M": ENERGY * TIME ** 2, "C": ENERGY * TIME, "K": ENERGY}


def _matrix_uses(matrices: object, q: Sequence[Dimension | None], coordinates: Sequence[str]
                 ) -> list[tuple[str, str, Expression, Dimension, str]]:
    """The inline entries of ``[matrices]`` and the harmonics' loads that are expressions of
    parameters, with the dimension each must have: ``(section, key, expression, dimension,
    what)``.  (M q'')_i, (C q')_i, (K q)_i and F_i are generalized forces, so M_ij q_i q_j
    has the unit of J s^2, C_ij q_i q_j of J s, K_ij q_i q_j of J and F_i q_i of J.  Plain
    numbers are SI of unknown dimension (as bare parameter values) and entries read from
    files are numbers: neither is judged."""
    uses = []
    for key, scale in _MATRIX_SCALE.items():
        rows = getattr(matrices, key, None)
        if not isinstance(rows, list):
            continue
        for i, row in enumerate(rows[:len(q)]):
            for j, entry in enumerate(row[:len(q)]):
                qi, qj = q[i], q[j]
                if qi is None or qj is None or not entry.names():
                    continue
                uses.append(("matrices", f"{key}[{i + 1}][{j + 1}]", entry, scale / (qi * qj),
                             f"the {key} entry of ({coordinates[i]}, {coordinates[j]})"))
    for number, harmonic in enumerate(getattr(matrices, "harmonics", ()), start=1):
        for key in ("F_S", "F_C"):
            for j, entry in enumerate(getattr(harmonic, key)[:len(q)]):
                qj = q[j]
                if qj is None or not entry.names():
                    continue
                uses.append((f"harmonic {number}", f"{key}[{j + 1}]", entry, ENERGY / qj,
                             f"the generalized force on {coordinates[j]}"))
    return uses


def _check_matrices(checker: Checker, matrices: object, q: Sequence[Dimension | None],
                    coordinates: Sequence[str]) -> None:
    """The inline matrix entries and harmonic loads against the coordinates' units."""
    for section, key, entry, wanted, what in _matrix_uses(matrices, q, coordinates):
        checker.expect(entry, section, key, wanted, what=what)


def check_units(source: str, parameters: Mapping[str, Expression],
                given: Mapping[str, tuple[Expression, Unit]],
                coordinate_units: Mapping[str, Unit], output_units: Mapping[str, Unit],
                display: Mapping[str, Unit], equilibrium: Mapping[str, Expression],
                signals: Mapping[str, Expression], definitions: Mapping[str, Expression],
                energy: Mapping[str, Expression], forces: Iterable[Any],
                outputs: Mapping[str, Expression], matrices: object = None,
                coordinates: Sequence[str] = ()) -> tuple[ModelUnits, list[Problem]]:
    """Infer every name's dimension and check the model's expressions (the loader's step).

    Returns the model's :class:`~resonant.model.units.ModelUnits` (with the notes on
    what could not be checked, and on values in Hz used as angular frequencies) and the
    problems found.
    """
    inferred = _inferred(source, parameters, given, coordinate_units, equilibrium, signals,
                         definitions, energy, forces, matrices, coordinates)
    checker = Checker({}, source)
    _parameter_dimensions(checker, parameters, given, inferred)
    for name, unit in coordinate_units.items():
        checker.dimensions[name] = unit.dimension
    for name, expression in equilibrium.items():
        dim = checker.dimensions.get(name)
        if dim is not None:
            checker.expect(expression, "equilibrium", name, dim, what=f"in the unit of {name}")
    for name, expression in signals.items():
        checker.infer(name, expression, "signals")
    for name, expression in definitions.items():
        checker.infer(name, expression, "definitions")
    for key, expression in energy.items():
        checker.expect(expression, "energy", key, POWER if key == "D" else ENERGY)
    _check_forces(checker, forces)
    if matrices is not None:
        _check_matrices(checker, matrices, [checker.dimensions.get(q) if q in coordinate_units
                                            else None for q in coordinates], coordinates)
    _check_outputs(checker, outputs, output_units)
    cyclic = {name for name, (_, unit) in given.items() if unit.cyclic}
    uses = [(f"[signals] {n}", e) for n, e in signals.items()] + \
        [(f"[definitions] {n}", e) for n, e in definitions.items()] + \
        [(f"[energy] {k}", e) for k, e in energy.items()] + \
        [(f"[{f.kind} '{f.name}']", e) for f in forces for e in (*f.vector,
                                                              *f.generalized.values())]
    notes = [*cyclic_uses(uses, cyclic), *_harmonic_notes(checker, matrices, cyclic)]
    found = {name: dim for name in parameters if (dim := inferred.get(name)) is not None}
    if found:
        notes.append("units: inferred from their uses: " + ", ".join(
            f"{name} in {dim.text() if not dim.dimensionless else '1 (dimensionless)'}"
            for name, dim in found.items()))
    contradicted = [name for name in parameters if name in inferred and inferred[name] is None]
    if contradicted:
        notes.append(f"units: the uses of {', '.join(contradicted)} contradict each other (no "
                     "one dimension fits them all): check the terms that hold them")
    note = checker.note()
    if note:
        notes.insert(0, note)
    units = ModelUnits(**frozen(given=given, dimensions=checker.dimensions,
                                coordinates=coordinate_units, outputs=output_units,
                                display=display), notes=tuple(notes))
    return units, checker.problems


def _parameter_dimensions(checker: Checker, parameters: Mapping[str, Expression],
                          given: Mapping[str, tuple[Expression, Unit]],
                          inferred: Mapping[str, Dimension | None]) -> None:
    """Each parameter's dimension: from its unit, from the parameters it is made of, from
    its uses (a bare number, :mod:`resonant.model.dimension_inference`), or unknown."""
    for name, expression in parameters.items():
        if name in given:
            written, unit = given[name]
            checker._unknown = set()
            try:
                value = checker.value(written.root)
            except DimensionMismatch as exc:
                checker.problems.append(Problem(str(exc), checker.source, "parameters", name))
                value = _Value(None)
            if value.dim is None and not value.any and written.names():
                checker.roots[name] = set(checker._unknown)
                checker.dimensions[name] = None
            else:  # a number (or an expression of numbers) with its unit
                own = value.dim if value.dim is not None else DIMENSIONLESS
                checker.dimensions[name] = own * unit.dimension
        elif expression.names():
            checker.infer(name, expression, "parameters")
        else:  # a bare number: SI, of the dimension its uses imply (or unknown)
            checker.dimensions[name] = inferred.get(name)


def _inferred(source: str, parameters: Mapping[str, Expression],
              given: Mapping[str, tuple[Expression, Unit]],
              coordinate_units: Mapping[str, Unit], equilibrium: Mapping[str, Expression],
              signals: Mapping[str, Expression], definitions: Mapping[str, Expression],
              energy: Mapping[str, Expression], forces: Iterable[Any], matrices: object = None,
              coordinates: Sequence[str] = ()) -> dict[str, Dimension | None]:
    """The dimensions of the bare-number parameters that the model's physics determines
    (the inline matrices' entries, harmonic loads and frequencies are uses too)."""
    scratch = Checker({}, source)
    _parameter_dimensions(scratch, parameters, given, {})
    bare = [n for n, e in parameters.items() if n not in given and not e.names()]
    defined = [("parameters", n, e) for n, e in parameters.items()
               if n not in given and e.names()]
    defined += [("signals", n, e) for n, e in signals.items()]
    defined += [("definitions", n, e) for n, e in definitions.items()]
    known = {n: d for n, d in scratch.dimensions.items() if n in given}
    known.update({n: u.dimension for n, u in coordinate_units.items()})
    constraints = [(e, POWER if key == "D" else ENERGY) for key, e in energy.items()]
    constraints += [(e, coordinate_units[n].dimension) for n, e in equilibrium.items()
                    if n in coordinate_units]
    for force in forces:
        pairs = [(e, Expression(q, Name(q), ("", "", ""))) for q, e in force.generalized.items()]
        pairs += list(zip(force.vector, force.point))
        constraints += [(Expression("", BinOp("*", f.root, d.root), ("", "", "")), ENERGY)
                        for f, d in pairs]
    if matrices is not None:
        q = [coordinate_units[c].dimension if c in coordinate_units else None
             for c in coordinates]
        constraints += [(e, wanted) for _, _, e, wanted, _ in _matrix_uses(matrices, q,
                                                                           coordinates)]
        constraints += [(h.omega, FREQUENCY) for h in getattr(matrices, "harmonics", ())]
    return infer_dimensions(known, bare, defined, constraints)


def _check_forces(checker: Checker, forces: Iterable[Any]) -> None:
    """Each force's virtual work has the dimension of an energy."""
    for force in forces:
        section = f"{force.kind} '{force.name}'"
        for coord, expression in force.generalized.items():
            displacement = Expression(coord, Name(coord), ("", "", ""))
            checker.work(expression, displacement, section, f"generalized.{coord}",
                         "its coordinate", section)
        for j, (component, point) in enumerate(zip(force.vector, force.point)):
            if force.kind == "torque":  # a moment acting on its body's angle
                checker.work(component, point, section, "moment", "its body's angle",
                             section)
            else:
                checker.work(component, point, section, f"vector[{j}]",
                             f"its point's position point[{j}] =", section)


def _check_outputs(checker: Checker, outputs: Mapping[str, Expression],
                   output_units: Mapping[str, Unit]) -> None:
    """Each output's dimension, against the unit it is to be shown in."""
    for name, expression in outputs.items():
        dim = checker.infer(name, expression, "outputs")
        shown = output_units.get(name)
        if shown is not None and dim is not None and dim != shown.dimension:
            checker.problems.append(Problem(
                f"{node_text(expression.root)} is {dim.text()} but its unit "
                f"{shown.text} is {shown.dimension.text()}", checker.source, "outputs", name))


def _harmonic_notes(checker: Checker, matrices: object, cyclic: set[str]) -> list[str]:
    """Each harmonic's omega is a frequency; a note where it is a value in Hz."""
    notes = []
    for i, harmonic in enumerate(getattr(matrices, "harmonics", ()), start=1):
        checker.expect(harmonic.omega, f"harmonic {i}", "omega", FREQUENCY)
        if {n for n, _ in harmonic.omega.names()} & cyclic and "pi" not in harmonic.omega.text:
            notes.append(
                f"[[harmonic]] {i}: omega = {harmonic.omega.text} is given in Hz, a "
                "cyclic frequency, but omega is an angular frequency: resonant keeps a "
                "value in Hz as its number (1/s); write 2*pi*f or give it in rad/s "
                "(docs/units.md)")
    return notes


def cyclic_uses(expressions: Iterable[tuple[str, Expression]], cyclic: set[str]) -> list[str]:
    """Warnings where a parameter in Hz multiplies t directly inside sin/cos/tan/exp.

    ``f = "50 Hz"`` is 50 cycles per second; ``sin(f*t)`` takes it as 50 rad/s.
    """
    if not cyclic:
        return []
    found: dict[str, str] = {}
    for where, expression in expressions:
        stack: list[Node] = [expression.root]
        while stack:
            node = stack.pop()
            if isinstance(node, Call):
                for arg in node.args:
                    for _, term in _chain(arg, "+-"):
                        factors = {n.name for _, n in _chain(term, "*/") if isinstance(n, Name)}
                        if "t" in factors and "pi" not in factors:
                            for name in sorted(factors & cyclic):
                                found.setdefault(name, f"{node.func}({node_text(arg)}) in {where}")
                stack.extend(node.args)
            elif isinstance(node, BinOp):
                stack.extend((node.left, node.right))
            elif isinstance(node, Neg):
                stack.append(node.operand)
    return [f"{name} is given in Hz, a cyclic frequency (cycles per second), but is used as "
            f"an angular frequency in {use}: resonant keeps a value in Hz as its number "
            f"(1/s), so {name}*t turns {name} radians per second, not 2*pi*{name}; write "
            f"2*pi*{name}*t or give {name} in rad/s (docs/units.md)"
            for name, use in found.items()]


__all__ = ["Checker", "DimensionMismatch", "node_text", "cyclic_uses", "check_units"]
