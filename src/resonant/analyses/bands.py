"""Band matrices: the band order of a model's coordinates, LAPACK band storage, the
modelled cost of a band LU, and the band LU of the dynamic matrix A(s) = K - s^2 M + i s C.

The harmonic kernel's ``banded`` method (:mod:`resonant.analyses.kernel`) and the reduced
models' factorizations (:mod:`resonant.analyses.reduced`) share them: a model whose band
is narrow (a chain read from an OP4 file: five diagonals) is factorized by LAPACK
``gbtrf`` in O(n) wherever it is factorized, not by SuperLU, whose ordering and
bookkeeping cost 10-20 times more on such a band (docs/performance-large.md).

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> n = 6
>>> K = sp.diags([-np.ones(n - 1), 3 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
>>> M = sp.identity(n)
>>> lu = BandLU(M, 0 * M, K, 1.0)
>>> b = np.arange(n) + 0j
>>> bool(np.allclose((K - M) @ lu.solve(b), b))
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arrays import Matrix

#: banded LAPACK's rate (real FLOP/s of the complex factorization) and the per-point
#: overhead of a Python call, in the cost model of the direct solves
BANDED_RATE = 1.5e10
CALL_OVERHEAD = 2e-5


def _entries(a: Matrix, position: np.ndarray | None = None
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows, columns and values of the nonzeros of a; ``position``: the new index of
    every old one (a symmetric permutation)."""
    if hasattr(a, "tocoo"):
        coo = a.tocoo()
        nonzero = coo.data != 0
        rows, cols, values = coo.row[nonzero], coo.col[nonzero], coo.data[nonzero]
    else:
        rows, cols = np.nonzero(a)
        values = np.asarray(a)[rows, cols]
    if position is not None:
        rows, cols = position[rows], position[cols]
    return rows, cols, values


def _bandwidths(*matrices: Matrix, position: np.ndarray | None = None) -> tuple[int, int]:
    lower = upper = 0
    for a in matrices:
        if position is None and not hasattr(a, "tocoo"):
            a_lower, a_upper = dense_bandwidths(np.asarray(a) != 0)
            lower, upper = max(lower, a_lower), max(upper, a_upper)
            continue
        rows, cols, _ = _entries(a, position)
        if rows.size:
            lower = max(lower, int((rows - cols).max()))
            upper = max(upper, int((cols - rows).max()))
    return lower, upper


def dense_bandwidths(pattern: np.ndarray) -> tuple[int, int]:
    """The bandwidths of a dense boolean pattern from each row's first and last nonzero
    column (no index arrays of every nonzero: 144 MB for a full 3,000 x 3,000)."""
    filled = pattern.any(axis=1)
    if not filled.any():
        return 0, 0
    rows = np.flatnonzero(filled)
    first = pattern[rows].argmax(axis=1)
    last = pattern.shape[1] - 1 - pattern[rows, ::-1].argmax(axis=1)
    return max(0, int((rows - first).max())), max(0, int((last - rows).max()))


@dataclass(frozen=True)
class BandOrdering:
    """The order of the coordinates a band solve takes, and its bandwidths there.

    An assembler's numbering can make a narrow band wide (quadratic beam elements
    with their midside unknowns numbered last: a bandwidth of n/2 where reverse
    Cuthill-McKee finds 5), so the band is measured in the given order and in the
    reverse Cuthill-McKee order of the pattern of M, C and K together, and the
    narrower taken.

    Attributes
    ----------
    order : ndarray of int or None
        Coordinate ``order[i]`` is the i-th unknown of the band system (None: as
        given).
    lower, upper : int
        Sub- and superdiagonals of the band.
    """

    order: np.ndarray | None
    lower: int
    upper: int

    @property
    def position(self) -> np.ndarray | None:
        """The band system's index of every coordinate (the inverse of ``order``)."""
        if self.order is None:
            return None
        position = np.empty_like(self.order)
        position[self.order] = np.arange(self.order.size)
        return position


def band_ordering(*matrices: Matrix) -> BandOrdering:
    """The narrower band of the given and the reverse Cuthill-McKee order.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> n = 40
    >>> K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    >>> scrambled = np.random.default_rng(0).permutation(n)
    >>> chain = K.tocsr()[scrambled][:, scrambled]
    >>> band = band_ordering(chain)
    >>> (band.lower, band.upper), band_ordering(K).order is None
    ((1, 1), True)
    """
    lower, upper = _bandwidths(*matrices)
    n = matrices[0].shape[0]
    entries = max(int(a.nnz) if hasattr(a, "nnz") else int(np.count_nonzero(a))
                  for a in matrices)
    # (no order narrows a pattern with more than a quarter of its entries filled)
    if lower + upper <= 2 or n < 3 or entries > n * n // 4:
        return BandOrdering(None, lower, upper)
    import scipy.sparse as sp
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    pattern = sp.csr_matrix((n, n))
    for a in matrices:
        pattern = pattern + abs(sp.csr_matrix(a))
    order = reverse_cuthill_mckee((pattern + pattern.T).tocsr(), symmetric_mode=True)
    order = np.asarray(order, dtype=np.intp)
    band = BandOrdering(order, 0, 0)
    new_lower, new_upper = _bandwidths(*matrices, position=band.position)
    if new_lower + new_upper >= lower + upper:
        return BandOrdering(None, lower, upper)
    return BandOrdering(order, new_lower, new_upper)


