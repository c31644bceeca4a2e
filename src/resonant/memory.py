"""The memory budget: the most one analysis may hold in one working array or result.

Every analysis whose arrays grow with what it is asked for (time steps x states, spectral
lines x responses, harmonics x coordinates) estimates their size from the sizes it is given
*before* it allocates them, and streams, chunks or refuses above the budget: a refusal is an
:class:`~resonant.errors.AnalysisError` (exit 3) that gives the size and how to ask for
less, never a ``MemoryError`` half-way through the work.

The budget is :data:`DEFAULT_BUDGET` (1 GiB), or the environment variable
``RESONANT_MEMORY`` (``"512M"``, ``"4G"``, ``"1.5GiB"``, or a number of bytes).

Examples
--------
>>> require(8 * 10**6, "the history", "ask for fewer samples")    # 8 MB: fine
>>> require(10**13, "the history", "ask for fewer samples")
Traceback (most recent call last):
resonant.errors.AnalysisError: the history would take 9.09 TiB of memory, above the budget \
of 1 GiB (RESONANT_MEMORY): ask for fewer samples
"""

from __future__ import annotations

import math
import os
import re

import numpy as np
import numpy.typing as npt

from .arrays import Matrix
from .errors import AnalysisError, ModelError, Problem

#: the budget without ``RESONANT_MEMORY``
DEFAULT_BUDGET = 2**30
#: what a chunked loop holds at once (a small share of the budget)
CHUNK_BYTES = 32 * 2**20

_UNITS = {"": 1, "b": 1, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}
_SIZE = re.compile(r"\s*([0-9]+(?:\.[0-9]*)?(?:e[0-9]+)?)\s*([kmgt]?)(?:i?b)?\s*", re.I)


def budget() -> int:
    """The budget in bytes: ``RESONANT_MEMORY`` if set, else :data:`DEFAULT_BUDGET`.

    Raises
    ------
    ModelError
        For a value of ``RESONANT_MEMORY`` that is no size (exit 2).

    Examples
    --------
    >>> budget() >= 2**20
    True
    """
    text = os.environ.get("RESONANT_MEMORY", "").strip()
    if not text:
        return DEFAULT_BUDGET
    match = _SIZE.fullmatch(text)
    value = float(match.group(1)) * _UNITS[match.group(2).lower()] if match else math.nan
    if not (math.isfinite(value) and 2**20 <= value <= 2**50):
        raise ModelError(Problem(f"'{text[:40]}' is no memory size from 1M to 1P (give e.g. "
                                 "512M, 4G or a number of bytes)", "RESONANT_MEMORY"))
    return int(value)


def size_text(nbytes: float) -> str:
    """A byte count as people read it (binary units, three digits).

    Examples
    --------
    >>> size_text(3 * 2**30), size_text(1536)
    ('3 GiB', '1.5 KiB')
    """
    for unit, factor in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if nbytes >= factor:
            return f"{nbytes / factor:.3g} {unit}"
    return f"{nbytes:.0f} B"


def require(nbytes: float, what: str, smaller: str) -> None:
    """Refuse (AnalysisError, exit 3) an allocation of ``nbytes`` above the budget.

    Parameters
    ----------
    nbytes : float
        The estimated size, from the sizes the analysis was given.
    what : str
        What it is ("the response histories (3000001 samples x 122 states)").
    smaller : str
        How to ask for less.

    Examples
    --------
    >>> require(1.0, "one number", "")
    """
    limit = budget()
    if not nbytes <= limit:
        raise AnalysisError(f"{what} would take {size_text(nbytes)} of memory, above the "
                            f"budget of {size_text(limit)} (RESONANT_MEMORY): {smaller}")


def chunk_rows(row_bytes: float, total: int) -> int:
    """How many rows of ``row_bytes`` a chunked loop takes at once (at least one).

    Examples
    --------
    >>> chunk_rows(8 * 1000, 10**6)
    4194
    """
    return int(max(1, min(total, CHUNK_BYTES // max(row_bytes, 1.0))))


def dense_matrix(a: Matrix, dtype: npt.DTypeLike | None = float) -> np.ndarray:
    """``a`` as a dense array; a sparse matrix is refused (AnalysisError) where its dense
    form would be above the budget.

    Parameters
    ----------
    a : ndarray or scipy sparse matrix
    dtype : numpy dtype, optional
        Of the result (None: the input's).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> dense_matrix(sp.identity(2, format="csr")).tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    if isinstance(a, np.ndarray) or not hasattr(a, "toarray"):
        return np.asarray(a, dtype=dtype)
    rows, columns = a.shape
    require(float(np.dtype(dtype or a.dtype).itemsize) * rows * columns,
            f"the dense form of a {rows} x {columns} sparse matrix",
            "this analysis works on dense matrices; modes (with a count), sweep and "
            "random take the sparse ones, or reduce the model")
    return np.asarray(a.toarray(), dtype=dtype)


__all__ = ["DEFAULT_BUDGET", "CHUNK_BYTES", "budget", "size_text", "require", "chunk_rows",
           "dense_matrix"]
