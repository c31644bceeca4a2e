"""A nonlinear system at other parameter values: the same compiled equations, new numbers.

A :class:`~resonant.system.NonlinearSystem` carries the model's parameter
values; an analysis that sweeps one parameter changes that one
(:meth:`~resonant.system.NonlinearSystem.parameter_point`).  A parameter study
needs the system at every sample's values without compiling it again:
:func:`nonlinear_at` wraps the compiled system with other values of every
parameter, and its ``parameter_point`` changes the swept parameter on top of
them (parameters defined from the swept one follow it, the others keep the
sample's values).

Examples
--------
>>> import numpy as np, resonant
>>> from resonant.system import nonlinear_system
>>> base = nonlinear_system(resonant.load("examples/duffing.toml"))
>>> values = dict(zip(base.parameters, base.parameter_values))
>>> system = nonlinear_at(base, {**values, "k3": 2.0})
>>> float(system.parameter_point("omega", 1.5)[base.parameters.index("k3")])
2.0
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..errors import AnalysisError
from .base import parameter_values
from .nonlinear import NonlinearSystem


class NonlinearAt(NonlinearSystem):
    """The equations of ``base`` with every parameter at ``values``.

    Parameters
    ----------
    base : NonlinearSystem
        The compiled system.
    values : mapping
        A value for every parameter of ``base`` (those defined from others included).

    Examples
    --------
    See :func:`nonlinear_at`.
    """

    def __init__(self, base: NonlinearSystem, values: Mapping[str, float]) -> None:
        missing = [k for k in base.parameters if k not in values]
        if missing:
            raise AnalysisError(f"no value for the parameter '{missing[0]}'")
        self.base = base
        self.model, self.linear = base.model, base.linear
        self.coordinates, self.outputs = base.coordinates, base.outputs
        self.parameters, self.forcing_size = base.parameters, base.forcing_size
        self.unsupported_outputs = base.unsupported_outputs
        self.values = {k: float(values[k]) for k in base.parameters}
        self.parameter_values = np.array([self.values[k] for k in self.parameters])

    def reference(self, pvals: np.ndarray) -> np.ndarray:
        return self.base.reference(pvals)

    def forcing(self, t: np.ndarray, pvals: np.ndarray) -> np.ndarray:
        return self.base.forcing(t, pvals)

    def equations(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                  pvals: np.ndarray, damping: float = 1.0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.base.equations(q, qd, qdd, s, pvals, damping)

    def output_values(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, s: np.ndarray,
                      pvals: np.ndarray) -> dict[str, np.ndarray]:
        return self.base.output_values(q, qd, qdd, s, pvals)

    def base_frequency(self, pvals: np.ndarray) -> float:
        return self.base.base_frequency(pvals)

    def dynamics(self, t: float | np.ndarray, q: np.ndarray, qd: np.ndarray, pvals: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
        return self.base.dynamics(t, q, qd, pvals)

    def parameter_point(self, param: str, value: float) -> np.ndarray:
        """These values with ``param = value`` (parameters defined from it follow).

        Parameters
        ----------
        param : str
        value : float

        Returns
        -------
        numpy.ndarray
        """
        if param not in self._dependent:
            probe = parameter_values(self.model, param, np.array([1.0, 2.0]), self.values)
            self._dependent[param] = any(
                np.ndim(v) and np.ptp(np.asarray(v, dtype=float)) != 0
                for k, v in probe.items() if k != param)
        if self._dependent[param]:
            point = parameter_values(self.model, param, np.array([float(value)]), self.values)
            return np.array([float(np.asarray(point[k], dtype=float).ravel()[0])
                             for k in self.parameters])
        pvals = self.parameter_values.copy()
        pvals[self.parameters.index(param)] = value
        return pvals


def nonlinear_at(system: NonlinearSystem, values: Mapping[str, float]) -> NonlinearSystem:
    """``system`` with every parameter at ``values`` (nothing compiled again).

    Parameters
    ----------
    system : NonlinearSystem
    values : mapping
        parameter -> value, for every parameter of ``system``.

    Returns
    -------
    NonlinearSystem

    Raises
    ------
    AnalysisError
        When a parameter has no value.

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import nonlinear_system
    >>> base = nonlinear_system(resonant.load("examples/duffing.toml"))
    >>> values = dict(zip(base.parameters, base.parameter_values))
    >>> nonlinear_at(base, {**values, "F": 0.5}).parameter_values.tolist()[-2:]
    [0.5, 1.0]
    """
    base = system.base if isinstance(system, NonlinearAt) else system
    return NonlinearAt(base, values)


__all__ = ["NonlinearAt", "nonlinear_at"]
