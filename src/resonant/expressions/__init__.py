"""Layer 1, expressions: the safe parser of the model language, its function table and
numeric evaluation.  Imports only :mod:`resonant.errors`."""

from .functions import FUNCTIONS, Function
from .numeric import FloatOps, compilable, numeric_value
from .parser import (
                     MAX_NUMBER,
                     MIN_NUMBER,
                     BinOp,
                     Call,
                     Expression,
                     ExpressionError,
                     Name,
                     Neg,
                     Num,
                     parse,
                     primed_names,
                     validate_name,
)

__all__ = ["FUNCTIONS", "Function", "FloatOps", "compilable", "numeric_value",
           "BinOp", "Call", "Expression",
           "ExpressionError", "Name", "Neg", "Num", "parse", "primed_names", "validate_name",
           "MAX_NUMBER", "MIN_NUMBER"]
