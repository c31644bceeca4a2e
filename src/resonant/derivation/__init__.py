"""Layer 3, the derivation: second-order jets, Lagrange's equations, the full nonlinear
equations and the harmonic split of the signals.  Imports from the model layer and below;
:mod:`resonant.system` turns its results into linear systems."""

from .harmonics import SignalHarmonics, decompose, decompose_signals
from .jet import Jet, Var
from .lagrange import Linearization, LinearMap, linearize, signal_symbol
from .nonlinear import (
           NonlinearEquations,
           derivative_symbol,
           find_equilibrium,
           nonlinear_equations,
)

__all__ = ["SignalHarmonics", "decompose", "decompose_signals", "Jet", "Var", "LinearMap",
           "Linearization", "linearize", "signal_symbol", "NonlinearEquations",
           "derivative_symbol", "find_equilibrium", "nonlinear_equations"]
