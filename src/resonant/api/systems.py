"""The linear systems as the user gets them: every analysis one method call away.

:class:`SystemMethods` adds ``stationary()``, ``modes()`` and ``sweep()`` (and the
Jupyter LaTeX repr) to the system layer's types; each method is a one-line call
of its analysis, written here where both are visible (the system layer below
knows nothing of the analyses).  :func:`with_methods` gives a system of the
system layer these methods, :func:`linear_system` derives one from a model.

Examples
--------
>>> import resonant
>>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
>>> type(eom).__name__, round(eom.stationary().amplitudes["x2"], 5)
('LinearEOM', 0.04514)
>>> len(eom.modes().natural_frequencies)
2
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import system as system_layer
from ..analyses import modes as modes_analysis
from ..analyses import stationary as stationary_analysis
from ..analyses import sweep as sweep_analysis
from ..deadline import NO_DEADLINE, Deadline
from ..model import Model
from ..system import base, matrix, symbolic
from ..views import display
from .results import FrequencyResponse, ModalAnalysis, StationarySolution, promote

__all__ = ["DeferredEOM", "LinearEOM", "MatrixEOM", "NumericEOM", "SystemMethods",
           "linear_system", "with_methods"]


class SystemMethods(base.LinearSystem):
    """The analyses of a :class:`~resonant.system.LinearSystem` as its methods.

    Mixed into each system type by :func:`with_methods`; each method is one call of its
    analysis in :mod:`resonant.analyses`, its result promoted to the class with views.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/two_dof_free.toml").linearize()
    >>> isinstance(eom, SystemMethods), eom.modes().natural_frequencies.round(3).tolist()
    (True, [20.0, 34.641])
    """

    def stationary(self, deadline: Deadline = NO_DEADLINE, **overrides: float | str
                   ) -> StationarySolution:
        """The stationary solution for harmonic excitation
        (:func:`resonant.analyses.stationary.stationary`).

        Parameters
        ----------
        deadline : Deadline, optional
            The run's time limit.
        **overrides
            Parameter values replacing the model's (numbers or expression text).

        Returns
        -------
        StationarySolution
        """
        return promote(StationarySolution,
                       stationary_analysis.stationary(self, deadline, **overrides))

    def modes(self, count: int | None = None, deadline: Deadline = NO_DEADLINE
              ) -> ModalAnalysis:
        """Natural frequencies, mode shapes, damping ratios
        (:func:`resonant.analyses.modes.modes`).

        Parameters
        ----------
        count : int, optional
            Only the ``count`` lowest modes.
        deadline : Deadline, optional
            The run's time limit.

        Returns
        -------
        ModalAnalysis
        """
        return promote(ModalAnalysis, modes_analysis.modes(self, count, deadline))

    def sweep(self, param: str, values: Sequence[float] | np.ndarray, **options: Any
              ) -> FrequencyResponse:
        """Amplitudes and phases against a parameter
        (:func:`resonant.analyses.sweep.sweep`).

        Parameters
        ----------
        param : str
            The parameter to vary.
        values : array_like
            Its values.
        **options
            ``method``, ``names``, ``tol``, ``deadline``, ...: passed on.

        Returns
        -------
        FrequencyResponse
        """
        return promote(FrequencyResponse,
                       sweep_analysis.sweep(self, param, values, **options))

    def numeric(self, deadline: Deadline = NO_DEADLINE, **overrides: float | str
                ) -> NumericEOM:
        """The equation of motion with the parameter values substituted.

        Parameters
        ----------
        deadline : Deadline, optional
            The run's time limit.
        **overrides
            Parameter values replacing the model's.

        Returns
        -------
        NumericEOM
        """
        return promote(NumericEOM, super().numeric(deadline, **overrides))


class LinearEOM(SystemMethods, symbolic.LinearEOM):
    """:class:`resonant.system.LinearEOM` (derived from energies) with its analyses."""

    def _repr_latex_(self) -> str:
        return display.eom_latex(self)


class DeferredEOM(SystemMethods, symbolic.DeferredEOM):
    """:class:`resonant.system.symbolic.DeferredEOM` (a large energy model) with its
    analyses."""

    def _repr_latex_(self) -> str:
        return display.eom_latex(self)


class MatrixEOM(SystemMethods, matrix.MatrixEOM):
    """:class:`resonant.system.MatrixEOM` (``[matrices]``) with its analyses."""

    def _repr_latex_(self) -> str:
        return display.eom_latex(self)


class NumericEOM(SystemMethods, base.NumericEOM):
    """:class:`resonant.system.NumericEOM` (numbers at one point) with its analyses."""

    def _repr_latex_(self) -> str:
        return display.numeric_eom_latex(self)


def with_methods(system: base.LinearSystem) -> SystemMethods:
    """The same system with the analyses as its methods.

    Parameters
    ----------
    system : LinearSystem
        A system of the system layer.

    Returns
    -------
    SystemMethods
        The same data (shared, not copied) as the matching class of this module.

    Raises
    ------
    TypeError
        For a kind of system this module does not know.

    Examples
    --------
    >>> import numpy as np
    >>> from resonant.system import NumericEOM as Plain
    >>> one = Plain(coordinates=("x",), M=np.eye(1), C=np.zeros((1, 1)), K=np.eye(1))
    >>> float(with_methods(one).modes().natural_frequencies[0])
    1.0
    """
    if isinstance(system, SystemMethods):
        return system
    if isinstance(system, symbolic.DeferredEOM):
        return promote(DeferredEOM, system)
    if isinstance(system, symbolic.LinearEOM):
        return promote(LinearEOM, system)
    if isinstance(system, matrix.MatrixEOM):
        return promote(MatrixEOM, system)
    if isinstance(system, base.NumericEOM):
        return promote(NumericEOM, system)
    raise TypeError(f"no analyses are known for a {type(system).__name__}")


def linear_system(model: Model, deadline: Deadline = NO_DEADLINE) -> SystemMethods:
    """The linear system of a model, with the analyses as its methods
    (:func:`resonant.system.linear_system`).

    Parameters
    ----------
    model : Model
        A loaded model.
    deadline : Deadline, optional
        Checked throughout the derivation.

    Returns
    -------
    SystemMethods

    Raises
    ------
    ModelError
        If the derivation fails or exceeds the time limit.

    Examples
    --------
    >>> import resonant
    >>> linear_system(resonant.load("examples/two_dof_free.toml")).n
    2
    """
    return with_methods(system_layer.linear_system(model, deadline))


def stationary(system: base.LinearSystem, deadline: Deadline = NO_DEADLINE,
               **overrides: float | str) -> StationarySolution:
    """The stationary solution of a system (:meth:`SystemMethods.stationary`).

    Parameters
    ----------
    system : LinearSystem
    deadline : Deadline, optional
    **overrides
        Parameter values replacing the model's.

    Returns
    -------
    StationarySolution

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> round(stationary(eom, k=120).amplitudes["x1"], 6) != round(
    ...     stationary(eom).amplitudes["x1"], 6)
    True
    """
    return with_methods(system).stationary(deadline, **overrides)


def modes(system: base.LinearSystem, count: int | None = None,
          deadline: Deadline = NO_DEADLINE) -> ModalAnalysis:
    """Natural frequencies, mode shapes and damping ratios (:meth:`SystemMethods.modes`).

    Parameters
    ----------
    system : LinearSystem
    count : int, optional
        Only the ``count`` lowest modes.
    deadline : Deadline, optional

    Returns
    -------
    ModalAnalysis

    Examples
    --------
    >>> import resonant
    >>> len(modes(resonant.load("examples/chain3_damped.toml").linearize(), 2).damping_ratios)
    2
    """
    return with_methods(system).modes(count, deadline)


def sweep(system: base.LinearSystem, param: str, values: Sequence[float] | np.ndarray,
          **options: Any) -> FrequencyResponse:
    """Amplitudes and phases against a parameter (:meth:`SystemMethods.sweep`).

    Parameters
    ----------
    system : LinearSystem
    param : str
        The parameter to vary.
    values : array_like
        Its values.
    **options
        Passed on to :func:`resonant.analyses.sweep.sweep`.

    Returns
    -------
    FrequencyResponse

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> sweep(eom, "omega", [10.0, 20.0]).values.tolist()
    [10.0, 20.0]
    """
    return with_methods(system).sweep(param, values, **options)
