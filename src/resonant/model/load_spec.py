"""The ``[shock]`` and ``[fatigue]`` sections: a classical shock pulse and an S-N curve.

``[shock]`` gives one transient input of the model, a classical pulse on a signal (a
support motion or a force) or a force on a coordinate, and the damping of the shock
response spectrum's oscillators::

    [shock]
    signal = "y"             # a signal of the model, or a coordinate (a force on it)
    derivative = 2           # the pulse is of y'' (0: of y itself, the default)
    pulse = "half-sine"      # half-sine, haversine, sawtooth, rectangular, step, impulse
    amplitude = 100          # the peak (the area for an impulse), in `unit`
    unit = "g"               # optional; g is standard gravity (default: SI)
    duration = 0.011         # s
    step = 1e-5              # s, the sampling step (default duration / 2000)
    total = 0.05             # s, the history computed (default 3 durations)
    Q = 10                   # the SRS oscillators' Q = 1/(2 zeta) (default 10)

``[periodic]`` gives one periodic, non-harmonic load: a shape with closed-form Fourier
coefficients, or an expression of ``t`` over one period::

    [periodic]
    signal = "F"             # a signal of the model, or a coordinate (a force on it)
    derivative = 0           # the series is of F itself (2: of an acceleration)
    shape = "square"         # square, sawtooth, triangle, rectified-sine; or
    # expression = "F0*t/T"  # s(t) on 0 <= t < period, of t and the parameters
    amplitude = 10           # the shape's A, in `unit` (default SI)
    period = 0.5             # s
    tolerance = 0.01         # the remainder's relative RMS (default 0.01)

``[fatigue]`` gives the S-N curve N S^k = C of a stress output (S its amplitude, SI), the
spectral method and the exposure, for the study quantity ``damage:NAME`` under the
``[random]`` inputs (docs/random.md)::

    [fatigue]
    k = 4                    # the inverse slope
    C = 1e40                 # N S_a^k = C, S_a in Pa; or C_range (stress ranges), or
                             # amplitude = 1e8 with cycles = 1e6 (a point of the curve)
    method = "dirlik"        # narrowband, dirlik or tovo-benasciutti (default dirlik)
    duration = 3600          # s, the exposure

Every problem names the file, the section and the key.

Examples
--------
>>> problems = []
>>> spec = parse_shock({"signal": "y", "derivative": 2, "pulse": "half-sine",
...                     "amplitude": 100, "unit": "g", "duration": 0.011},
...                    ["y"], ["x"], "f.toml", problems)
>>> round(spec.amplitude, 5), spec.step, problems
(980.665, 5.5e-06, [])
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Collection, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import Problem, name_list, printable
from ..expressions import Expression, ExpressionError, numeric_value, parse
from .fourier_shapes import SHAPES
from .limits import MAX_FREQUENCY_HZ
from .pulses import PULSES
from .units import (
    ACCELERATION,
    DIMENSIONLESS,
    FREQUENCY,
    GRAVITY_IN_UNIT,
    TIME,
    Dimension,
    ModelUnits,
    Unit,
    UnitError,
    parse_unit,
    parse_with_unit,
    split_value,
)

#: the spectral fatigue methods of ``[fatigue]`` (resonant.analyses.fatigue)
FATIGUE_METHODS = ("narrowband", "dirlik", "tovo-benasciutti")
#: the keys of ``[shock]`` and ``[fatigue]``
SHOCK_KEYS = ("signal", "derivative", "pulse", "amplitude", "unit", "duration", "step",
              "total", "Q")
PERIODIC_KEYS = ("signal", "derivative", "shape", "expression", "amplitude", "unit", "period",
                 "tolerance")
FATIGUE_KEYS = ("k", "C", "C_range", "amplitude", "cycles", "method", "duration")
#: most samples of the pulse's history (total / step + 1, the samples t = 0 ... total)
MAX_SHOCK_SAMPLES = 5_000_000
#: standard gravity (m/s^2): ``g`` as the unit of a pulse's amplitude
STANDARD_GRAVITY = 9.80665
#: the quantity of a duration, a step, a period
_TIME = TIME


@dataclass(frozen=True)
class ShockSpec:
    """The ``[shock]`` section: a classical pulse on one input, in SI.

    Parameters
    ----------
    signal : str
        A signal of the model, or a coordinate (a generalized force on it).
    derivative : int
        The pulse is of the signal's ``derivative``-th time derivative (0, 1 or 2).
    pulse : str
        One of :data:`PULSES`.
    amplitude, duration, step, total : float
        The peak (SI; the area for an impulse), the pulse's duration, the sampling step
        and the length of the history computed (s).
    Q : float
        The shock response spectrum's Q = 1 / (2 zeta).

    Examples
    --------
    >>> ShockSpec("y", 2, "half-sine", 1.0, 0.01, 1e-5, 0.03).Q
    10.0
    """

    signal: str
    derivative: int
    pulse: str
    amplitude: float
    duration: float
    step: float
    total: float
    Q: float = 10.0
    source: str = field(default="", compare=False)


@dataclass(frozen=True)
class PeriodicSpec:
    """The ``[periodic]`` section: a periodic load on one input (SI).

    Parameters
    ----------
    signal : str
        A signal of the model, or a coordinate (a generalized force on it).
    derivative : int
        The series is of the signal's ``derivative``-th time derivative.
    shape : str
        One of :data:`SHAPES`, or ``"expression"``.
    amplitude : float
        The shape's amplitude A (SI); with an expression, the factor on it (its
        ``amplitude``, 1 by default, times its ``unit``'s factor to SI).
    period : float
        T (s).
    tolerance : float
        The largest relative RMS of the series' remainder.
    expression : Expression or None
        s(t) over one period (SI), of ``t`` and the parameters.

    Examples
    --------
    >>> PeriodicSpec("F", 0, "square", 1.0, 2.0).tolerance
    0.01
    """

    signal: str
    derivative: int
    shape: str
    amplitude: float
    period: float
    tolerance: float = 1e-2
    expression: Expression | None = None
    source: str = field(default="", compare=False)


@dataclass(frozen=True)
class FatigueSpec:
    """The ``[fatigue]`` section: an S-N curve N S_a^k = C (S_a the stress amplitude, SI),
    a spectral method and the exposure.

    Examples
    --------
    >>> FatigueSpec(4.0, 1e40, "dirlik", 3600.0).method
    'dirlik'
    """

    k: float
    C: float
    method: str
    duration: float
    source: str = field(default="", compare=False)


def _unknown(data: dict[Any, Any], known: Sequence[str], source: str, section: str,
             problems: list[Problem]) -> None:
    for key in data:
        if key not in known:
            close = difflib.get_close_matches(str(key), known, n=1)
            hint = f"did you mean '{close[0]}'?" if close else f"known: {', '.join(known)}"
            problems.append(Problem(f"unknown key '{key}'; {hint}", source, section, str(key)))


def _finite(raw: object) -> float | None:
    """``raw`` as a finite float, or None (a bool, a text, NaN, infinity, or a whole number
    beyond the floating-point range, which TOML allows)."""
    if isinstance(raw, bool) or not isinstance(raw, (int, float)):
        return None
    try:
        value = float(raw)
    except OverflowError:
        return None
    return value if math.isfinite(value) else None


def _shown(raw: object) -> str:
    """``raw`` as quoted in a message: short, and safe to print."""
    return printable(repr(raw), limit=40)


def _scaled(value: float, factor: float, source: str, section: str, key: str,
            problems: list[Problem]) -> float | None:
    """``value`` times its unit's SI factor, if that is still a finite number."""
    scaled = value * factor
    if not math.isfinite(scaled):
        problems.append(Problem(f"{value:g} in SI units is beyond the floating-point range; "
                                "give a smaller value", source, section, key))
        return None
    return scaled


