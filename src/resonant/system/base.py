"""The one linear-system type that every analysis takes.

:class:`LinearSystem` is M q'' + C q' + K q = Q(t) about the reference state of
a model, with three implementations:

* :class:`~resonant.system.symbolic.LinearEOM` -- derived from energies, entries in
  the model's own symbols;
* :class:`~resonant.system.matrix.MatrixEOM` -- a ``[matrices]`` model (inline
  expressions or matrix files, dense or sparse);
* :class:`~resonant.system.numeric.NumericEOM` -- numbers at one parameter point
  (what :meth:`LinearSystem.numeric` returns; also a system in its own right).

Every analysis asks the system for numbers in one of two ways:
:meth:`numeric` (one parameter point) or :meth:`batch` (a parameter running
through an array of values, for sweeps).  The analyses never look at which
kind of system they hold.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import hooks
from ..deadline import NO_DEADLINE, Deadline
from ..errors import ModelError, Problem
from ..expressions import numeric_value
from ..model import Model

if TYPE_CHECKING:  # pragma: no cover
    from .numeric import Batch, NumericEOM


class LinearSystem(ABC):
    """M q'' + C q' + K q = Q(t): the interface every analysis uses.

    Attributes
    ----------
    coordinates : tuple of str
        The generalized coordinates, in order.
    model : Model or None
        The model it comes from (None for a bare :class:`NumericEOM`).
    """

    coordinates: tuple[str, ...]
    model: Model | None

    @property
    def n(self) -> int:
        """The number of coordinates."""
        return len(self.coordinates)

    @property
    def title(self) -> str:
        """The model's title ("" without a model)."""
        return self.model.title if self.model is not None else ""

    @property
    def source(self) -> str:
        """The model file ("" without a model)."""
        return self.model.source if self.model is not None else ""

    # -- numbers ---------------------------------------------------------------------------
    @abstractmethod
    def evaluate(self, values: Mapping[str, Any], count: int,
                 deadline: Deadline = NO_DEADLINE) -> "Batch":
        """Every matrix, load and output coefficient for the parameter ``values``.

        Parameters
        ----------
        values : mapping
            Every parameter's value: a float, or an array of ``count`` values.
        count : int
            The number of parameter points.
        deadline : Deadline, optional

        Returns
        -------
        Batch
        """

    def numeric(self, deadline: Deadline = NO_DEADLINE, **overrides: float | str
                ) -> "NumericEOM":
        """The equation of motion with the parameter values substituted.

        Parameters
        ----------
        deadline : Deadline, optional
        **overrides
            Parameter values replacing the model's (numbers or expression text).

        Returns
        -------
        NumericEOM
        """
        model = self._model()
        if overrides:
            model = model.with_parameters(**overrides)
        values = dict(model.parameter_values)
        return self.evaluate(values, 1, deadline).point(0, self, values)

    def batch(self, param: str, values: np.ndarray, deadline: Deadline = NO_DEADLINE
              ) -> "Batch":
        """The system while ``param`` runs through ``values`` (parameters defined from it
        follow it).

        Parameters
        ----------
        param : str
            A parameter of the model.
        values : ndarray
            Its values, shape (N,).
        deadline : Deadline, optional

        Returns
        -------
        Batch
        """
        values = np.asarray(values, dtype=float)
        return self.evaluate(parameter_values(self._model(), param, values), len(values),
                             deadline)

    def _model(self) -> Model:
        if self.model is None:
            raise ModelError("this system has no model: its parameters cannot change")
        return self.model

    # -- conveniences: one-line delegates to the analyses ------------------------------------
    def stationary(self, **overrides: float | str) -> Any:
        """The stationary solution for harmonic excitation
        (:func:`resonant.analyses.stationary.stationary`).

        Parameters
        ----------
        **overrides
            Parameter values replacing the model's.

        Returns
        -------
        StationarySolution
        """
        return hooks.call("stationary", self, **overrides)

    def modes(self, count: int | None = None, **options: Any) -> Any:
        """Natural frequencies, mode shapes, damping ratios
        (:func:`resonant.analyses.modes.modes`).

        Parameters
        ----------
        count : int, optional
            Only the ``count`` lowest modes.
        **options
            Passed on.

        Returns
        -------
        ModalAnalysis
        """
        return hooks.call("modes", self, count=count, **options)

    def sweep(self, param: str, values: Any, **options: Any) -> Any:
        """Amplitudes and phases against a parameter (:func:`resonant.analyses.sweep.sweep`).

        Parameters
        ----------
        param : str
            The parameter to vary.
        values : array_like
            Its values.
        **options
            Passed on.

        Returns
        -------
        FrequencyResponse
        """
        return hooks.call("sweep", self, param, values, **options)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form of the equation of motion (coordinates, M, C, K, Q as text).

        Returns
        -------
        dict
        """
        return {}

    def symbolic_dict(self) -> dict[str, Any] | None:
        """The symbolic form for the JSON of a solution, where it says more than the
        numbers (derived equations); None for given matrices.

        Returns
        -------
        dict or None
        """
        return None

    def _repr_latex_(self) -> str:
        return str(hooks.call("eom_latex", self))


def parameter_values(model: Model, param: str, values: np.ndarray,
                     base: Mapping[str, float] | None = None) -> dict[str, Any]:
    """Every parameter's value with ``param`` set to the array ``values``.

    Parameters defined by expressions of ``param`` follow it (evaluated
    elementwise); the others keep the model's values exactly.

    Parameters
    ----------
    model : Model
    param : str
        The parameter that varies.
    values : ndarray
        Its values.
    base : mapping, optional
        The values of the other parameters (default: the model's).

    Returns
    -------
    dict
        name -> float or ndarray.

    Raises
    ------
    ModelError
        For an unknown parameter, or a dependent parameter that is not finite.
    """
    if param not in model.parameters:
        import difflib

        close = difflib.get_close_matches(param, list(model.parameters), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else \
            f"; the parameters are {', '.join(list(model.parameters)[:20]) or 'none'}"
        raise ModelError(Problem(f"cannot sweep unknown parameter '{param}'{hint}",
                                 model.source, "parameters", param))
    out: dict[str, Any] = {}
    varying = {param}
    for name, expression in model.parameters.items():
        if name == param:
            out[name] = values
        elif any(n in varying for n, _ in expression.names()):
            value = np.broadcast_to(np.asarray(numeric_value(expression, out), dtype=float),
                                    values.shape)
            bad = ~np.isfinite(value)
            if bad.any():
                raise ModelError(Problem(
                    f"{name} = {expression.text} is not finite for {param} = "
                    f"{values[np.argmax(bad)]:.6g}", model.source, "parameters", name))
            out[name] = value
            varying.add(name)
        else:
            out[name] = (base or model.parameter_values)[name]
    return out


__all__ = ["LinearSystem", "parameter_values"]
