"""The ``[campbell]`` section (the speed range of a rotor's Campbell diagram) and the
``[[unbalance]]`` tables (the unbalances of its unbalance response); docs/rotors.md.

```toml
[campbell]
from = "0 rpm"        # a speed: a number (rad/s) or a value with a unit of angular speed
to = "6000 rpm"
points = 61           # the grid; refinement adds speeds where the tracking needs them
modes = 6             # the branches followed
orders = [1, 2]       # the excitation orders of the critical speeds
speed = "Omega"       # the speed parameter (default: [matrices] speed)

[[unbalance]]
at = "disc1"          # a station: its coordinates disc1_x, disc1_y (or "" for x, y)
amount = "1e-4 kg*m"  # m e
phase = "0 deg"       # the unbalance's angle from x at t = 0, towards y
```
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import Problem
from ..expressions import ExpressionError
from ..expressions.numeric import numeric_value
from .load_spec import quantity_parts
from .units import FREQUENCY, Unit, parse_with_unit

CAMPBELL_KEYS = ("from", "to", "points", "modes", "orders", "speed")
#: the most grid speeds of a Campbell diagram
MAX_POINTS = 100_000


@dataclass(frozen=True)
class CampbellSpec:
    """The ``[campbell]`` section.

    Parameters
    ----------
    start, stop : float
        The speed range (rad/s), start < stop.
    points : int
        The grid's speeds.
    modes : int
        The branches followed.
    orders : tuple of float
        The excitation orders.
    speed : str or None
        The speed parameter (None: the ``[matrices]`` one).

    Examples
    --------
    >>> problems = []
    >>> spec = parse_campbell({"from": 0, "to": "600 rpm"}, ["Omega"], "r.toml", problems)
    >>> round(spec.stop, 6), spec.points, problems
    (62.831853, 41, [])
    """

    start: float
    stop: float
    points: int = 41
    modes: int = 6
    orders: tuple[float, ...] = (1.0,)
    speed: str | None = None


def parse_speed(raw: object, source: str, section: str, key: str,
                problems: list[Problem], params: Sequence[str] = ()) -> float | None:
    """A speed: a number (rad/s) or text of arithmetic with a unit of angular speed (rpm,
    rad/s, rev/s; :func:`resonant.model.load_spec.quantity_parts`); Hz is refused (it
    would be read as cycles, not radians, per second), and so are the ``params``.

    Examples
    --------
    >>> problems = []
    >>> parse_speed("3000 rpm", "r.toml", "campbell", "to", problems)
    314.1592653589793
    >>> parse_speed("3 m/s", "r.toml", "campbell", "to", problems), len(problems)
    (None, 1)
    """
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        problems.append(Problem("must be a speed: a number (rad/s) or text such as "
                                "\"3000 rpm\"", source, section, key))
        return None
    unit: Unit | None = None
    if isinstance(raw, str):    # arithmetic and a unit, as every quantity key reads them
        parts = quantity_parts(raw, source, section, key, problems, params)
        if parts is None:
            return None
        value, unit = parts
    else:
        try:
            value = float(numeric_value(parse_with_unit(raw, [], source, section, key)[0], {}))
        except (ExpressionError, ValueError, TypeError) as exc:
            problems.append(Problem(f"not a speed: {exc}", source, section, key))
            return None
    if unit is not None and (unit.dimension != FREQUENCY or unit.cyclic):
        problems.append(Problem(f"{raw!r} is not an angular speed: use rpm, rad/s or rev/s "
                                "(Hz is refused: it counts cycles, not radians)", source,
                                section, key))
        return None
    if not math.isfinite(value) or value < 0:
        problems.append(Problem(f"must be a finite speed >= 0, got {raw!r}", source, section,
                                key))
        return None
    return value


def _count(data: dict, key: str, default: int, high: int, source: str,
           problems: list[Problem]) -> int:
    raw = data.get(key, default)
    if isinstance(raw, bool) or not isinstance(raw, int) or not 1 <= raw <= high:
        problems.append(Problem(f"must be an integer from 1 to {high}, got {raw!r}", source,
                                "campbell", key))
        return default
    return raw


def parse_campbell(data: object, params: Sequence[str], source: str,
                   problems: list[Problem]) -> CampbellSpec | None:
    """The ``[campbell]`` section, its problems appended to ``problems`` (None then).

    Parameters
    ----------
    data : Any
        The section as read from TOML.
    params : sequence of str
        The model's parameters (``speed`` names one).
    source : str
        The model file.
    problems : list of Problem

    Returns
    -------
    CampbellSpec or None

    Examples
    --------
    >>> problems = []
    >>> parse_campbell({"from": 10, "to": 5}, [], "r.toml", problems) is None
    True
    >>> print(problems[0])
    r.toml: [campbell] to: must be above from (10 rad/s)
    """
    count = len(problems)
    if not isinstance(data, dict):
        problems.append(Problem("expected a table", source, "campbell"))
        return None
    for key in data:
        if key not in CAMPBELL_KEYS:
            problems.append(Problem(f"unknown key; [campbell] takes {', '.join(CAMPBELL_KEYS)}",
                                    source, "campbell", str(key)))
    start = parse_speed(data.get("from", 0), source, "campbell", "from", problems, params)
    stop = parse_speed(data["to"], source, "campbell", "to", problems, params) \
        if "to" in data else None
    if "to" not in data:
        problems.append(Problem("missing: the highest speed", source, "campbell", "to"))
    if start is not None and stop is not None and stop <= start:
        problems.append(Problem(f"must be above from ({start:g} rad/s)", source, "campbell",
                                "to"))
    points = _count(data, "points", 41, MAX_POINTS, source, problems)
    if points < 2:
        problems.append(Problem("at least 2 speeds are needed", source, "campbell", "points"))
    modes = _count(data, "modes", 6, 10_000, source, problems)
    orders = data.get("orders", [1])
    if not isinstance(orders, list) or not orders or not all(
            isinstance(r, (int, float)) and not isinstance(r, bool) and math.isfinite(r)
            and r > 0 for r in orders):
        problems.append(Problem("must be a list of positive numbers (1 for unbalance)",
                                source, "campbell", "orders"))
        orders = [1]
    speed = data.get("speed")
    if speed is not None and speed not in params:
        problems.append(Problem(f"must name a parameter, got {speed!r}", source, "campbell",
                                "speed"))
    if len(problems) > count or start is None or stop is None:
        return None
    return CampbellSpec(start, stop, points, modes, tuple(float(r) for r in orders), speed)


UNBALANCE_KEYS = ("at", "amount", "phase")


@dataclass(frozen=True)
class Unbalance:
    """One unbalance: m e (kg m) at a station, at an angle (rad) from x towards y at t = 0.

    Parameters
    ----------
    station : str
        The station (its coordinates ``STATION_x``, ``STATION_y``; "" for ``x``, ``y``).
    amount : float
        m e (kg m).
    phase : float
        The angle (rad).
    """

    station: str
    amount: float
    phase: float = 0.0


def parse_unbalances(data: object, coordinates: Sequence[str], source: str,
                     problems: list[Problem]) -> tuple[Unbalance, ...]:
    """The ``[[unbalance]]`` tables, their problems appended to ``problems``.

    Examples
    --------
    >>> problems = []
    >>> parse_unbalances([{"at": "d", "amount": "1e-5 kg*m"}], ["d_x", "d_y"], "r.toml",
    ...                  problems)
    (Unbalance(station='d', amount=1e-05, phase=0.0),)
    """
    entries = data if isinstance(data, list) else [data]
    out = []
    for i, entry in enumerate(entries, start=1):
        where = f"unbalance {i}"
        if not isinstance(entry, dict):
            problems.append(Problem("expected a table", source, where))
            continue
        for key in set(entry) - set(UNBALANCE_KEYS):
            problems.append(Problem(f"unknown key; [[unbalance]] takes "
                                    f"{', '.join(UNBALANCE_KEYS)}", source, where, str(key)))
        station = entry.get("at", "")
        x, y = (f"{station}_x", f"{station}_y") if station else ("x", "y")
        if not isinstance(station, str) or x not in coordinates or y not in coordinates:
            problems.append(Problem(f"must name a station with coordinates {x} and {y}",
                                    source, where, "at"))
            continue
        amount = _constant(entry.get("amount"), source, where, "amount", problems)
        phase = _constant(entry.get("phase", 0), source, where, "phase", problems,
                          signed=True)
        if amount is not None and phase is not None:
            out.append(Unbalance(station, amount, phase))
    return tuple(out)


def unbalance_columns(unbalances: Sequence[Unbalance], coordinates: Sequence[str]
                      ) -> tuple[np.ndarray, np.ndarray]:
    """The sine and cosine columns of the unbalances' load per Omega^2: m e at angle phi
    on a station spinning at Omega loads it with m e Omega^2 (cos(Omega t + phi),
    sin(Omega t + phi)) = Omega^2 (c cos(Omega t) + s sin(Omega t)).

    Returns
    -------
    s, c : ndarray
        (n,) each, kg m (times Omega^2: N).

    Examples
    --------
    >>> s, c = unbalance_columns([Unbalance("", 2.0, math.pi / 2)], ["x", "y"])
    >>> s.round(12).tolist(), c.round(12).tolist()
    ([-2.0, 0.0], [0.0, 2.0])
    """
    index = {n: i for i, n in enumerate(coordinates)}
    s, c = np.zeros(len(coordinates)), np.zeros(len(coordinates))
    for u in unbalances:
        x, y = (index[f"{u.station}_x"], index[f"{u.station}_y"]) if u.station else \
            (index["x"], index["y"])
        # cos(W t + phi) = cos phi cos W t - sin phi sin W t; sin(W t + phi) likewise
        c[x] += u.amount * math.cos(u.phase)
        s[x] -= u.amount * math.sin(u.phase)
        c[y] += u.amount * math.sin(u.phase)
        s[y] += u.amount * math.cos(u.phase)
    return s, c


def _constant(raw: object, source: str, section: str, key: str, problems: list[Problem],
              signed: bool = False) -> float | None:
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        problems.append(Problem("must be a number or a value with a unit", source, section,
                                key))
        return None
    try:
        value = float(numeric_value(parse_with_unit(raw, [], source, section, key)[0], {}))
    except (ExpressionError, ValueError, TypeError) as exc:
        problems.append(Problem(f"not a constant: {exc}", source, section, key))
        return None
    if not math.isfinite(value) or (not signed and value <= 0):
        problems.append(Problem(f"must be {'finite' if signed else 'positive'}, got {raw!r}",
                                source, section, key))
        return None
    return value


__all__ = ["CampbellSpec", "parse_campbell", "parse_speed", "CAMPBELL_KEYS", "Unbalance",
           "parse_unbalances", "UNBALANCE_KEYS", "unbalance_columns"]