#: a stress (Pa), the quantity of an S-N curve's amplitude
STRESS = Dimension.of(kg=1, m=-1, s=-2)


def quantity_parts(raw: str, source: str, section: str, key: str, problems: list[Problem],
                   params: Collection[str] = ()) -> tuple[float, Unit | None] | None:
    """A text value of a load section's key: arithmetic of numbers with an optional unit
    after a space (as in ``[parameters]``; ``g`` is standard gravity), as its SI value and
    the unit given (None without one); None, and a problem, where the text is wrong.

    Parameter names are refused (``params`` names them as such): these keys are read once,
    when the model is loaded, not at each parameter value.

    Examples
    --------
    >>> problems = []
    >>> quantity_parts("2*25 g", "m.toml", "shock", "amplitude", problems)
    (490.3325, Unit('g0'))
    >>> quantity_parts("2*pi/w", "m.toml", "periodic", "period", problems, ["w"])
    >>> print(problems[0])
    m.toml: [periodic] period: 'w' is a parameter: these keys take numbers with units, \
not parameters
    """
    text, unit_text = split_value(raw)
    written = text if unit_text is None else f"{text} {GRAVITY_IN_UNIT.sub('g0', unit_text)}"
    try:
        expression, given = parse_with_unit(written, None, source, section, key)
    except ExpressionError as exc:
        problems.extend(exc.problems)
        return None
    names = sorted(name for name, _ in expression.names())
    if names:
        shown = printable(names[0], limit=30)
        problems.append(Problem(
            f"'{shown}' is a parameter: these keys take numbers with units, not parameters"
            if names[0] in params else
            f"'{shown}' is not a number: these keys take numbers with units (arithmetic of "
            "numbers, a unit after a space)", source, section, key))
        return None
    try:
        with np.errstate(all="ignore"):
            value = float(numeric_value(expression, {}))
    except (ArithmeticError, ValueError):
        value = math.nan
    if not math.isfinite(value):
        problems.append(Problem(f"{_shown(raw)} is not a finite number", source, section, key))
        return None
    return value, None if given is None else given[1]