def band_storage(a: Matrix, upper: int, rows: int, offset: int,
                  position: np.ndarray | None) -> np.ndarray:
    """LAPACK band storage: ab[offset + upper + i - j, j] = a[i, j], in the band
    system's order (``position``: see :class:`BandOrdering`)."""
    ab = np.zeros((rows, a.shape[0]))
    i, j, v = _entries(a, position)
    np.add.at(ab, (offset + upper + i - j, j), v)
    return ab


def band_lu_seconds(n: int, lower: int, upper: int) -> float:
    """The modelled seconds of one band LU of an n x n complex matrix (``gbtrf``):
    8 n kl (kl + ku + 1) FLOPs at :data:`BANDED_RATE` (less for narrow bands) plus
    building the band storage.

    Examples
    --------
    >>> round(band_lu_seconds(200_000, 2, 2) * 1e3, 1)   # ms: a five-diagonal chain
    17.3
    """
    rate = BANDED_RATE * min(1.0, 0.1 + (lower + upper) / 200)
    return (8.0 * n * max(lower, 1) * (lower + upper + 1) / rate
            + 2e-9 * n * (2 * lower + upper + 1) * 3 + CALL_OVERHEAD)


def sparse_lu_floor(nonzeros: int) -> float:
    """Seconds no sparse LU (SuperLU) of a matrix with this many nonzeros does with
    less: its nonzeros and a call.  A band LU below it is the cheaper one, with no
    sparse factorization tried.

    Examples
    --------
    >>> sparse_lu_floor(1_000_000)
    0.0301
    """
    return 3e-8 * nonzeros + 1e-4


class BandLU:
    """The LU of A(s) = K - s^2 M + i s C by LAPACK ``zgbtrf`` (partial pivoting) in the
    band order of the coordinates (:func:`band_ordering`), solving A x = b for one or
    several right-hand sides in the coordinates' own order.

    Parameters
    ----------
    M, C, K : sparse matrix or ndarray
        Real (n, n).
    s : float
        The frequency (rad/s).
    band : BandOrdering, optional
        :func:`band_ordering` of M, C, K (computed if not given).
    storage : tuple of ndarray, optional
        :func:`band_storage` of M, C, K in that band with ``lower`` extra rows (made
        if not given): several factorizations of one model share it.

    Raises
    ------
    RuntimeError
        "Factor is exactly singular" (as SuperLU says) where a pivot is zero.
    """

    def __init__(self, M: Matrix, C: Matrix, K: Matrix, s: float,
                 band: BandOrdering | None = None,
                 storage: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> None:
        from scipy.linalg.lapack import zgbtrf

        band = band_ordering(M, C, K) if band is None else band
        self.lower, self.upper, self.order = band.lower, band.upper, band.order
        self.position = band.position
        if storage is None:
            storage = band_storages(M, C, K, band)
        Mb, Cb, Kb = storage
        A = Kb - (s * s) * Mb + (1j * s) * Cb
        self.lu, self.pivots, info = zgbtrf(A, self.lower, self.upper, overwrite_ab=True)
        if info != 0:
            raise RuntimeError("Factor is exactly singular")
        self.shape = (Kb.shape[1], Kb.shape[1])

    def solve(self, b: np.ndarray) -> np.ndarray:
        """A^-1 b, b of shape (n,) or (n, k)."""
        from scipy.linalg.lapack import zgbtrs

        b = np.asarray(b, dtype=complex)
        rhs = b if self.order is None else b[self.order]
        x, info = zgbtrs(self.lu, self.lower, self.upper, rhs, self.pivots)
        result: np.ndarray = x if self.position is None else x[self.position]
        return result


def band_storages(M: Matrix, C: Matrix, K: Matrix, band: BandOrdering
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`band_storage` of M, C and K in ``band`` with the ``lower`` extra rows the
    LU's fill takes (``gbtrf``/``gbsv``)."""
    rows = 2 * band.lower + band.upper + 1
    Mb, Cb, Kb = (band_storage(a, band.upper, rows, band.lower, band.position)
                  for a in (M, C, K))
    return Mb, Cb, Kb


__all__ = ["BandOrdering", "band_ordering", "band_storage", "band_storages", "BandLU",
           "band_lu_seconds", "sparse_lu_floor", "dense_bandwidths", "BANDED_RATE", "CALL_OVERHEAD"]
