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
from ..analyses.campbell import Campbell
from ..analyses.correlate import Correlation
from ..analyses.fe_checks import MatrixChecks
from ..analyses.frf_estimate import MeasuredFRF
from ..analyses.identify import ModalIdentification
from ..analyses.model_update import ModelUpdate
from ..analyses.modes import ModalAnalysis, modes
from ..analyses.nonlinear_response import NonlinearResponse
from ..analyses.simulate import Simulation, simulate
from ..analyses.state_space import StateSpaceModel
from ..analyses.stationary import StationarySolution, stationary
from ..analyses.sweep import FrequencyResponse, sweep
from ..analyses.unbalance import UnbalanceResponse
from ..studies.result import StudyResult
from ..system import LinearEOM, LinearSystem, MatrixEOM, NumericEOM, linear_system
from .model import Model, load, loads

__all__ = ["Backbones", "Campbell", "Correlation", "FrequencyResponse", "LinearEOM",
           "LinearSystem", "MatrixChecks", "MatrixEOM", "MeasuredFRF", "ModalAnalysis",
           "ModalIdentification", "Model", "ModelUpdate", "NonlinearResponse", "NumericEOM",
           "Simulation", "StateSpaceModel", "StationarySolution", "StudyResult",
           "UnbalanceResponse", "linear_system", "load", "loads", "modes", "simulate",
           "stationary", "sweep"]
