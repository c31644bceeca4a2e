"""Physical units of a model: unit text, conversion to SI, dimensions, display units.

A parameter value may carry a unit after the number or expression, separated by a
space (``"150 N/mm"``, ``"60 deg"``, ``"2*pi*f"`` needs none).  The unit text is read
by a small tokenizer and parser of this module (names, ``*``, ``/``, ``^`` with integer
exponents, parentheses), never evaluated; each name is looked up in the table
:data:`UNITS` of the usual SI and engineering units and, only for a name not in it, in
pint's registry by that single validated name (pint is imported on first such use,
so neither a model without units nor one with the usual units pays for it).

Every value is converted once, at the model boundary, to SI (angles in rad, rpm to
rad/s); the analyses never see units.  The factor is kept exact where it can be
(``60 deg`` is exactly ``pi/3``), so the symbolic results do not change.

The Hz rule (docs/units.md): ``Hz`` is a *cyclic* frequency, cycles per second; a
value in Hz keeps its number (``50 Hz`` is 50 1/s), it is never silently turned into
an angular frequency.  ``rpm`` (revolutions per minute) holds its 2 pi: ``1200 rpm`` is
125.66 rad/s.  Write ``Omega = "2*pi*f"`` for the angular frequency of ``f = "50 Hz"``;
the loader warns where a parameter in Hz is used directly as an angular frequency.

Examples
--------
>>> u = parse_unit("N/mm")
>>> u.dimension.text(), float(u.factor)
('N/m', 1000.0)
>>> split_value("150 N/mm")
('150', 'N/mm')
>>> split_value("2*pi*f")
('2*pi*f', None)
>>> parse_unit("deg").sympy_factor()
pi/180
>>> float(parse_unit("rpm").factor * 3.141592653589793 ** parse_unit("rpm").pi_power)
0.10471975511965977
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from types import MappingProxyType
from typing import Any

import sympy

from ..expressions import BinOp, Expression, ExpressionError, Name, Num, parse

#: the base dimensions, as their SI units (the order of :attr:`Dimension.exponents`)
BASE = ("m", "kg", "s", "A", "K", "mol", "cd")
#: the order of the base units in a unit's text (kg*m^2/s^2, not m^2*kg/s^2)
_TEXT_ORDER = {"kg": 0, "m": 1, "s": 2, "A": 3, "K": 4, "mol": 5, "cd": 6}
#: longest unit text accepted, and largest exponent magnitude in it
MAX_UNIT_LENGTH = 200
MAX_UNIT_EXPONENT = 12


@dataclass(frozen=True)
class Dimension:
    """A physical dimension: rational exponents of the SI base units.

    Radians are dimensionless (an angle is a ratio of lengths).

    Examples
    --------
    >>> force = Dimension.of(m=1, kg=1, s=-2)
    >>> (force * Dimension.of(m=1)).text(), (force / Dimension.of(m=1)).text()
    ('J', 'N/m')
    >>> (Dimension.of(m=1) ** Fraction(1, 2)).text()
    'm^(1/2)'
    """

    #: ints, or Fractions where a square root made them non-integer (ints are fast)
    exponents: tuple[int | Fraction, ...] = (0,) * len(BASE)

    @staticmethod
    def of(**powers: int | Fraction) -> Dimension:
        """The dimension with the given exponents of the base units (``m=1, s=-1``)."""
        return Dimension(tuple(_exponent(powers.get(b, 0)) for b in BASE))

    def __mul__(self, other: Dimension) -> Dimension:
        return Dimension(tuple(a + b for a, b in zip(self.exponents, other.exponents)))

    def __truediv__(self, other: Dimension) -> Dimension:
        return Dimension(tuple(a - b for a, b in zip(self.exponents, other.exponents)))

    def __pow__(self, power: int | Fraction) -> Dimension:
        if isinstance(power, Fraction) and power.denominator == 1:
            power = power.numerator
        return Dimension(tuple(_exponent(a * power) for a in self.exponents))

    @property
    def dimensionless(self) -> bool:
        return not any(self.exponents)

    def __repr__(self) -> str:
        return f"Dimension({self.text()!r})"

    def text(self, moment: bool = False) -> str:
        """The SI unit of this dimension: a named one (``N``, ``J``, ``N*s/m``) or a
        product of base units (``kg*m^2/s^3``); ``moment`` writes J as ``N*m``."""
        if moment and self == ENERGY:
            return "N*m"
        named = _NAMED.get(self)
        if named is not None:
            return named
        up: list[str] = []
        down: list[str] = []
        for base in sorted(BASE, key=_TEXT_ORDER.__getitem__):
            power = self.exponents[BASE.index(base)]
            if power:
                size = power if power > 0 else -power
                text = base if size == 1 else f"{base}^{size}" if int(size) == size \
                    else f"{base}^({size})"
                (up if power > 0 else down).append(text)
        top = "*".join(up) or "1"
        return top if not down else f"{top}/{down[0]}" if len(down) == 1 else \
            f"{top}/({'*'.join(down)})"


def _exponent(value: int | Fraction) -> int | Fraction:
    """An exponent as an int where it is one (Fraction arithmetic is slow)."""
    if isinstance(value, int):
        return value
    value = Fraction(value)
    return value.numerator if value.denominator == 1 else value


DIMENSIONLESS = Dimension()
LENGTH = Dimension.of(m=1)
MASS = Dimension.of(kg=1)
TIME = Dimension.of(s=1)
FREQUENCY = Dimension.of(s=-1)
FORCE = Dimension.of(m=1, kg=1, s=-2)
ENERGY = Dimension.of(m=2, kg=1, s=-2)
POWER = Dimension.of(m=2, kg=1, s=-3)
VELOCITY = Dimension.of(m=1, s=-1)
ACCELERATION = Dimension.of(m=1, s=-2)
STRESS = Dimension.of(kg=1, m=-1, s=-2)
#: the SI names of common dimensions (everything else is written in base units)
_NAMED: dict[Dimension, str] = {
    DIMENSIONLESS: "1", LENGTH: "m", MASS: "kg", TIME: "s", FREQUENCY: "1/s",
    FORCE: "N", ENERGY: "J", POWER: "W", Dimension.of(m=1, s=-1): "m/s",
    Dimension.of(m=1, s=-2): "m/s^2", Dimension.of(kg=1, s=-2): "N/m",
    Dimension.of(kg=1, s=-1): "N*s/m", Dimension.of(kg=1, m=1, s=-1): "N*s",
    Dimension.of(kg=1, m=2, s=-1): "N*m*s", Dimension.of(kg=1, m=2): "kg*m^2",
    Dimension.of(kg=1, m=1): "kg*m", Dimension.of(kg=1, m=-1, s=-2): "Pa",
    Dimension.of(m=2): "m^2", Dimension.of(m=3): "m^3", Dimension.of(kg=1, m=-3): "kg/m^3",
    Dimension.of(s=-2): "1/s^2",
}


@dataclass(frozen=True)
class Unit:
    """A unit: its text, its SI factor ``factor * pi**pi_power`` and its dimension.

    ``cyclic`` marks Hz-like units (cycles per time), ``angle`` the angle units
    (rad, deg, rev: dimensionless, but shown as angles).
    """

    text: str
    factor: Fraction
    pi_power: int
    dimension: Dimension
    cyclic: bool = False
    angle: bool = False

    def __repr__(self) -> str:
        return f"Unit({self.text!r})"

    def to_si(self) -> float:
        """The SI value of one of this unit."""
        return float(self.factor) * math.pi ** self.pi_power

    def sympy_factor(self) -> sympy.Expr:
        """The exact SI value of one of this unit."""
        return sympy.Rational(self.factor.numerator, self.factor.denominator) \
            * sympy.pi ** self.pi_power

    def __mul__(self, other: Unit) -> Unit:
        return Unit(f"{self.text}*{other.text}", self.factor * other.factor,
                    self.pi_power + other.pi_power, self.dimension * other.dimension,
                    self.cyclic or other.cyclic)

    def __truediv__(self, other: Unit) -> Unit:
        return Unit(f"{self.text}/{other.text}", self.factor / other.factor,
                    self.pi_power - other.pi_power, self.dimension / other.dimension,
                    self.cyclic or other.cyclic)

    def __pow__(self, power: int) -> Unit:
        return Unit(f"{self.text}^{power}", self.factor ** power, self.pi_power * power,
                    self.dimension ** power, self.cyclic, False)


ONE = Unit("1", Fraction(1), 0, DIMENSIONLESS)


def _u(factor: Fraction | int | str, dimension: Dimension, pi_power: int = 0,
       cyclic: bool = False, angle: bool = False) -> tuple[Fraction, int, Dimension, bool, bool]:
    return Fraction(factor), pi_power, dimension, cyclic, angle


_F = Fraction
#: the units understood without pint: name -> (factor, power of pi, dimension, cyclic, angle).
#: tests/test_units.py checks every entry against pint's registry.
UNITS: dict[str, tuple[Fraction, int, Dimension, bool, bool]] = {
    # length
    "m": _u(1, LENGTH), "km": _u(1000, LENGTH), "dm": _u(_F(1, 10), LENGTH),
    "cm": _u(_F(1, 100), LENGTH), "mm": _u(_F(1, 1000), LENGTH),
    "um": _u(_F(1, 10**6), LENGTH), "µm": _u(_F(1, 10**6), LENGTH),
    "μm": _u(_F(1, 10**6), LENGTH), "nm": _u(_F(1, 10**9), LENGTH),
    "in": _u("0.0254", LENGTH), "inch": _u("0.0254", LENGTH), "ft": _u("0.3048", LENGTH),
    "foot": _u("0.3048", LENGTH), "yd": _u("0.9144", LENGTH),
    # mass
    "kg": _u(1, MASS), "g": _u(_F(1, 1000), MASS), "mg": _u(_F(1, 10**6), MASS),
    "t": _u(1000, MASS), "tonne": _u(1000, MASS), "lb": _u("0.45359237", MASS),
    "oz": _u("0.028349523125", MASS),
    # time
    "s": _u(1, TIME), "ms": _u(_F(1, 1000), TIME), "us": _u(_F(1, 10**6), TIME),
    "min": _u(60, TIME), "h": _u(3600, TIME),
    # frequency: Hz is cyclic (kept as its number), rpm holds its 2 pi
    "Hz": _u(1, FREQUENCY, cyclic=True), "kHz": _u(1000, FREQUENCY, cyclic=True),
    "rpm": _u(_F(1, 30), FREQUENCY, 1), "rps": _u(2, FREQUENCY, 1),
    # angle
    "rad": _u(1, DIMENSIONLESS, angle=True), "mrad": _u(_F(1, 1000), DIMENSIONLESS, angle=True),
    "deg": _u(_F(1, 180), DIMENSIONLESS, 1, angle=True),
    "degree": _u(_F(1, 180), DIMENSIONLESS, 1, angle=True),
    "°": _u(_F(1, 180), DIMENSIONLESS, 1, angle=True),
    "rev": _u(2, DIMENSIONLESS, 1, angle=True), "revolution": _u(2, DIMENSIONLESS, 1, angle=True),
    "turn": _u(2, DIMENSIONLESS, 1, angle=True),
    # force
    "N": _u(1, FORCE), "mN": _u(_F(1, 1000), FORCE), "kN": _u(1000, FORCE),
    "MN": _u(10**6, FORCE), "lbf": _u("4.4482216152605", FORCE), "kgf": _u("9.80665", FORCE),
    # energy, power
    "J": _u(1, ENERGY), "mJ": _u(_F(1, 1000), ENERGY), "kJ": _u(1000, ENERGY),
    "W": _u(1, POWER), "mW": _u(_F(1, 1000), POWER), "kW": _u(1000, POWER),
    "MW": _u(10**6, POWER),
    # pressure, stiffness of materials
    "Pa": _u(1, Dimension.of(kg=1, m=-1, s=-2)), "kPa": _u(1000, Dimension.of(kg=1, m=-1, s=-2)),
    "MPa": _u(10**6, Dimension.of(kg=1, m=-1, s=-2)),
    "GPa": _u(10**9, Dimension.of(kg=1, m=-1, s=-2)),
    "bar": _u(10**5, Dimension.of(kg=1, m=-1, s=-2)),
    "Nm": _u(1, ENERGY), "kNm": _u(1000, ENERGY),  # N*m (pint reads Nm otherwise)
    # dimensionless
    "dimensionless": _u(1, DIMENSIONLESS), "percent": _u(_F(1, 100), DIMENSIONLESS),
}


class UnitError(ValueError):
    """A unit text is invalid (the message says why, in words)."""


# -- reading unit text ---------------------------------------------------------------------

_UNIT_TOKEN = re.compile(r"(?P<ws>\s+)|(?P<int>[0-9]+)|(?P<name>[A-Za-z_µμ°][A-Za-z0-9_µμ]*)"
                         r"|(?P<op>\*\*|[*/^()·⋅-])")
#: the expression's tokens, to find where the unit starts (see split_value)
_VALUE_TOKEN = re.compile(r"(?P<ws>\s+)|(?P<num>(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)"
                          r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*'*)|(?P<op>\*\*|[-+*/^(),])")


def split_value(text: str) -> tuple[str, str | None]:
    """Split ``"value unit"`` into the expression and the unit text (None without one).

    The unit starts at the first number, name or other character that follows a
    complete operand (a number, a name or ``)``) after a space, outside parentheses:
    the expression language has no implicit product, so that place is unambiguous.

    Examples
    --------
    >>> split_value("0.1 N/mm"), split_value("(m1 + m2) kg"), split_value("m1 + m2")
    (('0.1', 'N/mm'), ('(m1 + m2)', 'kg'), ('m1 + m2', None))
    >>> split_value("60 °")
    ('60', '°')
    """
    pos, depth, previous_operand, spaced = 0, 0, False, False
    while pos < len(text):
        m = _VALUE_TOKEN.match(text, pos)
        if m is not None and m.group("ws"):
            spaced, pos = True, m.end()
            continue
        starts_operand = m is None or bool(m.group("num") or m.group("name"))
        if depth == 0 and previous_operand and spaced and starts_operand:
            return text[:pos].rstrip(), text[pos:].strip()
        if m is None:
            break
        tok = m.group()
        depth += (tok == "(") - (tok == ")")
        previous_operand = bool(m.group("num") or m.group("name")) or tok == ")"
        spaced, pos = False, m.end()
    return text, None


class _UnitParser:
    """unit := factor (('*' | '/') factor)*;  factor := atom ('^' int)?;
    atom := NAME | '1' | '(' unit ')';  int := '-'? DIGITS | '(' '-'? DIGITS ')'."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.tokens: list[tuple[str, str]] = []
        pos = 0
        while pos < len(text):
            m = _UNIT_TOKEN.match(text, pos)
            if m is None:
                raise UnitError(f"unexpected character {text[pos]!r} in the unit "
                                f"'{text}' (a unit is made of unit names, *, / and ^)")
            if not m.group("ws"):
                kind = next(k for k in ("int", "name", "op") if m.group(k))
                tok = m.group()
                self.tokens.append((kind, "*" if tok in "·⋅" else "^" if tok == "**" else tok))
            pos = m.end()
        self.tokens.append(("end", ""))
        self.i = 0
        self.depth = 0

    def peek(self) -> tuple[str, str]:
        return self.tokens[self.i]

    def take(self) -> tuple[str, str]:
        self.i += 1
        return self.tokens[self.i - 1]

    def parse(self) -> Unit:
        if self.peek()[0] == "end":
            raise UnitError("empty unit")
        unit = self.product()
        if self.peek()[0] != "end":
            raise UnitError(f"unexpected {self.peek()[1]!r} in the unit '{self.text}'")
        return unit

    def product(self) -> Unit:
        unit = self.factor()
        while self.peek()[1] in ("*", "/"):
            op = self.take()[1]
            right = self.factor()
            unit = unit * right if op == "*" else unit / right
        return unit

    def factor(self) -> Unit:
        kind, tok = self.take()
        if tok == "(":
            self.depth += 1
            if self.depth > 10:
                raise UnitError("unit nested too deeply")
            inner = self.product()
            if self.take()[1] != ")":
                raise UnitError(f"unclosed '(' in the unit '{self.text}'")
            self.depth -= 1
            unit = Unit(f"({inner.text})", inner.factor, inner.pi_power, inner.dimension,
                        inner.cyclic, inner.angle)
        elif kind == "int" and tok == "1":
            unit = ONE
        elif kind == "name":
            unit = lookup(tok)
        else:
            raise UnitError(f"expected a unit name in '{self.text}', found "
                            f"{tok!r}" if tok else f"the unit '{self.text}' ends too early")
        if self.peek()[1] == "^":
            self.take()
            unit = unit ** self.exponent()
        return unit

    def exponent(self) -> int:
        paren = self.peek()[1] == "("
        if paren:
            self.take()
        sign = -1 if self.peek()[1] == "-" else 1
        if sign < 0:
            self.take()
        kind, tok = self.take()
        if kind != "int":
            raise UnitError(f"the exponent of a unit must be an integer ('{self.text}')")
        if paren and self.take()[1] != ")":
            raise UnitError(f"unclosed '(' in the unit '{self.text}'")
        value = sign * int(tok[:4])
        if abs(value) > MAX_UNIT_EXPONENT or len(tok) > 3:
            raise UnitError(f"unit exponent too large (at most {MAX_UNIT_EXPONENT})")
        return value