def quantity_value(raw: object, dimension: Dimension, source: str, section: str, key: str,
                   problems: list[Problem], params: Collection[str] = ()) -> object:
    """A key's value as a number in SI: a number as it is, or a text like ``"41.4 ms"``
    or ``"2*60 s"`` (:func:`quantity_parts`) with a unit of ``dimension`` converted to SI
    (a frequency to Hz: ``"6000 rpm"`` is 100 Hz); the raw value where it is no text,
    None (and a problem) where the text is wrong or its unit of another quantity.

    Examples
    --------
    >>> problems = []
    >>> quantity_value("1 h", Dimension.of(s=1), "m.toml", "fatigue", "duration", problems)
    3600.0
    >>> quantity_value("6000 rpm", FREQUENCY, "m.toml", "random", "band", problems)
    100.0
    >>> quantity_value("2 m", Dimension.of(s=1), "m.toml", "fatigue", "duration", problems)
    >>> print(problems[0])
    m.toml: [fatigue] duration: the unit m is not one of time (s); give it in s
    """
    if not isinstance(raw, str):
        return raw
    parts = quantity_parts(raw, source, section, key, problems, params)
    if parts is None:
        return None
    value, unit = parts
    if unit is not None and unit.dimension != dimension:
        problems.append(Problem(wrong_unit(unit, dimension), source, section, key))
        return None
    return value / (2 * math.pi) if dimension == FREQUENCY and unit is not None and \
        not unit.cyclic else value


def wrong_unit(unit: Unit, dimension: Dimension) -> str:
    """The message for a unit given where a quantity of ``dimension`` is expected.

    Examples
    --------
    >>> wrong_unit(parse_unit("kg"), FREQUENCY)
    'the unit kg is not one of frequency (Hz); give it in Hz, kHz, rad/s or rpm'
    """
    name, how = _DIMENSION_NAMES.get(dimension, (f"{dimension.text()}",
                                                 f"it in {dimension.text()}"))
    shown = "g" if unit.text == "g0" else printable(unit.text.replace("g0", "g"), limit=30)
    return f"the unit {shown} is not one of {name}; give {how}"


#: how a message names a key's quantity, and how to give it
_DIMENSION_NAMES = {
    TIME: ("time (s)", "it in s"), STRESS: ("stress (Pa)", "it in Pa, MPa or GPa"),
    FREQUENCY: ("frequency (Hz)", "it in Hz, kHz, rad/s or rpm"),
    DIMENSIONLESS: ("a dimensionless quantity", "a number without a unit"),
    ACCELERATION: ("acceleration (m/s^2)", "it in m/s^2 or g"),
}


