"""Layer 5, the analyses: the one harmonic kernel and what is built on it (stationary
solution, sweeps), modes, and time simulation.  Every analysis takes a
:class:`~resonant.system.LinearSystem` and returns a frozen result."""

# The analysis functions stay in their modules (``resonant.analyses.sweep.sweep``): a
# package attribute named like a submodule would be replaced by the module on import.
from .kernel import solve_harmonic
from .modes import ModalAnalysis
from .simulate import Simulation
from .stationary import HarmonicResponse, StationarySolution
from .sweep import Extremum, FrequencyResponse

__all__ = ["solve_harmonic", "ModalAnalysis", "Simulation", "HarmonicResponse",
           "StationarySolution", "Extremum", "FrequencyResponse"]
