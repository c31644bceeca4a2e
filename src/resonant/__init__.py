"""resonant: vibrations of discrete mechanical systems.

Describe a system by its energies (or matrices) in a TOML model file, then::

    >>> import resonant
    >>> model = resonant.load("examples/cart_pendulum.toml")            # doctest: +SKIP
    >>> eom = model.linearize()                                        # doctest: +SKIP
    >>> sol = eom.stationary()                                         # doctest: +SKIP
    >>> eom.modes(), eom.sweep("omega", [10, 20, 30]), model.simulate()  # doctest: +SKIP

Imports are lazy: ``import resonant`` loads nothing heavy until it is used.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__version__ = "0.1.0"

_EXPORTS = {
    "load": "resonant.model", "loads": "resonant.model", "Model": "resonant.model",
    "linear_system": "resonant.system", "LinearSystem": "resonant.system",
    "LinearEOM": "resonant.system", "MatrixEOM": "resonant.system",
    "NumericEOM": "resonant.system",
    "stationary": "resonant.analyses.stationary", "modes": "resonant.analyses.modes",
    "sweep": "resonant.analyses.sweep", "simulate": "resonant.analyses.simulate",
    "StationarySolution": "resonant.analyses.stationary",
    "Simulation": "resonant.analyses.simulate", "ModalAnalysis": "resonant.analyses.modes",
    "FrequencyResponse": "resonant.analyses.sweep",
    "ResonantError": "resonant.errors", "ModelError": "resonant.errors",
    "AnalysisError": "resonant.errors", "Problem": "resonant.errors",
    "Deadline": "resonant.deadline",
}
# No package-level name equals a subpackage's name (``resonant.analyses`` is a package,
# ``resonant.sweep`` a function): an import of the subpackage would replace the function.

__all__ = sorted([*_EXPORTS, "__version__"])


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'resonant' has no attribute '{name}'")


def __dir__() -> list[str]:
    return __all__