def _positive(data: dict[Any, Any], key: str, source: str, section: str,
              problems: list[Problem], default: float | None = None,
              dimension: Dimension | None = DIMENSIONLESS,
              params: Collection[str] = ()) -> float | None:
    """A finite positive number (a missing key gives ``default``; None: required); with a
    ``dimension``, also a text with a unit (:func:`quantity_value`)."""
    raw = data.get(key, default)
    if raw is None:
        problems.append(Problem("missing: a positive number is required", source, section, key))
        return None
    if dimension is not None and isinstance(raw, str):
        count = len(problems)
        raw = quantity_value(raw, dimension, source, section, key, problems, params)
        if len(problems) > count:
            return None
    value = _finite(raw)
    if value is None or value <= 0:
        problems.append(Problem(f"must be a positive finite number, got {_shown(raw)}", source,
                                section, key))
        return None
    return value


def check_input_dimension(name: str, quantity: Dimension | None, derivative: int, base: bool,
                          units: ModelUnits | None, coordinates: Sequence[str],
                          where: tuple[str, str, str], problems: list[Problem],
                          density: bool = False) -> None:
    """An input's quantity (a load's or a density's unit) against the signal's (or the
    force's) dimension, where the model's units know it.

    Examples
    --------
    >>> from types import MappingProxyType
    >>> units = ModelUnits(dimensions=MappingProxyType({"y": Dimension.of(m=1)}))
    >>> problems = []
    >>> check_input_dimension("y", Dimension.of(kg=1), 2, False, units, ["x"],
    ...                       ("m.toml", "shock", "unit"), problems)
    >>> print(problems[0].message)
    the unit is kg, but y'' is in m/s^2; give it in m/s^2
    """
    if quantity is None or units is None:
        return
    expected: Dimension | None
    if base:
        expected = Dimension.of(m=1, s=-2)
    elif name in coordinates:
        coordinate = units.dimensions.get(name)
        expected = None if coordinate is None else \
            Dimension.of(kg=1, m=2, s=-2) / coordinate
    else:
        signal = units.dimensions.get(name)
        expected = None if signal is None else signal / Dimension.of(s=derivative)
    if expected is not None and expected != quantity:
        what = ("the base acceleration" if base else f"{name}" + "'" * derivative)
        wanted = f"({expected.text() or '1'})^2/Hz" if density else expected.text() or "1"
        problems.append(Problem(f"the unit is {'a density of ' if density else ''}"
                                f"{quantity.text() or '1'}, but {what} is in "
                                f"{expected.text() or '1'}; give it in {wanted}", *where))


def _input(data: dict[Any, Any], signals: Sequence[str], coordinates: Sequence[str],
           source: str, section: str, problems: list[Problem],
           units: ModelUnits | None = None) -> tuple[str, int, float, Dimension | None]:
    """(signal, derivative, unit factor, the unit's quantity or None) of a section giving
    one input; its unit checked against the signal's dimension where the model's units
    know it."""
    signal = data.get("signal")
    names = list(signals) + list(coordinates)
    if not isinstance(signal, str) or signal not in names:
        close = difflib.get_close_matches(str(signal), names, n=1)
        hint = f"did you mean '{close[0]}'?" if close else \
            f"they are {name_list(names, 20) or 'none'}"
        problems.append(Problem(f"{_shown(signal)} is neither a signal nor a coordinate; {hint}"
                                if signal is not None else
                                f"missing: the signal or coordinate the load acts on; {hint}",
                                source, section, "signal"))
    derivative = data.get("derivative", 0)
    if isinstance(derivative, bool) or derivative not in (0, 1, 2):
        problems.append(Problem(f"must be 0, 1 or 2, got {_shown(derivative)}", source, section,
                                "derivative"))
        derivative = 0
    factor = 1.0
    quantity: Dimension | None = None
    unit = data.get("unit")
    if unit is not None:
        if not isinstance(unit, str) or not unit.strip():
            problems.append(Problem("must be a unit text such as \"g\" or \"m/s^2\"", source,
                                    section, "unit"))
        elif unit.strip() == "g":
            factor = STANDARD_GRAVITY
            quantity = Dimension.of(m=1, s=-2)
        else:
            try:
                parsed = parse_unit(unit)
                factor, quantity = parsed.to_si(), parsed.dimension
            except UnitError as exc:
                problems.append(Problem(str(exc), source, section, "unit"))
        if quantity is not None and isinstance(signal, str) and signal in names:
            check_input_dimension(signal, quantity, int(derivative), False, units,
                                  coordinates, (source, section, "unit"), problems)
    return str(signal), int(derivative), factor, quantity


