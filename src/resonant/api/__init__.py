"""What ``import resonant`` offers, in one place: the names a user starts from.

Every class here is the one class of its concept, defined in its layer, with its
analyses and views as methods (``LinearSystem.stationary()``, ``FrequencyResponse.plot()``,
...); the model's analyses (``Model.linearize()``, ``Model.simulate()``, ...) are methods
of :class:`resonant.api.model.Model`, the model layer's data class with them added here,
at the top, so that the model layer reaches up for none of them.

Examples
--------
>>> import resonant.api as api
>>> model = api.load("examples/tuned_mass_damper.toml")
>>> len(model.linearize().modes().natural_frequencies)
2
>>> issubclass(api.Model, __import__("resonant.model", fromlist=["Model"]).Model)
True
"""

from __future__ import annotations

from ..analyses.backbone import Backbones
from ..analyses.modes import ModalAnalysis, modes
from ..analyses.nonlinear_response import NonlinearResponse
from ..analyses.simulate import Simulation, simulate
from ..analyses.stationary import StationarySolution, stationary
from ..analyses.sweep import FrequencyResponse, sweep
from ..studies.result import StudyResult
from ..system import LinearEOM, LinearSystem, MatrixEOM, NumericEOM, linear_system
from .model import Model, load, loads

__all__ = ["Backbones", "FrequencyResponse", "LinearEOM", "LinearSystem", "MatrixEOM",
           "ModalAnalysis", "Model", "NonlinearResponse", "NumericEOM", "Simulation",
           "StationarySolution", "StudyResult", "linear_system", "load", "loads", "modes",
           "simulate", "stationary", "sweep"]
