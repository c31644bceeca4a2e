"""resonant: vibrations of discrete mechanical systems.

Describe a system by its energies (or matrices) in a TOML model file, then::

    >>> import resonant
    >>> model = resonant.load(resonant.example_path("cart_pendulum"))   # doctest: +SKIP
    >>> sol = model.linearize().stationary()                           # doctest: +SKIP

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
    "simulate": "resonant.simulate", "Simulation": "resonant.simulate",
    "modes": "resonant.modes", "ModalAnalysis": "resonant.modes",
    "sweep": "resonant.sweep", "FrequencyResponse": "resonant.sweep",
}

__all__ = sorted([*_EXPORTS, "__version__"])


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'resonant' has no attribute '{name}'")


def __dir__() -> list[str]:
    return __all__
