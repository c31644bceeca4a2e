"""Accelerations shown in g where the model's input is given in g.

A shaker's spectrum written in g^2/Hz, a shock pulse of 50 g: the engineer reads the
response in the unit the input was given in.  Where a ``[random]`` density, the
``[shock]`` pulse or the ``[periodic]`` load is given in g (standard gravity,
9.80665 m/s^2), accelerations are shown in g by default, as if ``[display]`` said
``acceleration = "g"``; ``[display]`` and the command line's units choose otherwise.  The
numbers computed and JSON stay SI.

Examples
--------
>>> from resonant.model import loads
>>> model = loads('''
... [parameters]
... m = "1 kg"
... k = "1e4 N/m"
... [coordinates]
... x = { description = "absolute displacement", unit = "m" }
... [signals]
... y = "0"
... [energy]
... T = "m*x'^2/2"
... U = "k*(x - y)^2/2"
... [shock]
... signal = "y"
... derivative = 2
... pulse = "half-sine"
... amplitude = 50
... unit = "g"
... duration = 0.011
... ''')
>>> model.units.display["acceleration"].text
'g'
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from types import MappingProxyType
from typing import Any

from .random_spec import RandomSpec
from .units import GRAVITY_IN_UNIT, STANDARD_GRAVITY_UNIT, ModelUnits, split_value

#: the sections that give one input with a ``unit`` key
_INPUT_SECTIONS = ("shock", "periodic")


def given_in_g(random: RandomSpec | None, data: Mapping[str, Any]) -> bool:
    """Whether a ``[random]`` density or the ``[shock]`` / ``[periodic]`` input is given in g.

    Parameters
    ----------
    random : RandomSpec or None
        The parsed ``[random]`` section (each input keeps its unit as written).
    data : mapping
        The model file's tables (``[shock]`` and ``[periodic]`` as written).

    Examples
    --------
    >>> given_in_g(None, {"shock": {"unit": "g"}}), given_in_g(None, {"shock": {"unit": "kg"}})
    (True, False)
    """
    if random is not None and any(GRAVITY_IN_UNIT.search(u.unit) for u in random.inputs):
        return True
    for name in _INPUT_SECTIONS:
        section = data.get(name)
        if not isinstance(section, Mapping):
            continue
        unit, amplitude = section.get("unit"), section.get("amplitude")
        if isinstance(amplitude, str) and unit is None:   # "50 g": the amplitude's own unit
            unit = split_value(amplitude)[1]
        if isinstance(unit, str) and GRAVITY_IN_UNIT.search(unit):
            return True
    return False


def gravity_default(units: ModelUnits | None, in_g: bool) -> ModelUnits | None:
    """The model's units with accelerations shown in g when its input is (``in_g``) and
    ``[display]`` chose no unit of acceleration.

    Examples
    --------
    >>> gravity_default(None, True).display["acceleration"].text, gravity_default(None, False)
    ('g', None)
    """
    if not in_g or (units is not None and "acceleration" in units.display):
        return units
    own = units or ModelUnits()
    return replace(own, display=MappingProxyType({**own.display,
                                                  "acceleration": STANDARD_GRAVITY_UNIT}))


__all__ = ["given_in_g", "gravity_default"]
