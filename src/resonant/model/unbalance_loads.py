"""A rotor's ``[[unbalance]]`` as the load a time simulation integrates: the model with its
unbalance added as a ``[[harmonic]]`` of the speed parameter (docs/rotors.md, "The
unbalance in time").  A module of its own because it builds a :class:`Model` from the
``[campbell]`` section's data: beside ``campbell_spec`` (which ``types`` imports) it would
close a cycle of imports.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from ..expressions import parse
from .campbell_spec import unbalance_columns
from .matrix_spec import Harmonic
from .types import Model


def with_unbalance_loads(model: Model) -> Model:
    """The model with its ``[[unbalance]]`` as a ``[[harmonic]]`` load of circular
    frequency the speed parameter Omega, F_S and F_C = Omega^2 :func:`unbalance_columns`:
    the rotating load a time simulation integrates (docs/rotors.md).  The model itself
    where it has no unbalance, no ``[matrices]`` (a ``[rotor]`` is one) or no speed
    parameter.

    Examples
    --------
    >>> from resonant.model import load
    >>> rotor = with_unbalance_loads(load("examples/rotors/jeffcott_rotor.toml"))
    >>> h = rotor.matrices.harmonics[-1]
    >>> h.omega.text, [e.text for e in h.F_C]
    ('Omega', ['0.0001*Omega^2', '0'])
    """
    spec = model.matrices
    if not model.unbalances or spec is None or spec.speed is None:
        return model
    s, c = unbalance_columns(model.unbalances, model.coordinates)
    speed = spec.speed

    def column(values: np.ndarray) -> tuple[Any, ...]:
        # a round-off term (sin of 0 deg written as 1e-17) is no load
        return tuple(parse(f"{float(v)!r}*{speed}^2" if abs(v) > 1e-14 * np.abs(values).max()
                           else "0") for v in values)

    harmonic = Harmonic(parse(speed), column(s), column(c))
    return replace(model, matrices=replace(spec, harmonics=(*spec.harmonics, harmonic)))
