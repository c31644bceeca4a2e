"""The array types the layers share in their signatures, and read-only arrays.

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

from collections.abc import Mapping
from dataclasses import fields
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, TypeAlias, TypeVar, Union

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from _typeshed import DataclassInstance
    from scipy.sparse import sparray, spmatrix

__all__ = ["ComplexArray", "FloatArray", "Matrix", "frozen_array", "freeze_fields"]

_T = TypeVar("_T")

#: an array of floats
FloatArray: TypeAlias = npt.NDArray[np.float64]
#: an array of complex numbers
ComplexArray: TypeAlias = npt.NDArray[np.complex128]
#: a system matrix: a dense array or a scipy sparse matrix or array
Matrix: TypeAlias = Union["np.ndarray", "spmatrix", "sparray"]  # noqa: UP007


def frozen_array(a: _T) -> _T:
    """A read-only view of an array (sparse matrices and non-arrays pass unchanged).

    Examples
    --------
    >>> frozen_array(np.zeros(2)).flags.writeable
    False
    """
    if isinstance(a, np.ndarray):
        a = a.view()
        a.flags.writeable = False
    return a


def freeze_fields(result: DataclassInstance) -> None:
    """Make a frozen dataclass's arrays read-only, in place (for ``__post_init__``): what
    every result of an analysis does.

    Every ndarray field becomes a read-only view (:func:`frozen_array`), and so does every
    ndarray value of a mapping field (the mapping is then replaced by a read-only
    ``MappingProxyType``).  Other fields are left as they are.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Result:
    ...     values: np.ndarray
    ...     def __post_init__(self) -> None:
    ...         freeze_fields(self)
    >>> Result(np.ones(2)).values.flags.writeable
    False
    """
    for f in fields(result):
        value: Any = getattr(result, f.name)
        if isinstance(value, np.ndarray):
            object.__setattr__(result, f.name, frozen_array(value))
        elif isinstance(value, Mapping) and any(isinstance(v, np.ndarray)
                                                for v in value.values()):
            object.__setattr__(result, f.name, MappingProxyType(
                {k: frozen_array(v) for k, v in value.items()}))
