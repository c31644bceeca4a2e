"""Layer 4, the system: the one linear-system type every analysis takes, and the
nonlinear-system type (:class:`NonlinearSystem`: the full equations of motion, compiled
once, :func:`nonlinear_system`) the analyses beyond small oscillations take.

:func:`linear_system` turns a model into its :class:`LinearSystem`: a
:class:`LinearEOM` (derived from energies by :mod:`resonant.derivation`) or a
:class:`MatrixEOM` (``[matrices]``).  Numbers come as :class:`NumericEOM` (one
parameter point) or :class:`Batch` (many).
"""

from __future__ import annotations

from .base import (
    LinearSystem,
    NumericEOM,
    NumericHarmonic,
    NumericOutput,
    parameter_values,
)
from .batch import Batch, BatchHarmonic
from .build import linear_system, nonlinear_system
from .element_system import ElementSystem
from .matrix import MatrixEOM
from .nonlinear import EnergySystem, NonlinearSystem, nonlinear_only
from .nonlinear_at import NonlinearAt, nonlinear_at
from .symbolic import LinearEOM

__all__ = ["LinearSystem", "LinearEOM", "MatrixEOM", "NumericEOM", "NumericHarmonic",
           "NumericOutput", "Batch", "BatchHarmonic", "linear_system", "parameter_values",
           "NonlinearSystem", "EnergySystem", "ElementSystem", "nonlinear_system", "NonlinearAt",
           "nonlinear_at", "nonlinear_only"]
