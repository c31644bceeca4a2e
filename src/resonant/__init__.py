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
    "linearize": "resonant.linearize", "LinearEOM": "resonant.linearize",
    "NumericEOM": "resonant.numeric", "stationary": "resonant.stationary",
    "StationarySolution": "resonant.stationary",
    "ResonantError": "resonant.errors", "ModelError": "resonant.errors",
    "AnalysisError": "resonant.errors", "ResonantWarning": "resonant.errors",
    "Problem": "resonant.errors",
    "Simulation": "resonant.simulate", "ModalAnalysis": "resonant.modes",
    "FrequencyResponse": "resonant.sweep",
}
# The analyses are methods (``eom.modes()``, ``eom.sweep(...)``, ``model.simulate(...)``) or
# functions of their modules (``resonant.sweep.sweep``): a package-level function named like
# its submodule would be replaced by the module as soon as the submodule is imported.

__all__ = sorted([*_EXPORTS, "__version__"])


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'resonant' has no attribute '{name}'")


def __dir__() -> list[str]:
    return __all__
