"""resonant: vibrations of discrete mechanical systems.

Describe a system by its energies (or matrices) in a TOML model file, then::

    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")            # doctest: +SKIP
    >>> eom = model.linearize()                                        # doctest: +SKIP
    >>> sol = eom.stationary()                                         # doctest: +SKIP
    >>> eom.modes(), eom.sweep("omega", [10, 20, 30]), model.simulate()  # doctest: +SKIP

The names below are those of :mod:`resonant.api` (the top of the library) and
the error types.  ``import resonant`` itself loads nothing heavy: the command
line starts through this package and must not pay for sympy-based analyses it
does not run, so :mod:`resonant.api` is imported on the first use of one of its
names (the scientific Python community's lazy-loading convention, SPEC 1; the
stub ``__init__.pyi`` states the same imports for editors and type checkers).
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

from .deadline import Deadline
from .errors import AnalysisError, ModelError, Problem, ResonantError

__version__ = "0.1.0"

#: the names taken from :mod:`resonant.api` on first use
API_NAMES = ("load", "loads", "Model", "linear_system", "stationary", "modes", "sweep", "simulate",
             "StationarySolution", "ModalAnalysis", "FrequencyResponse", "Simulation",
             "NonlinearResponse", "Backbones", "LinearSystem", "LinearEOM", "MatrixEOM",
             "NumericEOM", "StudyResult", "Campbell", "UnbalanceResponse", "MeasuredFRF",
             "ModalIdentification", "Correlation", "ModelUpdate", "StateSpaceModel",
             "MatrixChecks")

__all__ = ["AnalysisError", "Backbones", "Campbell", "Correlation", "Deadline",
           "FrequencyResponse", "LinearEOM", "LinearSystem", "MatrixChecks", "MatrixEOM",
           "MeasuredFRF", "ModalAnalysis", "ModalIdentification", "Model", "ModelError",
           "ModelUpdate", "NonlinearResponse", "NumericEOM", "Problem", "ResonantError",
           "Simulation", "StateSpaceModel", "StationarySolution", "StudyResult",
           "UnbalanceResponse", "__version__", "linear_system", "load", "loads", "modes",
           "simulate", "stationary", "sweep"]


def __getattr__(name: str) -> Any:
    if name in API_NAMES:
        return getattr(import_module("resonant.api"), name)
    raise AttributeError(f"module 'resonant' has no attribute '{name}'")


def __dir__() -> list[str]:
    return __all__