def _amplitude(raw: object, given: tuple[float, Dimension | None], load: tuple[str, int, bool],
               units: ModelUnits | None, coordinates: Sequence[str],
               where: tuple[str, str, str], problems: list[Problem], params: Sequence[str],
               factor_of: str = "") -> float | None:
    """A load's amplitude in SI: a number (or arithmetic) in the section's ``unit``
    (``given``: its factor and quantity), or a value with its own unit
    (:func:`quantity_parts`) of the input's quantity (times s for an impulse's area:
    ``load`` is the signal, the derivative and whether the value is an area)."""
    count = len(problems)
    unit: Unit | None = None
    value: float | None = _finite(raw)
    if isinstance(raw, str):
        parts = quantity_parts(raw, *where, problems, params)
        value, unit = (None, None) if parts is None else parts
    if len(problems) == count and (value is None or value == 0):
        problems.append(Problem(f"must be a finite non-zero number{factor_of}, got "
                                f"{_shown(raw)}", *where))
    if len(problems) > count or value is None:
        return None
    if unit is None:
        return _scaled(value, given[0], *where, problems)
    signal, derivative, area = load
    quantity = unit.dimension / TIME if area else unit.dimension
    if given[1] is not None and quantity != given[1]:
        problems.append(Problem(f"{wrong_unit(unit, given[1] * TIME if area else given[1])}"
                                ", as the key unit says (or give the number alone, in "
                                "that unit)", *where))
        return None
    check_input_dimension(signal, quantity, derivative, False, units, coordinates, where,
                          problems)
    return value if len(problems) == count else None


def parse_periodic(data: object, params: Sequence[str], signals: Sequence[str],
                   coordinates: Sequence[str], source: str, problems: list[Problem],
                   units: ModelUnits | None = None) -> PeriodicSpec | None:
    """The ``[periodic]`` section, its problems appended to ``problems``.

    Parameters
    ----------
    data : Any
        The section as read from TOML.
    params : sequence of str
        The parameters (allowed in an expression, with ``t``).
    signals, coordinates : sequence of str
        The model's signals and coordinates.
    source : str
        The model file.
    problems : list of Problem
        Receives every problem found.
    units : ModelUnits, optional
        The model's units: a ``unit`` is checked against the signal's dimension.

    Returns
    -------
    PeriodicSpec or None
        None when the section has problems.

    Examples
    --------
    >>> problems = []
    >>> parse_periodic({"signal": "F", "shape": "square", "amplitude": 2, "period": 0.5},
    ...                [], ["F"], ["x"], "m.toml", problems).period
    0.5
    >>> parse_periodic({"signal": "F", "shape": "wave", "period": 0.5}, [], ["F"], ["x"],
    ...                "m.toml", problems)
    >>> print(problems[0])  # doctest: +ELLIPSIS
    m.toml: [periodic] shape: must be one of square, sawtooth, triangle, rectified-sine...
    """
    section = "periodic"
    count = len(problems)
    if not isinstance(data, dict):
        problems.append(Problem("expected a table", source, section))
        return None
    _unknown(data, PERIODIC_KEYS, source, section, problems)
    signal, derivative, factor, quantity = _input(data, signals, coordinates, source, section,
                                                  problems, units)
    load = (signal, derivative, False)
    expression: Expression | None = None
    if "expression" in data:
        if "shape" in data:
            problems.append(Problem("give either shape or expression, not both", source,
                                    section, "expression"))
        text = data["expression"]
        if not isinstance(text, (str, int, float)) or isinstance(text, bool):
            problems.append(Problem("an expression of t and the parameters is a text",
                                    source, section, "expression"))
        else:
            try:
                expression = parse(text, allowed=[*params, "t"], file=source,
                                   section=section, key="expression")
                if any(primes for _, primes in expression.names()):
                    problems.append(Problem("no primes: an expression of t and the "
                                            "parameters", source, section, "expression"))
            except ExpressionError as exc:
                problems.extend(exc.problems)
        shape: object = "expression"
        # the expression in the section's unit, scaled by its amplitude where one is given
        amplitude = _amplitude(data.get("amplitude", 1.0), (factor, quantity), load, units,
                               coordinates, (source, section, "amplitude"), problems, params,
                               " (a factor on the expression)")
    else:
        shape = data.get("shape")
        if shape not in SHAPES:
            problems.append(Problem(f"must be one of {', '.join(SHAPES)} (or give an "
                                    f"expression of t), got {_shown(shape)}", source, section,
                                    "shape"))
        amplitude = _amplitude(data.get("amplitude"), (factor, quantity), load, units,
                               coordinates, (source, section, "amplitude"), problems, params)
    period = _positive(data, "period", source, section, problems, dimension=_TIME,
                       params=params)
    if period is not None and 1 / period > MAX_FREQUENCY_HZ:
        problems.append(Problem(
            f"a period of {period:g} s is a base frequency of {1 / period:g} Hz, above "
            f"{MAX_FREQUENCY_HZ:g} Hz, where the dynamic stiffness (2 pi f)^2 M leaves "
            "the floating-point range; give the period in seconds", source, section,
            "period"))
        period = None
    tolerance = quantity_value(data.get("tolerance", 1e-2), DIMENSIONLESS, source, section,
                               "tolerance", problems, params)
    if tolerance is None:
        pass
    elif isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or \
            not 1e-8 <= tolerance < 1:
        problems.append(Problem(f"must be a number in [1e-8, 1), got {_shown(tolerance)}", source,
                                section, "tolerance"))
    if len(problems) > count:
        return None
    assert amplitude is not None and period is not None and isinstance(tolerance, (int, float))
    return PeriodicSpec(signal, derivative, str(shape), amplitude, period, float(tolerance),
                        expression, source)


