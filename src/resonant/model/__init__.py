"""Layer 2, the model: its types, the loader (TOML schema), matrix files and limits.

Imports only from :mod:`resonant.errors`, :mod:`resonant.deadline` and
:mod:`resonant.expressions`.
"""

from .loader import load, loads
from .matrix_spec import Harmonic, MatrixSpec
from .types import TIME, Force, Model, symbol

__all__ = ["load", "loads", "Model", "Force", "Harmonic", "MatrixSpec", "symbol", "TIME"]
