# What ``import resonant`` offers, for editors and type checkers (the module itself
# imports resonant.api on first use: see its docstring).
from .api import Backbones as Backbones
from .api import Campbell as Campbell
from .api import Correlation as Correlation
from .api import FrequencyResponse as FrequencyResponse
from .api import LinearEOM as LinearEOM
from .api import LinearSystem as LinearSystem
from .api import MatrixChecks as MatrixChecks
from .api import MatrixEOM as MatrixEOM
from .api import MeasuredFRF as MeasuredFRF
from .api import ModalAnalysis as ModalAnalysis
from .api import ModalIdentification as ModalIdentification
from .api import Model as Model
from .api import ModelUpdate as ModelUpdate
from .api import NonlinearResponse as NonlinearResponse
from .api import NumericEOM as NumericEOM
from .api import Simulation as Simulation
from .api import StateSpaceModel as StateSpaceModel
from .api import StationarySolution as StationarySolution
from .api import StudyResult as StudyResult
from .api import UnbalanceResponse as UnbalanceResponse
from .api import linear_system as linear_system
from .api import load as load
from .api import loads as loads
from .api import modes as modes
from .api import simulate as simulate
from .api import stationary as stationary
from .api import sweep as sweep
from .deadline import Deadline as Deadline
from .errors import AnalysisError as AnalysisError
from .errors import ModelError as ModelError
from .errors import Problem as Problem
from .errors import ResonantError as ResonantError

__version__: str
API_NAMES: tuple[str, ...]