def parse_shock(data: object, signals: Sequence[str], coordinates: Sequence[str], source: str,
                problems: list[Problem], units: ModelUnits | None = None,
                params: Sequence[str] = ()) -> ShockSpec | None:
    """The ``[shock]`` section, its problems appended to ``problems``.

    Parameters
    ----------
    data : Any
        The section as read from TOML.
    signals, coordinates : sequence of str
        The model's signals and coordinates (the names the input may have).
    source : str
        The model file.
    problems : list of Problem
        Receives every problem found.
    units : ModelUnits, optional
        The model's units: a ``unit`` is checked against the signal's dimension.
    params : sequence of str, optional
        The parameters (named as such where a key is given one).

    Returns
    -------
    ShockSpec or None
        None when the section has problems.

    Examples
    --------
    >>> problems = []
    >>> parse_shock({"signal": "yy", "pulse": "half-sine", "amplitude": 1, "duration": 0.01},
    ...             ["y"], ["x"], "m.toml", problems)
    >>> print(problems[0])
    m.toml: [shock] signal: 'yy' is neither a signal nor a coordinate; did you mean 'y'?
    """
    section = "shock"
    count = len(problems)
    if not isinstance(data, dict):
        problems.append(Problem("expected a table", source, section))
        return None
    _unknown(data, SHOCK_KEYS, source, section, problems)
    signal, derivative, factor, quantity = _input(data, signals, coordinates, source, section,
                                                  problems, units)
    kind = data.get("pulse")
    if kind not in PULSES:
        problems.append(Problem(f"must be one of {', '.join(PULSES)}, got {_shown(kind)}", source,
                                section, "pulse"))
    amplitude = _amplitude(data.get("amplitude"), (factor, quantity),
                           (signal, derivative, kind == "impulse"), units, coordinates,
                           (source, section, "amplitude"), problems, params)
    duration = _positive(data, "duration", source, section, problems, dimension=_TIME,
                         params=params)
    # without a valid duration, a missing step or total (their defaults) is not a problem more
    step = _positive(data, "step", source, section, problems,
                     None if duration is None else duration / 2000, _TIME, params) \
        if duration is not None or "step" in data else None
    total = _positive(data, "total", source, section, problems,
                      None if duration is None else 3 * duration, _TIME, params) \
        if duration is not None or "total" in data else None
    count_Q = len(problems)
    raw_Q = data.get("Q", 10.0)
    Q = _finite(quantity_value(raw_Q, DIMENSIONLESS, source, section, "Q", problems, params))
    if len(problems) > count_Q:
        pass
    elif Q is None or Q <= 0.5:
        problems.append(Problem(f"must be a number above 0.5 (Q = 1/(2 zeta)), got "
                                f"{_shown(raw_Q)}", source, section, "Q"))
    if duration is not None and total is not None and total < duration:
        problems.append(Problem(f"the history ({total:g} s) must cover the pulse's duration "
                                f"({duration:g} s)", source, section, "total"))
    # the history holds the samples t = 0, step, ..., total: one more than total / step
    samples = total / step + 1 if step is not None and total is not None else 0.0
    if not samples < MAX_SHOCK_SAMPLES + 0.5:   # the pulse rounds total / step
        problems.append(Problem(f"{samples:.3g} samples (total / step + 1); at most "
                                f"{MAX_SHOCK_SAMPLES}: a larger step or a shorter total",
                                source, section, "step"))
    if step is not None and duration is not None and kind not in ("step", "impulse") \
            and step > duration / 10:
        problems.append(Problem(f"the step {step:g} s samples the pulse in fewer than 10 "
                                f"steps; at most {duration / 10:g} s", source, section, "step"))
    if len(problems) > count:
        return None
    assert amplitude is not None and duration is not None and step is not None \
        and total is not None
    assert Q is not None
    return ShockSpec(str(signal), int(derivative), str(kind), amplitude, duration, step,
                     total, Q, source)


