"""The top of the library: what ``import resonant`` offers, with every analysis as a method.

The layers below keep data and computation apart: the model layer's
:class:`resonant.model.Model` holds the validated model, the analyses take a
:class:`~resonant.system.LinearSystem` and return plain results, the views draw
them.  Here they meet: :func:`load` returns a :class:`Model` whose
``linearize()`` gives a system with ``stationary()``, ``modes()``, ``sweep()``,
whose results have ``summary()``, ``plot()`` and Jupyter reprs.  Every such
method is a one-line call of the function that does the work, written where
both are visible.

Examples
--------
>>> import resonant.api as api
>>> model = api.load("examples/tuned_mass_damper.toml")
>>> len(model.linearize().modes().natural_frequencies)
2
"""

from __future__ import annotations

from ..system import LinearEOM, LinearSystem, MatrixEOM, NumericEOM
from .model import Model, load, loads, simulate, with_methods
from .results import (
    Backbones,
    FrequencyResponse,
    ModalAnalysis,
    NonlinearResponse,
    Simulation,
    StationarySolution,
    promote,
)
from .systems import SystemMethods, linear_system, modes, stationary, sweep
from .systems import with_methods as system_with_methods

__all__ = ["Backbones", "FrequencyResponse", "LinearEOM", "LinearSystem", "MatrixEOM",
           "ModalAnalysis", "Model", "NumericEOM", "NonlinearResponse",
           "Simulation", "StationarySolution", "SystemMethods", "linear_system", "load",
           "loads", "modes", "promote", "simulate", "stationary", "sweep",
           "system_with_methods", "with_methods"]
