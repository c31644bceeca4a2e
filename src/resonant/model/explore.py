"""The ``[explore]`` section: the ranges of the sliders of the explore page.

``resonant explore`` writes a page with a slider for every parameter.  A model may
say how far each slider goes, which names the frequency response shows and which
parameter is the excitation frequency::

    [explore]
    k = { from = 50, to = 200 }                   # SI values, or "50 N/m" with a unit
    m2 = { from = 0.5, to = 2, scale = "log" }    # scale "linear" (default) or "log"
    show = ["x1", "phi"]                          # coordinates and outputs in the curves
    frequency = "omega"                           # the parameter swept in the curves

A table is the range of the parameter of that name; ``show`` (a list) and
``frequency`` (a string) are options.  Every problem names the file, the section
and the key.

Examples
--------
>>> problems = []
>>> spec = parse_explore({"k": {"from": 50, "to": 200}, "show": ["x"]}, ["k", "m"], ["x"],
...                      [], "f.toml", problems)
>>> spec.ranges["k"], spec.show, problems
(ExploreRange(name='k', start=50.0, stop=200.0, log=False), ('x',), [])
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from ..errors import Problem, name_list
from ..expressions import ExpressionError, numeric_value
from .units import ModelUnits, parse_with_unit

SECTION = "explore"
#: the keys of a range table
RANGE_KEYS = ("from", "to", "scale")


@dataclass(frozen=True)
class ExploreRange:
    """The range of one parameter's slider (SI values).

    Parameters
    ----------
    name : str
        The parameter.
    start, stop : float
        The ends of the slider, ``start < stop``.
    log : bool
        A logarithmic slider (both ends positive).

    Examples
    --------
    >>> ExploreRange("k", 50.0, 200.0).log
    False
    """

    name: str
    start: float
    stop: float
    log: bool = False


@dataclass(frozen=True)
class ExploreSpec:
    """A model's ``[explore]`` section.

    Parameters
    ----------
    ranges : mapping
        parameter -> :class:`ExploreRange`.
    show : tuple of str
        The coordinates and outputs the frequency response shows (empty: resonant
        chooses).
    frequency : str or None
        The parameter the frequency response sweeps (None: resonant chooses).

    Examples
    --------
    >>> ExploreSpec({}, (), "omega").frequency
    'omega'
    """

    ranges: Mapping[str, ExploreRange]
    show: tuple[str, ...] = ()
    frequency: str | None = None


def _unknown(name: str, known: Sequence[str], what: str) -> str:
    close = difflib.get_close_matches(name, list(known), n=1)
    hint = f"; did you mean '{close[0]}'?" if close else \
        f"; the {what} are {name_list(known, 20) or 'none'}"
    return f"'{name}' is not one of the model's {what}{hint}"


def _bound(value: object, part: str, where: tuple[str, str], units: ModelUnits | None,
           problems: list[Problem]) -> float | None:
    """One end of a range: a number (SI) or a string with a unit, converted to SI."""
    source, key = where
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        problems.append(Problem(f"'{part}' must be a number (SI) or a value with a unit such "
                                f"as \"50 N/m\", got {type(value).__name__}", source, SECTION,
                                key))
        return None
    try:
        expression, given = parse_with_unit(value, [], source, SECTION, key)
    except ExpressionError as exc:
        problems.extend(exc.problems)
        return None
    if given is not None and units is not None:
        mismatch = units.replacement_problem(key, *given)
        if mismatch:
            problems.append(Problem(f"'{part}': {mismatch}", source, SECTION, key))
            return None
    number = float(numeric_value(expression, {}))
    if not math.isfinite(number):
        problems.append(Problem(f"'{part}' is not a finite number", source, SECTION, key))
        return None
    return number


def _range(name: str, table: Mapping[str, Any], source: str, units: ModelUnits | None,
           problems: list[Problem]) -> ExploreRange | None:
    unknown = sorted(set(table) - set(RANGE_KEYS))
    if unknown:
        problems.append(Problem(f"unknown key '{unknown[0]}' in the range; a range is "
                                "{ from = ..., to = ..., scale = \"linear\" or \"log\" }",
                                source, SECTION, name))
        return None
    missing = [part for part in ("from", "to") if part not in table]
    if missing:
        problems.append(Problem(f"the range needs '{missing[0]}' (a range is "
                                "{ from = ..., to = ... })", source, SECTION, name))
        return None
    start = _bound(table["from"], "from", (source, name), units, problems)
    stop = _bound(table["to"], "to", (source, name), units, problems)
    if start is None or stop is None:
        return None
    if not start < stop:
        problems.append(Problem(f"'from' ({start:.6g}) must be below 'to' ({stop:.6g})",
                                source, SECTION, name))
        return None
    scale = table.get("scale", "linear")
    if scale not in ("linear", "log"):
        problems.append(Problem(f"scale must be \"linear\" or \"log\", not {scale!r}", source,
                                SECTION, name))
        return None
    if scale == "log" and start <= 0:
        problems.append(Problem("a logarithmic range needs positive ends; 'from' is "
                                f"{start:.6g}", source, SECTION, name))
        return None
    return ExploreRange(name, start, stop, scale == "log")


def _options(data: Mapping[str, Any], parameters: Sequence[str], names: Sequence[str],
             source: str, problems: list[Problem]) -> tuple[tuple[str, ...], str | None]:
    """``show`` and ``frequency``."""
    show: list[str] = []
    raw = data.get("show")
    if raw is not None and not isinstance(raw, dict):
        if not isinstance(raw, list) or not all(isinstance(s, str) for s in raw):
            problems.append(Problem("show must be a list of coordinate and output names, "
                                    "such as [\"x1\", \"phi\"]", source, SECTION, "show"))
        else:
            for item in raw:
                if item not in names:
                    problems.append(Problem(_unknown(item, names, "coordinates and outputs"),
                                            source, SECTION, "show"))
                elif item not in show:
                    show.append(item)
    frequency = data.get("frequency")
    if isinstance(frequency, dict):
        frequency = None  # the range of a parameter called "frequency"
    elif frequency is not None:
        if not isinstance(frequency, str):
            problems.append(Problem("frequency must name a parameter, such as \"omega\"",
                                    source, SECTION, "frequency"))
            frequency = None
        elif frequency not in parameters:
            problems.append(Problem(_unknown(frequency, parameters, "parameters"), source,
                                    SECTION, "frequency"))
            frequency = None
    return tuple(show), frequency


def parse_explore(data: object, parameters: Sequence[str], coordinates: Sequence[str],
                  outputs: Sequence[str], source: str, problems: list[Problem],
                  units: ModelUnits | None = None) -> ExploreSpec | None:
    """Validate ``[explore]``; append every problem to ``problems``.

    Parameters
    ----------
    data : object
        The section as read from TOML.
    parameters, coordinates, outputs : sequence of str
        The model's names.
    source : str
        The file (for messages).
    problems : list of Problem
        Where the problems go.
    units : ModelUnits, optional
        The model's units: a bound with a unit must have the parameter's dimension.

    Returns
    -------
    ExploreSpec or None
        None when the section is not a table.

    Examples
    --------
    >>> problems = []
    >>> parse_explore({"kk": {"from": 1, "to": 2}}, ["k"], [], [], "f.toml", problems)
    ExploreSpec(ranges=mappingproxy({}), show=(), frequency=None)
    >>> print(problems[0])
    f.toml: [explore] kk: 'kk' is not one of the model's parameters; did you mean 'k'?
    """
    if not isinstance(data, dict):
        problems.append(Problem("[explore] must be a table of parameter ranges, such as "
                                "k = { from = 50, to = 200 }", source, SECTION))
        return None
    names = [*coordinates, *outputs]
    show, frequency = _options(data, parameters, names, source, problems)
    ranges: dict[str, ExploreRange] = {}
    for key, value in data.items():
        if key in ("show", "frequency") and not isinstance(value, dict):
            continue
        if key not in parameters:
            problems.append(Problem(_unknown(key, parameters, "parameters"), source, SECTION,
                                    key))
            continue
        if not isinstance(value, dict):
            problems.append(Problem("expected a range { from = ..., to = ... }, got "
                                    f"{type(value).__name__}", source, SECTION, key))
            continue
        found = _range(key, value, source, units, problems)
        if found is not None:
            ranges[key] = found
    return ExploreSpec(MappingProxyType(ranges), show, frequency)


__all__ = ["ExploreRange", "ExploreSpec", "parse_explore"]
