"""The array types the layers share in their signatures.

A system matrix (``M``, ``C``, ``K``) is a dense numpy array or a scipy sparse matrix;
scipy has no type information, so for mypy its part of :data:`Matrix` is open, but the
name says what a parameter takes.

Examples
--------
>>> import numpy as np
>>> from resonant.arrays import Matrix
>>> def size(a: Matrix) -> int:
...     return a.shape[0]
>>> size(np.eye(3))
3
"""

from __future__ import annotations

from typing import TYPE_CHECKING, TypeAlias, Union

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from scipy.sparse import sparray, spmatrix

__all__ = ["ComplexArray", "FloatArray", "Matrix"]

#: an array of floats
FloatArray: TypeAlias = npt.NDArray[np.float64]
#: an array of complex numbers
ComplexArray: TypeAlias = npt.NDArray[np.complex128]
#: a system matrix: a dense array or a scipy sparse matrix or array
Matrix: TypeAlias = Union["np.ndarray", "spmatrix", "sparray"]  # noqa: UP007
