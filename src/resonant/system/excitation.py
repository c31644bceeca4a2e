"""The excitation columns in numbers: Q(t) = sum of column * d^order s / dt^order.

A harmonic analysis needs only the forcing of each frequency (:class:`Batch`); a random or
transient analysis needs the load of each signal derivative on its own, to apply its own
spectrum or time history.  :func:`excitation_columns` gives them at one parameter point
for every kind of system: from the numeric derivation where the system was derived
numerically, else the symbolic columns compiled once.

Examples
--------
>>> import resonant
>>> system = resonant.load("examples/base_excitation.toml").linearize()
>>> {v: c.tolist() for v, c in sorted(excitation_columns(system).items())}
{('y', 0): [4000.0], ('y', 1): [40.0]}
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..deadline import NO_DEADLINE, Deadline
from ..model import symbol
from .base import LinearSystem, NumericEOM, parameter_values
from .batch import Var, compile_expressions
from .symbolic import DeferredEOM, LinearEOM


def excitation_columns(system: LinearSystem, values: Mapping[str, float] | None = None,
                       deadline: Deadline = NO_DEADLINE) -> dict[Var, np.ndarray]:
    """The generalized-force column of every signal derivative, at one parameter point.

    Parameters
    ----------
    system : LinearSystem
    values : mapping, optional
        The parameter values (default: the model's, or those of a numeric system).
    deadline : Deadline, optional

    Returns
    -------
    dict
        ``(signal, order) -> ndarray (n,)``; empty for a system without signals (given
        matrices, or a numeric system without its model).
    """
    if isinstance(system, NumericEOM):
        if system.system is None:
            return {}
        return excitation_columns(system.system, values or dict(system.parameters), deadline)
    if not isinstance(system, LinearEOM) or system.model is None:
        return {}
    values = dict(values if values is not None else system.model.parameter_values)
    if isinstance(system, DeferredEOM):
        found = system.point(values, deadline)
        if found is not None:
            return {var: np.asarray(c, dtype=float).ravel().copy()
                    for var, c in found.excitation.items()}
    return _evaluated(system, values, ())


def _evaluated(system: LinearEOM, values: Mapping[str, Any], shape: tuple[int, ...]
               ) -> dict[Var, np.ndarray]:
    """The symbolic columns compiled once and evaluated at ``values`` (numbers, or arrays
    of ``shape``): (signal, order) -> (*shape, n)."""
    columns = sorted(system.excitation)
    if not columns:
        return {}
    n = system.n
    expressions: list[Any] = [system.excitation[var][i] for var in columns for i in range(n)]
    names = list(system.model.parameters) if system.model is not None else []
    compiled = compile_expressions(expressions, [symbol(name) for name in names])
    flat = np.asarray(compiled(*(np.broadcast_to(values[name], shape) for name in names)))
    flat = np.broadcast_to(flat, (len(columns) * n, *shape)).reshape(len(columns), n, -1)
    return {var: np.asarray(np.moveaxis(flat[k].real, 0, -1).reshape(*shape, n), dtype=float)
            for k, var in enumerate(columns)}


def excitation_columns_along(system: LinearSystem, param: str, values: np.ndarray,
                             deadline: Deadline = NO_DEADLINE
                             ) -> dict[Var, np.ndarray] | None:
    """The generalized-force column of every signal derivative at each value of one
    parameter (the others at the model's values, those defined from it following), in
    one compiled evaluation.

    Parameters
    ----------
    system : LinearSystem
    param : str
        The parameter that varies.
    values : ndarray
        Its values, (N,).
    deadline : Deadline, optional

    Returns
    -------
    dict or None
        ``(signal, order) -> ndarray (N, n)``; empty for a system without signals; None
        for a numerically derived system (a derivation at each value: not cheap).

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/base_excitation.toml").linearize()
    >>> {v: c.tolist() for v, c in sorted(excitation_columns_along(system, "k",
    ...                                                             [1000.0, 2000.0]).items())}
    {('y', 0): [[1000.0], [2000.0]], ('y', 1): [[40.0], [40.0]]}
    """
    values = np.asarray(values, dtype=float).ravel()
    if isinstance(system, NumericEOM):
        if system.system is None:
            return {}
        return _along(system.system, param, values, dict(system.parameters))
    return _along(system, param, values, None)


def _along(system: LinearSystem, param: str, values: np.ndarray,
           base: Mapping[str, float] | None) -> dict[Var, np.ndarray] | None:
    if isinstance(system, DeferredEOM):
        return None
    if not isinstance(system, LinearEOM) or system.model is None:
        return {}
    point = parameter_values(system.model, param, values, base=base)
    return _evaluated(system, point, values.shape)


def loaded_coordinates(system: LinearSystem, inputs: Sequence[str],
                       deadline: Deadline = NO_DEADLINE) -> dict[str, tuple[str, ...]]:
    """The coordinates each input's load acts on: a coordinate itself, a signal those where
    one of its load columns (of any derivative order, :func:`excitation_columns` at the
    model's values) is not zero.

    A signal that only enters outputs (feedthrough) acts on none; so does a name that is
    neither a signal nor a coordinate.

    Parameters
    ----------
    system : LinearSystem
    inputs : sequence of str
        Signals of the model or coordinates.
    deadline : Deadline, optional

    Returns
    -------
    dict
        Input -> its coordinates, in the system's order.

    Examples
    --------
    >>> import resonant
    >>> system = resonant.load("examples/chain3_lab.toml").linearize()
    >>> loaded_coordinates(system, ["F", "x1"])
    {'F': ('x3',), 'x1': ('x1',)}
    """
    coordinates = tuple(system.coordinates)
    columns = excitation_columns(system, deadline=deadline) if any(
        name not in coordinates for name in inputs) else {}
    found: dict[str, tuple[str, ...]] = {}
    for name in inputs:
        if name in coordinates:
            found[name] = (name,)
            continue
        loaded = np.zeros(len(coordinates), dtype=bool)
        for (signal, _), column in columns.items():
            if signal == name:
                loaded |= np.asarray(column) != 0
        found[name] = tuple(c for c, on in zip(coordinates, loaded, strict=True) if on)
    return found


__all__ = ["excitation_columns", "excitation_columns_along", "loaded_coordinates"]
