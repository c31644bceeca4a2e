"""Layer 4, the system: the one linear-system type every analysis takes, and the
nonlinear-system type (:class:`NonlinearSystem`: the full equations of motion, compiled
once, :func:`nonlinear_system`) the analyses beyond small oscillations take.

:func:`linear_system` turns a model into its :class:`LinearSystem`: a
:class:`LinearEOM` (derived from energies by :mod:`resonant.derivation`) or a
:class:`MatrixEOM` (``[matrices]``).  Numbers come as :class:`NumericEOM` (one
parameter point) or :class:`Batch` (many).
"""

from __future__ import annotations

from ..deadline import NO_DEADLINE, Deadline
from ..model import Model
from .base import (
    LinearSystem,
    NumericEOM,
    NumericHarmonic,
    NumericOutput,
    parameter_values,
)
from .batch import Batch, BatchHarmonic
from .matrix import MatrixEOM
from .nonlinear import EnergySystem, NonlinearSystem, nonlinear_system
from .nonlinear_at import NonlinearAt, nonlinear_at
from .symbolic import LinearEOM


def linear_system(model: Model, deadline: Deadline = NO_DEADLINE) -> LinearSystem:
    """The linear system of a model: derived from its energies, or its given matrices.

    Parameters
    ----------
    model : Model
    deadline : Deadline, optional
        Checked throughout the derivation.

    Returns
    -------
    LinearSystem

    Raises
    ------
    ModelError
        If the derivation fails (see :func:`resonant.derivation.linearize`).

    Examples
    --------
    >>> import resonant
    >>> type(linear_system(resonant.load("examples/two_dof_free.toml"))).__name__
    'LinearEOM'
    """
    if model.matrices is not None:
        return MatrixEOM(model, model.coordinates)
    return LinearEOM.of_model(model, deadline)


__all__ = ["LinearSystem", "LinearEOM", "MatrixEOM", "NumericEOM", "NumericHarmonic",
           "NumericOutput", "Batch", "BatchHarmonic", "linear_system", "parameter_values",
           "NonlinearSystem", "EnergySystem", "nonlinear_system", "NonlinearAt", "nonlinear_at"]