def parse_fatigue(data: object, source: str, problems: list[Problem],
                  params: Sequence[str] = ()) -> FatigueSpec | None:
    """The ``[fatigue]`` section, its problems appended to ``problems``.

    Parameters
    ----------
    data : Any
        The section as read from TOML.
    source : str
        The model file.
    problems : list of Problem
        Receives every problem found.
    params : sequence of str, optional
        The parameters (named as such where a key is given one).

    Returns
    -------
    FatigueSpec or None
        None when the section has problems.

    Examples
    --------
    >>> problems = []
    >>> parse_fatigue({"k": 4, "C": 1e40, "duration": 60}, "m.toml", problems).C
    1e+40
    >>> parse_fatigue({"k": 4, "duration": 60}, "m.toml", problems)
    >>> print(problems[0])
    m.toml: [fatigue] C: give the S-N curve as one of: C, C_range, or amplitude with cycles
    """
    section = "fatigue"
    count = len(problems)
    if not isinstance(data, dict):
        problems.append(Problem("expected a table", source, section))
        return None
    _unknown(data, FATIGUE_KEYS, source, section, problems)
    k = _positive(data, "k", source, section, problems, params=params)
    given = [g for g in ("C", "C_range", "amplitude") if g in data]
    C: float | None = None
    if len(given) != 1 or ("amplitude" in data) != ("cycles" in data):
        problems.append(Problem("give the S-N curve as one of: C, C_range, or amplitude with "
                                "cycles", source, section, given[1] if len(given) > 1 else
                                ("cycles" if "cycles" in data and not given else "C")))
    else:
        value = _positive(data, given[0], source, section, problems,
                          dimension=STRESS if given[0] == "amplitude" else DIMENSIONLESS,
                          params=params)
        if value is not None and k is not None:
            try:
                if given[0] == "C":
                    C = value
                elif given[0] == "C_range":
                    C = value / 2.0 ** k
                else:
                    cycles = _positive(data, "cycles", source, section, problems,
                                       params=params)
                    if cycles is not None:
                        C = cycles * value ** k
            except OverflowError:
                C = math.inf
            if C is not None and not (math.isfinite(C) and C > 0):
                problems.append(Problem(f"the curve's C = {C:g} is not a positive finite "
                                        "number", source, section, given[0]))
    method = data.get("method", "dirlik")
    if method not in FATIGUE_METHODS:
        problems.append(Problem(f"must be one of {', '.join(FATIGUE_METHODS)}, got "
                                f"{_shown(method)}",
                                source, section, "method"))
    duration = _positive(data, "duration", source, section, problems, dimension=_TIME,
                         params=params)
    if len(problems) > count:
        return None
    assert k is not None and C is not None and duration is not None
    return FatigueSpec(k, C, str(method), duration, source)


__all__ = ["FATIGUE_METHODS", "FatigueSpec", "PULSES", "PeriodicSpec", "SHAPES", "ShockSpec",
           "parse_fatigue", "parse_periodic", "parse_shock", "quantity_parts", "quantity_value",
           "wrong_unit"]