@lru_cache(maxsize=512)
def parse_unit(text: str) -> Unit:
    """The unit of a unit text such as ``"N*s/m"`` or ``"kg*m^2"``.

    Raises
    ------
    UnitError
        If the text is not a product of known units with integer exponents.

    Examples
    --------
    >>> parse_unit("kg*m^2").dimension.text()
    'kg*m^2'
    >>> parse_unit("N*m").dimension == ENERGY
    True
    >>> try:
    ...     parse_unit("N/mmm")
    ... except UnitError as err:
    ...     print(err)
    unknown unit 'mmm'; did you mean 'mm'?
    """
    if len(text) > MAX_UNIT_LENGTH:
        raise UnitError(f"unit text too long (at most {MAX_UNIT_LENGTH} characters)")
    unit = _UnitParser(text).parse()
    return Unit(text, unit.factor, unit.pi_power, unit.dimension, unit.cyclic, unit.angle)


def lookup(name: str) -> Unit:
    """One unit name: the table :data:`UNITS`, else pint's registry (by that name only)."""
    entry = UNITS.get(name)
    if entry is not None:
        return Unit(name, *entry)
    return _pint_unit(name)


@lru_cache(maxsize=256)
def _pint_unit(name: str) -> Unit:
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", name):
        raise UnitError(f"unknown unit '{name}'")
    registry = _registry()
    try:
        candidates = registry.parse_unit_name(name)
    except Exception:  # noqa: BLE001 - pint's own errors: an unknown name
        candidates = ()
    if not candidates:
        close = difflib.get_close_matches(name, list(UNITS), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else " (docs/units.md lists the units)"
        raise UnitError(f"unknown unit '{name}'{hint}")
    try:
        unit = registry.Unit(name)
        if not registry._units[candidates[0][1]].is_multiplicative:
            raise UnitError(f"'{name}' has an offset (like a temperature scale); "
                            "give the value in a unit without one")
        quantity = registry.Quantity(1, unit).to_base_units()
        dims = dict(quantity.dimensionality)
    except UnitError:
        raise
    except Exception as exc:  # noqa: BLE001 - pint refused it
        raise UnitError(f"unknown unit '{name}' ({type(exc).__name__})") from None
    order = {"[length]": "m", "[mass]": "kg", "[time]": "s", "[current]": "A",
             "[temperature]": "K", "[substance]": "mol", "[luminosity]": "cd"}
    if set(dims) - set(order):
        raise UnitError(f"'{name}' has a dimension resonant does not know ({dims})")
    powers = {order[k]: Fraction(v).limit_denominator(12) for k, v in dims.items()}
    magnitude = float(quantity.magnitude)
    if not math.isfinite(magnitude) or magnitude <= 0:
        raise UnitError(f"unit '{name}' has no positive SI factor")
    return Unit(name, Fraction(repr(magnitude)), 0, Dimension.of(**powers))


@lru_cache(maxsize=1)
def _registry() -> Any:
    """pint's unit registry, made on first use (pint is imported here, lazily)."""
    import pint  # a heavy library: imported only for a unit outside the table

    return pint.UnitRegistry()


def scaled(expression: Expression, unit: Unit, text: str) -> Expression:
    """``expression`` times the SI factor of ``unit``, keeping ``text`` as its text.

    Examples
    --------
    >>> from resonant.expressions import parse
    >>> e = scaled(parse("60"), parse_unit("deg"), "60 deg")
    >>> e.text, e.to_sympy(lambda n, p: sympy.Symbol(n))
    ('60 deg', pi/3)
    """
    factor: Any = None
    if unit.factor.numerator != 1 or unit.factor.denominator == 1:
        factor = Num(str(unit.factor.numerator))
    if unit.factor.denominator != 1:
        denominator = Num(str(unit.factor.denominator))
        factor = BinOp("/", factor if factor is not None else Num("1"), denominator)
    for _ in range(abs(unit.pi_power)):
        factor = BinOp("*" if unit.pi_power > 0 else "/",
                       factor if factor is not None else Num("1"), Name("pi"))
    if factor is None or (unit.factor == 1 and unit.pi_power == 0):
        return Expression(text, expression.root, expression.origin)
    return Expression(text, BinOp("*", expression.root, factor), expression.origin)


def parse_with_unit(value: str | float, allowed: Collection[str] | None, file: str = "",
                    section: str = "", key: str = ""
                    ) -> tuple[Expression, tuple[Expression, Unit] | None]:
    """A parameter value with an optional unit: the SI expression, and what was given.

    Numbers and strings without a unit are parsed as before (:func:`parse`).

    Raises
    ------
    ExpressionError
        For an invalid expression or unit (naming file, section and key).

    Examples
    --------
    >>> e, given = parse_with_unit("0.1 N/mm", [])
    >>> e.to_sympy(lambda n, p: sympy.Symbol(n)), given[1].text
    (100, 'N/mm')
    >>> parse_with_unit(2, [])[1] is None
    True
    """
    text, unit_text = split_value(value) if isinstance(value, str) else (value, None)
    expression = parse(text, allowed=allowed, file=file, section=section, key=key)
    if unit_text is None:
        return expression, None
    try:
        unit = parse_unit(unit_text)
    except UnitError as exc:
        hint = "" if _looks_like_unit(unit_text) else \
            " (a unit follows the value after a space; for a product write *)"
        raise ExpressionError(f"{exc}{hint}", "", None, file, section, key) from None
    return scaled(expression, unit, str(value)), (expression, unit)


def _looks_like_unit(text: str) -> bool:
    return all(lookup_known(name) for name in re.findall(r"[A-Za-z_µμ°][A-Za-z0-9_µμ]*", text))


def lookup_known(name: str) -> bool:
    """Whether ``name`` is in the table :data:`UNITS` (no pint)."""
    return name in UNITS


# -- a model's units -------------------------------------------------------------------------

@dataclass(frozen=True)
class ModelUnits:
    """What a model with units knows about them (``Model.units``; None without units).

    Attributes
    ----------
    given : mapping
        parameter -> (the expression as written, without its unit, and the unit).
    dimensions : mapping
        every name (parameters, coordinates, signals, definitions, outputs) -> its
        dimension, or None where it is unknown (a bare number, a coordinate without unit).
    coordinates : mapping
        coordinate -> its declared unit.
    outputs : mapping
        output -> the unit it is shown in, where ``[outputs]`` gives one.
    display : mapping
        ``[display]`` quantity (length, angle, frequency, ...) -> unit.
    notes : tuple of str
        What could not be checked and where a value in Hz is used as an angular
        frequency; said once when the model is loaded.
    """

    given: Mapping[str, tuple[Expression, Unit]] = field(default_factory=dict)
    dimensions: Mapping[str, Dimension | None] = field(default_factory=dict)
    coordinates: Mapping[str, Unit] = field(default_factory=dict)
    outputs: Mapping[str, Unit] = field(default_factory=dict)
    display: Mapping[str, Unit] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def replacement_problem(self, name: str, written: Expression, unit: Unit) -> str | None:
        """Why a new value ``written unit`` cannot replace parameter ``name`` (its dimension
        differs from the parameter's), or None. Only a number with a unit is judged: an
        expression's dimension needs the other parameters' (the loader's full check).

        Examples
        --------
        >>> units = ModelUnits(dimensions={"k": parse_unit("N/m").dimension})
        >>> units.replacement_problem("k", parse("3"), parse_unit("kg"))
        'the value is in kg (a mass), but k is in N/m; give it in a unit of N/m'
        >>> units.replacement_problem("k", parse("3"), parse_unit("N/mm")) is None
        True
        """
        expected = self.dimensions.get(name)
        if expected is None or written.names() or unit.dimension == expected:
            return None
        kind = display_quantity(unit)
        kind = f" ({'an' if kind and kind[0] in 'aeiou' else 'a'} {kind})" if kind else ""
        return (f"the value is in {unit.text}{kind}, but {name} is in {expected.text()}; "
                f"give it in a unit of {expected.text()}")

    def dimension(self, name: str) -> Dimension | None:
        return self.dimensions.get(name)


#: the quantities a display unit can be chosen for (--units, [display])
DISPLAY_QUANTITIES = ("length", "angle", "frequency", "mass", "force", "time", "energy",
                      "moment", "velocity", "acceleration", "stress")

#: ``g`` as a display unit: standard gravity, an acceleration (as in a pulse's or a
#: spectral density's unit), never the gram (nobody asks for a result in grams)
STANDARD_GRAVITY_UNIT = Unit("g", Fraction("9.80665"), 0, ACCELERATION)
#: ``g`` as a unit in a load's unit text (``"g^2/Hz"``, ``"50 g"``: standard gravity, read as
#: ``g0``), not inside a name (``"kg"``)
GRAVITY_IN_UNIT = re.compile(r"(?<![A-Za-z0-9_µμ])g(?![A-Za-z0-9_])")

#: the quantity each dimension is shown as (its display unit chosen by that name)
_DISPLAYED: dict[Dimension, str] = {
    LENGTH: "length", FREQUENCY: "frequency", MASS: "mass", FORCE: "force", TIME: "time",
    ENERGY: "energy", VELOCITY: "velocity", ACCELERATION: "acceleration", STRESS: "stress"}


def display_quantity(unit: Unit) -> str | None:
    """Which quantity a display unit is for: ``mm`` -> length, ``deg`` -> angle, ...

    Examples
    --------
    >>> [display_quantity(parse_unit(u)) for u in ("mm", "deg", "Hz", "kN", "J", "MPa")]
    ['length', 'angle', 'frequency', 'force', 'energy', 'stress']
    """
    if unit.angle:
        return "angle"
    return _DISPLAYED.get(unit.dimension)


def display_units(texts: Iterable[str]) -> dict[str, Unit]:
    """``["mm", "deg", "Hz"]`` -> ``{"length": mm, "angle": deg, "frequency": Hz}``.

    ``g`` is standard gravity (:data:`STANDARD_GRAVITY_UNIT`), for accelerations.

    Raises
    ------
    UnitError
        For an unknown unit or one that is none of :data:`DISPLAY_QUANTITIES`.

    Examples
    --------
    >>> sorted(display_units(["g", "MPa", "mm/s"]).items())
    [('acceleration', Unit('g')), ('stress', Unit('MPa')), ('velocity', Unit('mm/s'))]
    """
    out: dict[str, Unit] = {}
    for text in texts:
        unit = STANDARD_GRAVITY_UNIT if text.strip() == "g" else parse_unit(text.strip())
        quantity = display_quantity(unit)
        if quantity is None:
            raise UnitError(f"'{text.strip()}' is not a unit of length, angle, frequency, "
                            "mass, force, time, energy, velocity, acceleration or stress")
        out[quantity] = unit
    return out


def frozen(**maps: Mapping[str, Any]) -> dict[str, Any]:
    """Read-only copies of mappings (for :class:`ModelUnits`)."""
    return {key: MappingProxyType(dict(value)) for key, value in maps.items()}


__all__ = ["Dimension", "Unit", "UnitError", "ModelUnits", "UNITS", "BASE", "DIMENSIONLESS",
           "LENGTH", "MASS", "TIME", "FREQUENCY", "FORCE", "ENERGY", "POWER", "ONE",
           "VELOCITY", "ACCELERATION", "STRESS", "STANDARD_GRAVITY_UNIT",
           "parse_unit", "lookup", "split_value", "scaled", "display_units",
           "display_quantity", "DISPLAY_QUANTITIES", "frozen", "parse_with_unit"]
