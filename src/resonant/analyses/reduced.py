"""Reduced-order frequency response of large matrix models, exact to a tolerance.

The harmonic response of a large model, (K - w^2 M + i w C) z = b at N
frequencies, is computed in a small subspace instead of by N sparse
factorizations (the Krylov harmonic method of ANSYS, the asymptotic waveform
evaluation of COMSOL):

1. **Basis.**  At a few *expansion frequencies* s_j in the band the matrix
   A(s_j) = K - s_j^2 M + i s_j C is factorized once (SuperLU, fill-reducing
   ordering) and the Taylor coefficients ("moments") of z(w) about s_j,
   A0 x_k = -(A1 x_(k-1) + A2 x_(k-2)) with A1 = -2 s_j M + i C, A2 = -M,
   are generated stably as the second-order Krylov space of the linearization
   (Arnoldi on the 2n vectors [x_k; x_(k-1)], as in SOAR/TOAR).  Real and
   imaginary parts of the moments are split, so the basis V is *real*, then
   orthonormalised (block Gram-Schmidt twice, rank-revealing SVD dropping
   directions that carry nothing new).  A real V keeps M, C, K's symmetry
   and definiteness in the reduced matrices Vᵀ M V, Vᵀ C V, Vᵀ K V, and
   reproduces z(s_j) and its first moments exactly.
2. **Reduced solve.**  The small quadratic problem is linearized (2r x 2r)
   and diagonalized once; y(w) at all N frequencies is then a sum over the
   reduced poles (a stacked dense solve when the eigenvectors are
   ill-conditioned), z = V y.
3. **Error estimate.**  The residual of the *full* equation
   r(w) = A(w) V y(w) - b is computed at every frequency without forming
   the n x N responses: with the real QR factorization [KV, MV, CV, Re b,
   Im b] = Q R, ||r(w)|| = ||R u(w)|| for u = [y; -w^2 y; i w y; -1; -i]
   (no cancellation, unlike a Gram matrix).  The relative residual
   rho(w) = ||r|| / ||b|| is turned into an error estimate by *validation*:
   at the frequency of the largest rho the full system is factorized and
   solved exactly, giving the true error there; the estimate is
   ``max(true errors, SAFETY * gamma * rho(w))`` with gamma the largest
   ratio of true error to rho at the latest validations (at least 1).
4. **Adaptive enrichment.**  While the estimate exceeds the tolerance, the
   validation frequency (whose factorization is already there) becomes a new
   expansion point; the loop stops at the tolerance or at a cap (expansion
   points, basis size, memory, time budget, the caller's deadline), and then
   says so (``converged`` is False and ``reason`` tells why).

Limits: the estimate is not a bound (a safety factor over validated ratios).
Against exact solves at all 48,708 frequencies of 240 models (uniform and random
chains and grids; Rayleigh, mass-proportional, non-proportional and light damping;
``benchmarks/bench_reduced_estimate.py``, docs/sweeps.md) the band's
``estimated_error`` was at least the largest true error in every model (usually
10-1000x above it), and where ``converged`` was claimed the tolerance was met at
every frequency; at single frequencies the estimate fell below the true error
there by up to 1.5x (by up to 11x only at rounding level, below 1e-10).
The residual has a rounding floor near 1e-10 relative, so tolerances much
below 1e-8 may not be certified (``converged`` False, ``reason`` says so) even
where the true error is smaller.  The basis needs one real column per moment
and part: bands with hundreds of resonances need hundreds of vectors (capped by
:data:`MAX_BASIS` and by the memory budget, :func:`resonant.memory.budget`).

Examples
--------
A chain of 300 masses, Rayleigh-damped, swept over its ten lowest resonances:

>>> import numpy as np, scipy.sparse as sp
>>> n = 300
>>> K = sp.diags([-np.ones(n - 1), np.r_[2 * np.ones(n - 1), 1.0], -np.ones(n - 1)],
...              [-1, 0, 1], format="csr") * 1e4
>>> M = sp.identity(n, format="csr")
>>> C = 0.05 * M + 1e-4 * K
>>> b = np.zeros(n, dtype=complex); b[-1] = 1.0
>>> w = np.linspace(1.0, 10.0, 400)
>>> red = reduced_response(M, C, K, b, w, tol=1e-8)
>>> red.converged, red.estimated_error <= 1e-8, red.basis_size < 100
(True, True, True)
>>> import scipy.sparse.linalg as sla
>>> i = 200
>>> exact = sla.spsolve((K - w[i]**2 * M + 1j * w[i] * C).tocsc(), b)
>>> bool(np.linalg.norm(red.Z[i] - exact) <= 1e-8 * np.linalg.norm(exact))
True
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol, TypedDict, TypeVar, Unpack

import numpy as np

from ..arrays import Matrix
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError
from ..memory import budget
from ..modal import factor_stiffness, modes_below
from .bands import (
    BandLU,
    BandOrdering,
    band_lu_seconds,
    band_ordering,
    band_storages,
    sparse_lu_floor,
)
from .forward_error import Residuals
from .threads import blas_threads

if TYPE_CHECKING:
    from scipy.sparse.linalg import SuperLU


class Solver(Protocol):
    """A factorization that solves A x = b (a :class:`ScaledLU` or SciPy's SuperLU)."""

    def solve(self, b: np.ndarray) -> np.ndarray: ...

#: default relative tolerance of the reduced response (normwise, per frequency)
DEFAULT_TOL = 1e-6
#: moments (Krylov vectors) generated at each expansion point
MOMENTS = 12
#: expansion points placed across the band before any enrichment
INITIAL_POINTS = 3
#: most expansion points (factorizations used for the basis)
MAX_POINTS = 40
#: most basis vectors
MAX_BASIS = 800
#: basis columns the residual's QR factorization has room for at first (it doubles when
#: full: address space is reserved as the basis grows, not for the largest basis at once)
FIRST_CAPACITY = 64
#: the estimate is this many times the relative residual scaled by the worst ratio
#: of true error to residual seen at the validation solves
SAFETY = 4.0
#: the ratio of true error to residual is taken from this many latest validations (the
#: first bases' ratios say little about the last)
RECENT = 3
#: enrichment stops when the largest residual has not halved over this many steps
STALL = 4
#: condition number (||A|| ||z|| / ||b||) beyond which a point may be an exact resonance
SINGULAR_CONDITION = 1e13
#: ... when the damping also acts on the response less than this (:func:`damping_fraction`):
#: an ill-conditioned but damped structure (a fine beam mesh, stiffness condition 1e12)
#: is not resonant
DAMPED_FRACTION = 1e-12
#: the enrichment stops when the validated error is within this factor of the rounding
#: floor (eps times the condition number): a richer basis cannot do better
FLOOR_REACHED = 10.0
#: safety factor on the componentwise error estimate of an exact solve (two random probes
#: of |A^-1|)
FLOOR_SAFETY = 10.0
#: moments of each adjoint load of :func:`reduced_model` put into the basis
ADJOINT_MOMENTS = 3
#: models of at least this many coordinates factorize several expansion points at once
PARALLEL_FACTOR_SIZE = 20_000

_T = TypeVar("_T")
#: bytes of complex responses computed at once
_CHUNK_BYTES = 32 * 2**20


@dataclass(frozen=True)
class ReducedResponse:
    """The reduced-order responses of one load at N frequencies.

    Attributes
    ----------
    Z : ndarray
        z = V y at the kept coordinates, shape (N, kept) (at an expansion point that is
        one of the frequencies, the exact solve made there); NaN at singular points.
    norms : ndarray
        ||z(w)||_2 of the whole response (all coordinates), shape (N,).
    residual : ndarray
        Relative residual of the full equation ||A(w) z - b|| / ||b||, shape (N,).
    error : ndarray
        Estimated relative error ||z - z_exact|| / ||z_exact|| per frequency, shape (N,):
        an estimate, not a bound (seen up to 1.5x below the true error at a frequency,
        more only at rounding level; see the module docstring).
    estimated_error : float
        The largest of ``error`` (NaN points left out), compared with the tolerance: an
        estimate, seen at least as large as the largest true error in every model
        tried (docs/sweeps.md).
    converged : bool
        Whether ``estimated_error`` is at most the tolerance.
    expansion : tuple of float
        The expansion frequencies (rad/s) of the basis.
    basis_size : int
        Columns of the real basis V.
    checks : tuple of (float, float)
        The validation solves: frequency and true relative error of the reduced
        response there (with the basis of that moment).
    singular : ndarray of bool
        Points where the reduced system is singular (undamped resonance), shape (N,).
    reason : str
        Why the enrichment stopped before the tolerance ("" when converged).
    seconds : float
        Wall time of the whole computation.
    """

    Z: np.ndarray
    norms: np.ndarray
    residual: np.ndarray
    error: np.ndarray
    estimated_error: float
    converged: bool
    expansion: tuple[float, ...]
    basis_size: int
    checks: tuple[tuple[float, float], ...]
    singular: np.ndarray
    reason: str = ""
    seconds: float = 0.0

    def __post_init__(self) -> None:
        for name in ("Z", "norms", "residual", "error", "singular"):
            array = np.array(getattr(self, name))
            array.flags.writeable = False
            object.__setattr__(self, name, array)


# -- factorizations ---------------------------------------------------------------------------

class SuperLUOptions(TypedDict, total=False):
    """The keywords of ``scipy.sparse.linalg.splu`` that :func:`sparse_lu_options` sets."""

    permc_spec: str
    diag_pivot_thresh: float
    options: dict[str, bool]


def sparse_lu_options(pattern: Matrix) -> SuperLUOptions:
    """SuperLU options (``scipy.sparse.linalg.splu`` keywords) for matrices of this pattern.

    A structurally symmetric pattern (every mass-spring-damper model) gets a
    minimum degree ordering on A^T + A (about half the fill of COLAMD on a 2-D
    grid) and *symmetric mode* with threshold pivoting (a diagonal pivot is kept
    when it is at least 0.1 of the largest in its column): strict partial
    pivoting of an indefinite K - w^2 M + i w C (above the first resonances)
    leaves the ordering and multiplied the fill of a 10,000-DOF grid by 47
    (23 s instead of 0.03 s per factorization).  Other patterns: COLAMD and
    partial pivoting.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> sparse_lu_options(sp.diags([1.0, 2.0, 1.0], [-1, 0, 1], shape=(4, 4)))["permc_spec"]
    'MMD_AT_PLUS_A'
    >>> sparse_lu_options(sp.diags([2.0, 1.0], [0, 1], shape=(4, 4)))
    {'permc_spec': 'COLAMD'}
    """
    coo = (pattern != 0).astype(np.int8)
    if abs(coo - coo.T).nnz:
        return {"permc_spec": "COLAMD"}
    return {"permc_spec": "MMD_AT_PLUS_A", "diag_pivot_thresh": 0.1,
            "options": {"SymmetricMode": True}}


def symmetric_scale(diagonal: np.ndarray) -> np.ndarray:
    """Powers of two d_i near 1 / sqrt(|a_ii|): D A D has a diagonal of order 1, exactly
    (a power of two changes no digit).  Zero or non-finite diagonals get 1.

    Examples
    --------
    >>> symmetric_scale(np.array([4.0, 1e6, 0.0])).tolist()
    [0.5, 0.0009765625, 1.0]
    """
    a = np.abs(np.asarray(diagonal, dtype=float))
    good = (a > 0) & np.isfinite(a)
    e = np.zeros(a.shape)
    e[good] = np.round(-0.5 * np.log2(a[good]))
    result: np.ndarray = np.exp2(np.clip(e, -500, 500))
    return result


class ScaledLU:
    """The SuperLU factorization of D A D (D = diag(d), powers of two), solving A x = b as
    x = D (D A D)^-1 D b.

    The symmetric-mode ordering of :func:`sparse_lu_options` keeps its diagonal pivots
    only when the diagonal is not small against its column.  Coordinates of different
    units (deflections in m beside slopes in rad: a Morley plate) make it so, the pivots
    leave the diagonal and the fill explodes: on a 1,985-coordinate Kirchhoff plate 776
    pivots left it, 1.3 million nonzeros and 15 s against 97,000 and 0.015 s after the
    scaling (and 0.1 s for SuperLU's default COLAMD with partial pivoting).

    Parameters
    ----------
    A : sparse matrix
        (n, n).
    d : ndarray
        (n,) scale factors (:func:`symmetric_scale`).
    **options
        ``scipy.sparse.linalg.splu`` keywords.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.csc_matrix(np.array([[4e6, 1e3], [1e3, 2.0]]))
    >>> lu = ScaledLU(A, symmetric_scale(A.diagonal()), **sparse_lu_options(A))
    >>> x = lu.solve(np.array([1.0, 1.0]))
    >>> bool(np.allclose(A @ x, 1.0, rtol=1e-14))
    True
    """

    def __init__(self, A: Matrix, d: np.ndarray, **options: Unpack[SuperLUOptions]) -> None:
        import scipy.sparse as sp
        from scipy.sparse.linalg import splu

        self.d = np.asarray(d, dtype=float)
        scaled = sp.csc_matrix(A, copy=True)
        columns = np.repeat(np.arange(scaled.shape[1]), np.diff(scaled.indptr))
        scaled.data *= self.d[scaled.indices] * self.d[columns]
        self.lu = splu(scaled, **options)
        self.shape = A.shape

    @property
    def L(self) -> Any:
        return self.lu.L

    @property
    def U(self) -> Any:
        return self.lu.U

    @property
    def perm_r(self) -> np.ndarray:
        result: np.ndarray = self.lu.perm_r
        return result

    @property
    def perm_c(self) -> np.ndarray:
        result: np.ndarray = self.lu.perm_c
        return result

    def solve(self, b: np.ndarray) -> np.ndarray:
        d = self.d if np.ndim(b) == 1 else self.d[:, None]
        result: np.ndarray = d * self.lu.solve(d * b)
        return result


def backward_stable(A: Matrix, x: np.ndarray, b: np.ndarray, a_norm: float | None = None
                    ) -> bool:
    """Whether ||A x - b|| <= 1e-10 (||A|| ||x|| + ||b||) (infinity norms): the solve was
    backward stable (a stable LU gives about 1e-15; not finite counts as stable, the
    callers judge singular points).  ``a_norm``: ||A||_inf or a bound of it, if known.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.csr_matrix(np.array([[2.0, 1.0], [1.0, 3.0]]))
    >>> backward_stable(A, np.array([0.4, 0.2]), np.array([1.0, 1.0]))
    True
    >>> backward_stable(A, np.array([0.5, 0.2]), np.array([1.0, 1.0]))
    False
    """
    with np.errstate(all="ignore"):
        r = float(np.abs(A @ x - b).max(initial=0.0))
        if a_norm is None:
            a_norm = float(abs(A).sum(axis=1).max())
        scale = a_norm * float(np.abs(x).max(initial=0.0)) + \
            float(np.abs(b).max(initial=0.0))
    return not np.isfinite(r) or r <= 1e-10 * scale


def _rayleigh(M: Matrix, C: Matrix, K: Matrix) -> tuple[float, float] | None:
    """(alpha, beta) when C = alpha M + beta K (to rounding), else None: tested on two
    random vectors (a C of another form fits them only by accident of measure zero)."""
    X = np.random.default_rng(0).standard_normal((M.shape[0], 2))
    A = np.column_stack([(M @ X).ravel(), (K @ X).ravel()])
    c = (C @ X).ravel()
    coef, *_ = np.linalg.lstsq(A, c, rcond=None)
    if np.linalg.norm(A @ coef - c) <= 1e-12 * np.linalg.norm(c):
        return float(coef[0]), float(coef[1])
    return None


def damping_norm(C: Matrix) -> float:
    """max(||C||_1, ||C||_inf), a bound of ||C||_2 (0 for an empty or zero C).

    Examples
    --------
    >>> damping_norm(np.array([[1.0, -2.0], [0.0, 0.5]]))
    3.0
    """
    a = abs(C)
    if not (a.nnz if hasattr(a, "nnz") else a.size):
        return 0.0
    return float(max(a.sum(axis=0).max(), a.sum(axis=1).max()))


def damping_fraction(C: Matrix, X: np.ndarray, c_norm: float | None = None) -> np.ndarray:
    """How much the damping acts on each response: |x^H C x| / (||x||^2 ||C||), per row.

    A response bounded by damping has a fraction of the order of the damping's share in
    its dominant modes (1e-4 to 1 on the structures of benchmarks/corpus.py, fine
    beam meshes and stiff springs included).  At an undamped resonance (a mode C does
    not touch) x is huge along that mode and the fraction falls as 1/|x|^2: 1e-18 at
    an exactly singular point of a damped chain beside an undamped oscillator.  So a
    large condition number with a fraction below :data:`DAMPED_FRACTION` is a
    resonance, with a larger fraction only an ill-conditioned structure.

    Parameters
    ----------
    C : sparse matrix or ndarray
        (n, n), real; or (N, n, n), one for each response.
    X : ndarray
        (N, n) responses.
    c_norm : float, optional
        ||C|| (a bound of the 2-norm); default max(||C||_1, ||C||_inf).

    Returns
    -------
    ndarray
        (N,) fractions (0 without damping or where x is 0 or not finite).

    Examples
    --------
    >>> C = np.diag([0.1, 0.0])
    >>> f = damping_fraction(C, np.array([[1.0, 0.0], [1e-3, 1e9], [0.0, 1.0]]))
    >>> [f"{v:.3g}" for v in f]
    ['1', '1e-24', '0']
    """
    X = np.atleast_2d(np.asarray(X, dtype=complex))
    if np.ndim(C) == 3:
        return _stacked_damping_fraction(np.asarray(C), X)
    sparse = hasattr(C, "tocsr")
    if c_norm is None:
        c_norm = damping_norm(C)
    if not c_norm > 0:
        return np.zeros(X.shape[0])
    with np.errstate(all="ignore"):
        CX = np.asarray(C @ X.T).T if sparse else X @ np.asarray(C).T
        quadratic = np.abs(np.einsum("ij,ij->i", X.conj(), CX))
        size = np.einsum("ij,ij->i", X.conj(), X).real
        fraction = np.where(size > 0, quadratic / (size * c_norm), 0.0)
    return np.where(np.isfinite(fraction), fraction, 0.0)


class DampingFraction:
    """:func:`damping_fraction` of one response at a time against one C, made cheap for
    a sweep that needs it at every point (a stiff structure, whose condition number
    looks resonant everywhere): C restricted to the coordinates it touches (a dashpot
    or two: a few entries of x) and made complex once.

    Parameters
    ----------
    C : sparse matrix or ndarray
        (n, n), real, not zero.
    c_norm : float, optional
        ||C|| (a bound of the 2-norm); default max(||C||_1, ||C||_inf).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> C = sp.csr_matrix(([0.5], ([2], [2])), shape=(4, 4))
    >>> x = np.array([1.0, 0.0, 1.0j, 0.0])
    >>> DampingFraction(C)(x), float(damping_fraction(C, x[None])[0])
    (0.5, 0.5)
    """

    def __init__(self, C: Matrix, c_norm: float | None = None) -> None:
        import scipy.sparse as sp

        a = sp.csr_matrix(C)
        coo = a.tocoo()
        touched = np.union1d(coo.row[coo.data != 0], coo.col[coo.data != 0])
        self.support = None if touched.size > a.shape[0] // 2 else touched
        sub = a if self.support is None else a[self.support][:, self.support]
        self.C = sp.csr_matrix(sub, dtype=complex)
        self.c_norm = damping_norm(C) if c_norm is None else c_norm

    def __call__(self, x: np.ndarray) -> float:
        xs = x if self.support is None else x[self.support]
        with np.errstate(all="ignore"):
            size = np.vdot(x, x).real * self.c_norm
            if not size > 0:   # (x zero, or underflowing to it)
                return 0.0
            fraction = float(np.abs(np.vdot(xs, self.C @ xs)) / size)
        return fraction if np.isfinite(fraction) else 0.0


def _stacked_damping_fraction(C: np.ndarray, X: np.ndarray) -> np.ndarray:
    """:func:`damping_fraction` with one C per response (C of shape (N, n, n))."""
    a = np.abs(C)
    c_norm = np.maximum(a.sum(axis=1).max(axis=1), a.sum(axis=2).max(axis=1))
    with np.errstate(all="ignore"):
        quadratic = np.abs(np.einsum("ki,kij,kj->k", X.conj(), C, X))
        size = np.einsum("ij,ij->i", X.conj(), X).real
        fraction = np.where((size > 0) & (c_norm > 0), quadratic / (size * c_norm), 0.0)
    return np.where(np.isfinite(fraction), fraction, 0.0)


class _Operators:
    """M, C, K as real CSR matrices, with the factorization of A(s) at any s."""

    def __init__(self, M: Matrix, C: Matrix, K: Matrix) -> None:
        import scipy.sparse as sp

        self.M, self.C, self.K = (sp.csr_matrix(a, dtype=float) for a in (M, C, K))
        self.C.eliminate_zeros()
        self.damped = self.C.nnz > 0
        self.rayleigh = _rayleigh(self.M, self.C, self.K) if self.damped else None
        self.n = self.M.shape[0]
        pattern = self.K + self.M + self.C
        self.lu_options = sparse_lu_options(pattern)
        # a narrow band (a chain: five diagonals) is factorized by LAPACK's band LU, which
        # costs less than any sparse LU could (5 ms against SuperLU's 90 ms on a
        # 20,000-row chain), as the kernel's direct choice does
        band = band_ordering(self.M, self.C, self.K)
        cheap = band_lu_seconds(self.n, band.lower, band.upper) <= sparse_lu_floor(pattern.nnz)
        #: the band LU's order where it is the factorization used, else None
        self.band: BandOrdering | None = band if cheap else None
        self._storages: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        #: factorizations kept by frequency (several loads share them), or None
        self.cache: dict[float, Any] | None = None
        #: factorizations made before (the cost probe of ``auto``), by frequency
        self.given: dict[float, Any] = {}
        #: |K|, |M|, |C| (for the rounding error of exact solves), made when needed
        self.abs: tuple[Any, Any, Any] | None = None
        #: work done once while a helper thread factorizes a validation point, or None
        self.side: Any = None
        #: the helper thread of :meth:`helper`, made on first use
        self.maker: FactorThread | None = None

    def helper(self) -> FactorThread:
        """The one helper thread of this model's factorizations (:meth:`release` frees
        what it made)."""
        if self.maker is None:
            self.maker = FactorThread()
        return self.maker

    def release(self) -> None:
        """Drop every factorization kept here; those of the helper thread are freed
        there (:class:`FactorThread`)."""
        self.cache, self.given, self.side = None, {}, None
        if self.maker is not None:
            self.maker.release()
            self.maker = None

    def matrix(self, s: float) -> Any:
        return (self.K - (s * s) * self.M + (1j * s) * self.C).tocsc()

    def factor(self, s: float, partial: bool = False) -> Any:
        """The LU of A(s): the band LU (:class:`resonant.analyses.bands.BandLU`, partial
        pivoting) where the band is narrow, else SuperLU's, symmetrically scaled
        (:class:`ScaledLU`; ``partial``: with partial pivoting); RuntimeError when A(s) is
        exactly singular."""
        if self.band is not None:
            if self._storages is None:   # (shared by every point's factorization)
                self._storages = band_storages(self.M, self.C, self.K, self.band)
            return BandLU(self.M, self.C, self.K, s, self.band, self._storages)
        return ScaledLU(self.matrix(s), self.scale(s),
                        **({} if partial else self.lu_options))

    def scale(self, s: float) -> np.ndarray:
        """:func:`symmetric_scale` of |K_ii| + s^2 |M_ii| + s |C_ii| (no cancellation)."""
        return symmetric_scale(np.abs(self.K.diagonal()) + s * s * np.abs(self.M.diagonal())
                               + abs(s) * np.abs(self.C.diagonal()))


def _real_times(A: np.ndarray, x: np.ndarray) -> np.ndarray:
    """A @ x for a real A and a complex x without converting A to complex (numpy would
    copy a large A, the n x r basis or its transpose, into complex numbers first)."""
    if not np.iscomplexobj(x):
        result: np.ndarray = A @ x
        return result
    product: np.ndarray = (A @ x.real) + 1j * (A @ x.imag)
    return product


def _krylov(ops: _Operators, lu: Solver, b: np.ndarray, s: float, q: int,
            deadline: Deadline, x0: np.ndarray | None = None) -> np.ndarray:
    """q moments of z(w) about s, as the top halves of an Arnoldi basis of the
    linearization (columns complex, shape (n, <= q)); ``x0``: A(s)^-1 b if solved
    already."""
    n = ops.n
    x0 = lu.solve(b) if x0 is None else x0
    U = np.zeros((2 * n, q), dtype=complex, order="F")   # contiguous columns
    nrm = np.linalg.norm(x0)
    if not np.isfinite(nrm) or nrm == 0:
        return np.zeros((n, 0), dtype=complex)
    U[:n, 0] = x0 / nrm
    for k in range(1, q):
        deadline.check("while building the reduced basis", analysis=True)
        top, bottom = U[:n, k - 1], U[n:, k - 1]
        v = np.empty(2 * n, dtype=complex)
        v[:n] = -lu.solve(ops.M @ ((-2.0 * s) * top - bottom) + 1j * (ops.C @ top))
        v[n:] = top
        for _ in range(2):  # classical Gram-Schmidt, twice (no conjugated copy of U)
            v -= U[:, :k] @ (v.conj() @ U[:, :k]).conj()
        nv = np.linalg.norm(v)
        if not np.isfinite(nv) or nv < 1e-13:
            return U[:n, :k]
        U[:, k] = v / nv
    return U[:n]


def _cholesky_qr(X: np.ndarray, shift: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """X = Q R by one Cholesky QR step (Q = X R^-1 with R = chol(Xᵀ X + shift I)): a Gram
    matrix and a triangular solve, both BLAS-3 (ten times faster than Householder QR
    of a tall matrix here)."""
    import scipy.linalg

    G = X.T @ X
    G[np.diag_indices_from(G)] += shift
    R = scipy.linalg.cholesky(G, lower=False, check_finite=False)
    Q = scipy.linalg.solve_triangular(R, X.T, trans="T", lower=False,
                                      check_finite=False).T
    return Q, R


def _svd_tall(X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The thin SVD X = U S Wt of a tall matrix (n >> k), through its QR factorization
    by shifted Cholesky QR3 (Fukaya et al., SIAM J. Sci. Comput. 42 (2020) A477: a
    shifted step makes any X, even rank deficient, well conditioned, two plain steps
    make Q orthonormal to rounding; X = Q R to rounding of ||X||) and the SVD of R.
    The columns are scaled to unit norm for the QR (X = Xs D, X = Q (R D)): columns of
    very different sizes (K V and M V of a stiff model) would leave the small ones
    below the shift, and the unshifted steps would fail."""
    n, k = X.shape
    norm2 = float(np.einsum("ij,ij->", X, X))
    if 4 * k > n or not norm2 > 0 or not np.isfinite(norm2):  # not tall: LAPACK is cheap
        U, S, Wt = np.linalg.svd(X, full_matrices=False)
        return U, S, Wt
    d = np.linalg.norm(X, axis=0)
    d[~(d > 0)] = 1.0
    Xs = X / d
    shift = 11.0 * (n * k + k * (k + 1)) * np.finfo(float).eps * float(
        np.einsum("ij,ij->", Xs, Xs))
    try:
        Q, R = _cholesky_qr(Xs, shift)
        for step in range(2):
            Q, T = _cholesky_qr(Q) if step else _gram_qr(Q)
            R = T @ R
    except np.linalg.LinAlgError:  # (not seen: the shift makes X well conditioned)
        U, S, Wt = np.linalg.svd(X, full_matrices=False)
        return U, S, Wt
    Ur, S, Wt = np.linalg.svd(R * d)
    return Q @ Ur, S, Wt


def _gram_qr(Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Q = Qo T with Qo orthonormal (to the accuracy of a Cholesky QR step) for the Q of a
    shifted Cholesky QR step: by Cholesky, or, where X was rank deficient (the products
    K V, M V of a Krylov basis are: K x_0 lies in the span of b, M x_0 and C x_0) and Q
    holds directions the shift took down to rounding, by the eigenvectors of Qᵀ Q
    without those directions (T then has fewer rows than columns).  A LAPACK SVD of the
    tall matrix instead costs as much as 50 Gram matrices."""
    G = Q.T @ Q
    try:
        import scipy.linalg

        T = scipy.linalg.cholesky(G, lower=False, check_finite=False)
        return scipy.linalg.solve_triangular(T, Q.T, trans="T", lower=False,
                                             check_finite=False).T, T
    except np.linalg.LinAlgError:
        lam, W = np.linalg.eigh(G)
        keep = lam > 1e-14 * max(G.shape[0], 1) * max(float(lam.max(initial=0.0)), 1e-300)
        lam, W = lam[keep], W[:, keep]
        root = np.sqrt(lam)
        return (Q @ W) / root, root[:, None] * W.T


def _orthonormalize(Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Q = Qo T with Qo orthonormal, for Q whose columns are nearly orthonormal already
    (Cholesky QR twice; Householder QR when Q is not tall or not well conditioned)."""
    if 4 * Q.shape[1] <= Q.shape[0]:
        try:
            Q1, T1 = _cholesky_qr(Q)
            Q2, T2 = _cholesky_qr(Q1)
            return Q2, T2 @ T1
        except np.linalg.LinAlgError:
            pass
    Qo, T = np.linalg.qr(Q)
    return Qo, T


def _extend(V: np.ndarray, X: np.ndarray, drop: float) -> np.ndarray:
    """V with the new directions of X (complex columns split into real and imaginary
    parts), orthonormal; directions below ``drop`` (relative) are left out."""
    X = np.hstack([X.real, X.imag])
    norms = np.linalg.norm(X, axis=0)
    X = X[:, norms > 0] / norms[norms > 0]
    if X.shape[1] == 0:
        return V
    for _ in range(2):
        if V.shape[1]:
            X -= V @ (V.T @ X)
    U, S, _ = _svd_tall(X)
    Q = U[:, S > drop]
    if Q.shape[1] == 0:
        return V
    if V.shape[1]:
        Q -= V @ (V.T @ Q)
        Q, _ = _orthonormalize(Q)
    return np.hstack([V, Q])


# -- the reduced system -----------------------------------------------------------------------

class _Projection:
    """Vᵀ K V, Vᵀ M V and Vᵀ C V kept up to date as the basis V grows: each update
    multiplies only the new columns (K V of the whole basis is never stored)."""

    def __init__(self, ops: _Operators) -> None:
        self.ops = ops
        self.size = 0
        self.reduced = [np.zeros((0, 0)) for _ in range(3)]   # K, M, C

    def update(self, V: np.ndarray) -> list[np.ndarray]:
        """Extend to the columns of V beyond those seen; the products K V_new, M V_new
        (and C V_new when damped) of the new columns, for the residual."""
        r0, r = self.size, V.shape[1]
        new, old = V[:, r0:], V[:, :r0]
        products = []
        for i, A in enumerate((self.ops.K, self.ops.M, self.ops.C)):
            grown = np.zeros((r, r))
            grown[:r0, :r0] = self.reduced[i]
            if i < 2 or self.ops.damped:
                AN = np.asarray(A @ new)
                grown[:, r0:] = V.T @ AN
                # Vnᵀ A V0 = (Aᵀ Vn)ᵀ V0: no product with the old columns
                grown[r0:, :r0] = np.asarray(A.T @ new).T @ old
                products.append(AN)
            self.reduced[i] = grown
        self.size = r
        return products


class _Reduced:
    """The reduced matrices Kr, Mr, Cr and load br, solved at any frequencies."""

    def __init__(self, Kr: np.ndarray, Mr: np.ndarray, Cr: np.ndarray, br: np.ndarray
                 ) -> None:
        self.Kr, self.Mr, self.Cr, self.br = Kr, Mr, Cr, br
        self.r = Kr.shape[0]
        self._modal = self._diagonalize()

    def _diagonalize(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        r = self.r
        try:
            minv = np.linalg.solve(self.Mr, np.hstack([self.Kr, self.Cr,
                                                        self.br.real[:, None],
                                                        self.br.imag[:, None]]))
            H = np.zeros((2 * r, 2 * r))
            H[:r, r:] = np.eye(r)
            H[r:, :r] = -minv[:, :r]
            H[r:, r:] = -minv[:, r:2 * r]
            mu, X = np.linalg.eig(H)
            if not np.all(np.isfinite(X)) or np.linalg.cond(X) > 1e8:
                return None
            rhs = np.zeros(2 * r, dtype=complex)
            rhs[r:] = minv[:, 2 * r] + 1j * minv[:, 2 * r + 1]
            g = np.linalg.solve(X, rhs)
        except np.linalg.LinAlgError:
            return None
        return mu, g, X[:r]

    def solve(self, w: np.ndarray, deadline: Deadline = NO_DEADLINE) -> np.ndarray:
        """y(w), shape (len(w), r); inf/NaN rows where the reduced system is singular;
        ``deadline`` checked at every chunk of frequencies."""
        r = self.r
        out = np.empty((len(w), r), dtype=complex)
        per_point = 4 * r if self._modal is not None else r * r  # complex numbers
        chunk = max(1, _CHUNK_BYTES // (16 * max(per_point, 1)))
        for start in range(0, len(w), chunk):
            deadline.check("while solving the reduced model", analysis=True)
            ww = w[start:start + chunk]
            with np.errstate(all="ignore"):
                if self._modal is not None:
                    mu, g, top = self._modal
                    out[start:start + chunk] = (g / (1j * ww[:, None] - mu)) @ top.T
                    continue
                A = self.Kr - ww[:, None, None] ** 2 * self.Mr + 1j * ww[:, None, None] * self.Cr
                try:
                    out[start:start + chunk] = np.linalg.solve(
                        A, np.broadcast_to(self.br, (len(ww), r))[..., None])[..., 0]
                except np.linalg.LinAlgError:
                    for i, Ai in enumerate(A):
                        try:
                            out[start + i] = np.linalg.solve(Ai, self.br)
                        except np.linalg.LinAlgError:
                            out[start + i] = np.nan
        return out


class _Residual:
    """||A(w) V y(w) - b||_2 at every frequency without forming an n x N array.

    The real matrix P = [Re b, Im b, K V, M V, C V] (columns added block by block as
    the basis grows) is kept as P = Q R (block Gram-Schmidt twice); then
    A(w) V y - b = P u(w) with u = [-1, -i, y, -w^2 y, i w y] and ||P u|| = ||R u||,
    with no cancellation (a Gram matrix would lose half the digits).  Rayleigh
    damping C = alpha M + beta K needs no C V columns.
    """

    def __init__(self, ops: _Operators, b: np.ndarray, capacity: int = 64) -> None:
        self.ops = ops
        # Q's columns live in a column-major buffer: pages of columns not yet written are
        # never touched (no resident memory), and adding columns copies nothing
        self._buffer = np.empty((ops.n, max(capacity, 2)), order="F")
        self.Q = self._buffer[:, :0]
        self.R = np.zeros((0, 0))   # (directions, columns of P): upper trapezoidal
        self.column: list[int] = []   # basis column of each column of P (-1: the load)
        self.kind: list[int] = []     # 0: K, 1: M, 2: C; for the load 0: Re b, 1: Im b
        self._add(np.column_stack([b.real, b.imag]), [-1, -1], [0, 1])
        self.size = 0

    def _add(self, X: np.ndarray, column: list[int], kind: list[int]) -> None:
        m = self.Q.shape[1]
        X = np.asfortranarray(X, dtype=float)   # (columns contiguous, as Q's)
        scale = float(max(X.max(initial=0.0), -X.min(initial=0.0)))
        R12 = np.zeros((m, X.shape[1]))
        for _ in range(2):
            if m:
                h = self.Q.T @ X
                X = X - (h.T @ self.Q.T).T   # = Q h, computed into Fortran order
                R12 += h
        # What is left spans at most n - m new directions; rounding noise of columns that
        # were (nearly) in the span of Q is dropped (below 1e-14 of the block).
        U, S, Wt = _svd_tall(X)
        rank = min(int(np.count_nonzero(S > 1e-14 * max(scale, 1e-300))), self.Q.shape[0] - m)
        Qn, R22 = U[:, :rank], S[:rank, None] * Wt[:rank]
        # orthogonalize Qn again and book the part taken out into R12 (X = Q R12 + Qn R22
        # stays exact, [Q Qn] stays orthonormal)
        if m and rank:
            h = self.Q.T @ Qn
            Qn = Qn - self.Q @ h
            R12 += h @ R22
            Qn, T = _orthonormalize(Qn)
            R22 = T @ R22
        R = np.zeros((m + rank, self.R.shape[1] + X.shape[1]))
        R[:m, :self.R.shape[1]], R[:m, self.R.shape[1]:] = self.R, R12
        R[m:, self.R.shape[1]:] = R22
        if m + rank > self._buffer.shape[1]:
            grown = np.empty((self._buffer.shape[0], max(m + rank, 2 * self._buffer.shape[1])),
                             order="F")
            grown[:, :m] = self.Q
            self._buffer = grown
        self._buffer[:, m:m + rank] = Qn
        self.Q, self.R = self._buffer[:, :m + rank], R
        self.column += column
        self.kind += kind

    def replace_load(self, b: np.ndarray) -> None:
        """The residual of another load on the same basis: the old load's columns leave P
        (their directions stay in Q, which spans more than P then: P = Q R holds), the new
        load's are added, O(n) per basis vector instead of a new factorization."""
        self.replace_loads(b[:, None])

    def replace_loads(self, B: np.ndarray) -> None:
        """:meth:`replace_load` with the loads of all columns of B (n, p) at once, load j
        being column -1 - j of P (:meth:`norms` with ``which=j``): one pass over Q for
        all of them."""
        kept = [i for i, c in enumerate(self.column) if c >= 0]
        self.R = self.R[:, kept]
        self.column = [self.column[i] for i in kept]
        self.kind = [self.kind[i] for i in kept]
        p = B.shape[1]
        X = np.empty((B.shape[0], 2 * p))
        X[:, 0::2], X[:, 1::2] = B.real, B.imag
        self._add(X, [-1 - j for j in range(p) for _ in range(2)], [0, 1] * p)

    def extend(self, products: list[np.ndarray], r: int) -> None:
        """Add the columns of the new basis vectors (``products``: K V_new, M V_new and
        C V_new when damped; r: the basis size now)."""
        if r == self.size:
            return
        new = range(self.size, r)
        blocks = products[:2]
        kinds = [0, 1]
        if len(products) > 2 and self.ops.rayleigh is None:  # (Rayleigh: C V is in there)
            blocks.append(products[2])
            kinds.append(2)
        self._add(np.hstack(blocks), [j for _ in kinds for j in new],
                  [k for k in kinds for _ in new])
        self.size = r

    def norms(self, w: np.ndarray, Y: np.ndarray, which: int = 0,
              deadline: Deadline = NO_DEADLINE) -> np.ndarray:
        """||A(w) V y(w) - b|| at the frequencies w for the reduced responses Y (N, r);
        b the load of column -1 - ``which`` (:meth:`replace_loads`); ``deadline``
        checked at every chunk of frequencies (10^5 of them on a basis of 300 took 6 s)."""
        column, kind = np.array(self.column), np.array(self.kind)
        used = (column >= 0) | (column == -1 - which)
        column, kind, R = column[used], kind[used], self.R[:, used]
        load = column < 0
        out = np.empty(len(w))
        chunk = max(1, _CHUNK_BYTES // (16 * max(len(column), 1)))
        for start in range(0, len(w), chunk):
            deadline.check("while estimating the reduced model's error", analysis=True)
            ww, yy = w[start:start + chunk, None], Y[start:start + chunk]
            if self.ops.rayleigh is None:
                factor = np.stack([np.ones_like(ww) + 0j, -(ww ** 2) + 0j, 1j * ww])
            else:  # C = alpha M + beta K: i w C V y goes onto the K and M columns
                alpha, beta = self.ops.rayleigh
                factor = np.stack([1 + 1j * beta * ww, -(ww ** 2) + 1j * alpha * ww])
            u = np.empty((len(ww), len(column)), dtype=complex)
            u[:, ~load] = factor[kind[~load], :, 0].T * yy[:, column[~load]]
            u[:, load] = np.where(kind[load] == 0, -1.0, -1j)
            with np.errstate(all="ignore"):
                out[start:start + chunk] = np.linalg.norm(u @ R.T, axis=1)
        return out


# -- the public function ----------------------------------------------------------------------

def _initial_points(w: np.ndarray, count: int) -> list[float]:
    """``count`` points spread over the band, each moved to the nearest frequency of w
    (where the reduced response is then exact, and a direct sweep can reuse the
    factorization of ``auto``'s cost probe)."""
    lo, hi = float(w.min()), float(w.max())
    if hi <= lo:
        return [lo]
    grid = np.unique(w)
    targets = [lo + (hi - lo) * (j + 0.5) / count for j in range(count)]
    return list(dict.fromkeys(float(grid[np.argmin(np.abs(grid - t))]) for t in targets))


def probe_frequency(w: np.ndarray) -> float:
    """The frequency (rad/s) where ``method="auto"`` measures a sparse factorization.

    It is the frequency of w nearest the middle of the band, one of the reduced
    model's first expansion points, so the measured factorization is one the
    reduced model uses as it is (pass it in ``factorizations``) and one a sparse
    direct sweep uses as it is.  (A shift outside the band, say s^2 = mean(diag K) / mean(diag M),
    can cancel the diagonal of K - s^2 M: on a uniform grid with unit masses it
    did, and the threshold pivoting that then leaves the diagonal multiplied the
    factorization's fill by 60 and its time by 400.)

    Parameters
    ----------
    w : ndarray
        The frequencies of the sweep (rad/s, signs ignored), not empty.

    Returns
    -------
    float

    Examples
    --------
    >>> probe_frequency(np.array([3.5, 1.0, 2.0, 5.0]))
    3.5
    """
    w = np.abs(np.asarray(w, dtype=float)).ravel()
    points = _initial_points(w, min(INITIAL_POINTS, len(np.unique(w))))
    return points[len(points) // 2]


class FactorThread:
    """A helper thread that factorizes, and frees in that thread what it made.

    SuperLU (scipy 1.17) gives a factor's memory back only when the factor is freed in the
    thread that made it: freed in another thread, every factorization of a 40,000-row
    grid kept its 40 MB (https://github.com/scipy/scipy/issues/15921).  So the thread
    keeps a reference to each factor it makes, and :meth:`release` -- called when the
    caller has let go of all of them -- drops those references in the thread, then lets
    the thread end.

    Examples
    --------
    >>> maker = FactorThread()
    >>> maker.submit(sum, [1, 2]).result()
    3
    >>> maker.release()
    """

    def __init__(self) -> None:
        self._pool = ThreadPoolExecutor(1, thread_name_prefix="resonant-lu")
        self._made: list[Any] = []
        self._futures: list[Future[Any]] = []

    def submit(self, fn: Callable[..., _T], *args: object) -> Future[_T]:
        """Run ``fn(*args)`` in the thread; its result is kept there until :meth:`release`."""
        future = self._pool.submit(self._keep, fn, *args)
        self._futures.append(future)
        return future

    def _keep(self, fn: Callable[..., _T], *args: object) -> _T:
        made = fn(*args)
        self._made.append(made)
        return made

    def release(self) -> None:
        """Cancel what has not started, free what was made (in the thread, after one
        under way), and let the thread end; the caller does not wait."""
        for future in self._futures:
            future.cancel()
        self._futures.clear()
        self._pool.submit(self._made.clear)
        self._pool.shutdown(wait=False)


class FactorizationsAhead:
    """The factorizations of a reduced model's first expansion points, made in a helper
    thread while the caller does something else (``auto``'s cost probe): pass
    :attr:`futures` in the ``factorizations`` of :func:`reduced_model` (each is waited
    for when its point comes), and call :meth:`stop` at the end (a factorization
    under way then finishes unused).  Large models only (:data:`PARALLEL_FACTOR_SIZE`):
    elsewhere :attr:`futures` is empty.

    Parameters
    ----------
    M, C, K : sparse matrix or ndarray
        As for :func:`reduced_model`.
    w : ndarray
        Its frequencies (rad/s).
    skip : sequence of float
        Points factorized elsewhere (the probe's :func:`probe_frequency`).

    Examples
    --------
    >>> ahead = FactorizationsAhead(np.eye(2), np.eye(2), np.eye(2), np.linspace(1, 2, 9))
    >>> ahead.futures, ahead.stop()
    ({}, None)
    """

    def __init__(self, M: Matrix, C: Matrix, K: Matrix, w: np.ndarray,
                 skip: tuple[float, ...] = ()) -> None:
        self.futures: dict[float, Any] = {}
        self._helper: FactorThread | None = None
        if M.shape[0] < PARALLEL_FACTOR_SIZE or not np.size(w):
            return
        w = np.abs(np.asarray(w, dtype=float)).ravel()
        points = [s for s in _initial_points(w, min(INITIAL_POINTS, len(np.unique(w))))
                  if s not in skip]
        if not points:
            return
        ops = _Operators(M, C, K)
        self._helper = FactorThread()
        self.futures = {s: self._helper.submit(ops.factor, s) for s in points}

    def stop(self) -> None:
        """Cancel what has not started and free the factors in the thread that made them
        (:class:`FactorThread`); call it when no factor of :attr:`futures` is used any
        more."""
        self.futures = {}
        if self._helper is not None:
            self._helper.release()
            self._helper = None


def off_diagonal_pivots(lu: SuperLU) -> int:
    """How many pivots of a SuperLU factorization were taken off the diagonal.

    With the symmetric-mode options of :func:`sparse_lu_options` every pivot
    should be diagonal (then the fill-reducing ordering holds); each pivot
    taken elsewhere (a diagonal below the threshold) breaks the ordering and
    adds fill.

    Parameters
    ----------
    lu : scipy.sparse.linalg.SuperLU

    Returns
    -------
    int

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from scipy.sparse.linalg import splu
    >>> A = sp.csc_matrix(np.array([[4.0, 1.0], [1.0, 3.0]]))
    >>> off_diagonal_pivots(splu(A, **sparse_lu_options(A)))
    0
    >>> A = sp.csc_matrix(np.array([[0.0, 1.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 0.0]]))
    >>> off_diagonal_pivots(splu(A, **sparse_lu_options(A)))   # a zero diagonal
    3
    """
    return int(np.count_nonzero(lu.perm_r != lu.perm_c))


def reduced_response(M: Matrix, C: Matrix, K: Matrix, b: np.ndarray, w: np.ndarray, *,
                     tol: float = DEFAULT_TOL, keep: np.ndarray | None = None,
                     deadline: Deadline = NO_DEADLINE, budget: float | None = None,
                     max_points: int | None = None, moments: int = MOMENTS,
                     factorizations: dict[float, Any] | None = None) -> ReducedResponse:
    """The response z(w) of (K - w^2 M + i w C) z = b by a reduced model, to ``tol``.

    Parameters
    ----------
    M, C, K : sparse matrix or ndarray
        Real (n, n) matrices, the same at every frequency.
    b : ndarray
        The complex load F_C - i F_S, shape (n,).
    w : ndarray
        The frequencies (rad/s), shape (N,).
    tol : float
        Relative tolerance of ||z - z_exact|| / ||z_exact|| at every frequency.
    keep : ndarray of int, optional
        The coordinates whose responses are returned (default all).
    deadline : Deadline, optional
        Checked between the factorizations and the moments.
    budget : float, optional
        Seconds after which no further expansion point is added (the result is
        then returned with ``converged`` False).
    max_points : int, optional
        Most expansion points (default :data:`MAX_POINTS`).
    moments : int
        Moments per expansion point.
    factorizations : dict, optional
        SuperLU factorizations of A(s) made before, by frequency s (the options of
        :func:`sparse_lu_options`): used instead of a new factorization where an
        expansion or validation point falls on s (``auto`` passes its cost probe,
        made at :func:`probe_frequency`, one of the first expansion points).  An
        entry used is removed from the dict, so that its memory is freed with the
        point's moments.

    Returns
    -------
    ReducedResponse

    Raises
    ------
    AnalysisError
        When no expansion point can be factorized (A singular everywhere tried).

    Examples
    --------
    >>> import numpy as np
    >>> M, K, C = np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]]), 0.01 * np.eye(2)
    >>> red = reduced_response(M, C, K, np.array([0.0, 1.0 + 0j]), np.linspace(0.1, 2, 50))
    >>> red.basis_size, red.converged
    (2, True)
    """
    start = time.monotonic()
    if not tol > 0:
        raise AnalysisError(f"the tolerance must be positive, not {tol}")
    w = np.abs(np.asarray(w, dtype=float))
    b = np.asarray(b, dtype=complex).ravel()
    ops = _Operators(M, C, K)
    ops.given = factorizations if factorizations is not None else {}
    keep = np.arange(ops.n) if keep is None else np.asarray(keep, dtype=int)
    if float(np.linalg.norm(b)) == 0:
        zeros = np.zeros(w.shape[0])
        return ReducedResponse(np.zeros((w.shape[0], len(keep)), dtype=complex), zeros, zeros,
                               zeros, 0.0, True, (), 0, (), np.zeros(w.shape[0], dtype=bool),
                               seconds=time.monotonic() - start)
    model = _Enrichment(ops, b, w, tol, moments, deadline)
    with blas_threads(_largest_call(ops.n)):
        _grow(model, _Limits(MAX_POINTS if max_points is None else max_points, budget, start))
        return model.result(keep, time.monotonic() - start)


def _largest_call(n: int) -> float:
    """FLOPs of the largest dense call of the enrichment: a product of the n x r basis
    with an r x r matrix, r of the order of 100."""
    return 8.0 * n * 1e4


def _grow(model: _Enrichment, stop: _Limits) -> None:
    """Enrich until the tolerance is met, a limit is reached or nothing is left to check."""
    while True:
        model.enrich()
        worst = model.evaluate()
        if worst is None:
            return
        model.deadline.check("while checking the reduced model", analysis=True)
        lu = model.validate(worst)
        if lu is None or model.done():
            return
        model.reason = model.at_floor() or model.stalled() or stop.reached(model)
        if model.reason:
            return
        model.pending = [(float(model.checks[-1][0]), lu)]


class _Limits:
    """When the enrichment stops short of the tolerance: points, basis, time."""

    def __init__(self, max_points: int, budget: float | None, start: float) -> None:
        self.max_points, self.budget, self.start = max_points, budget, start

    def reached(self, model: _Enrichment) -> str:
        if len(model.expansion) >= self.max_points:
            return f"the cap of {self.max_points} expansion points was reached"
        if model.V.shape[1] >= model.max_basis:
            return f"the cap of {model.max_basis} basis vectors was reached"
        if self.budget is not None and time.monotonic() - self.start > self.budget:
            return f"the time budget of {self.budget:.3g} s was used up"
        return ""


class _Enrichment:
    """The reduced basis grown point by point, with its residual-based error estimate
    calibrated by exact solves where the residual is largest."""

    def __init__(self, ops: _Operators, b: np.ndarray, w: np.ndarray, tol: float,
                 moments: int, deadline: Deadline, V: np.ndarray | None = None,
                 shared: tuple[_Projection, _Residual] | None = None) -> None:
        self.ops, self.b, self.w, self.tol = ops, b, w, tol
        self.moments, self.deadline = moments, deadline
        self.b_norm = float(np.linalg.norm(b))
        self.drop = min(1e-8, 1e-3 * tol)
        # bounds of the 2-norms: ||a||_2 <= sqrt(||a||_1 ||a||_inf)
        self.norms = [float(max(abs(a).sum(axis=0).max(), abs(a).sum(axis=1).max()))
                      if a.nnz else 0.0 for a in (ops.K, ops.M, ops.C)]
        # bytes per basis column: V and the residual's Q (K V, M V, C V directions), with
        # room for the temporaries of the newest point's columns, and the reduced
        # responses at every frequency (Y, and its copy as it grows)
        self.max_basis = int(min(MAX_BASIS, budget() // (8 * ops.n * 5 + 32 * len(w))))
        self.width = float(w.max() - w.min())
        # a basis given (other loads') is enriched further
        self.V = np.zeros((ops.n, 0)) if V is None else V
        self.expansion: list[float] = []
        #: the exact solves at the expansion points that are frequencies of w, by index
        self.exact: dict[int, np.ndarray] = {}
        self.exact_error: dict[int, float] = {}
        self.checks: list[tuple[float, float]] = []
        self.ratios: list[float] = []
        self.history: list[float] = []
        self.medians: list[float] = []
        self.pending: list[tuple[float, Any]] = [
            (s, None) for s in _initial_points(w, min(INITIAL_POINTS, len(np.unique(w))))]
        if shared is None:
            self.residual = _Residual(ops, b, 2 + 3 * min(self.max_basis, FIRST_CAPACITY))
            self.projection = _Projection(ops)
        else:   # another load's, on the basis V given: its products are not made again
            self.projection, self.residual = shared
            self.residual.replace_load(b)
        self.reason = ""
        N = w.shape[0]
        self.Y = np.zeros((N, 0), dtype=complex)
        self.finite = np.zeros(N, dtype=bool)
        self.rho = np.full(N, np.inf)
        self.estimate = np.full(N, np.inf)
        self.floor = np.zeros(N)
        self.floor_ratios: list[float] = []

    def a_norm(self, w: np.ndarray) -> np.ndarray:
        """A bound of the 2-norm of A(w)."""
        return self.norms[0] + w**2 * self.norms[1] + w * self.norms[2]

    def enrich(self) -> None:
        """The moments at every pending point (its factorization, if known).

        Where several points of a large model need a factorization, a helper thread
        factorizes the later ones while this thread factorizes the first and builds the
        moments (SuperLU releases the GIL: on two cores the three first points of a
        250,000-coordinate grid took 3.8 s instead of 6.0 s)."""
        todo = [s for s, lu in self.pending if lu is None]
        ahead: dict[float, Any] = {}
        stack = contextlib.ExitStack()
        if len(todo) > 1 and self.ops.n >= PARALLEL_FACTOR_SIZE:
            helper = self.ops.helper()
            for s in todo[1:]:
                made: dict[float, Any] = {}
                ahead[s] = (helper.submit(_factor_near, self.ops, s, self.width, made), made)
            # one core for the helper, one for this thread's BLAS calls (a BLAS thread
            # sharing its core with the helper would hold up the others at every step)
            stack.enter_context(blas_threads(0.0))
        try:
            for s, lu in self.pending:
                self.deadline.check("while building the reduced basis", analysis=True)
                if lu is None and s in ahead:
                    future, made = ahead.pop(s)
                    lu, s = future.result()
                    if self.ops.cache is not None:
                        self.ops.cache.update(made)
                elif lu is None:
                    lu, s = _factor_near(self.ops, s, self.width)
                if lu is None:
                    continue
                self.expansion.append(float(s))
                x0 = lu.solve(self.b)
                self._keep_exact(lu, float(s), x0)
                self.V = _extend(self.V, _krylov(self.ops, lu, self.b, s, self.moments,
                                                 self.deadline, x0), self.drop)
                del lu
                if self.V.shape[1] >= self.max_basis:
                    self.V = self.V[:, :self.max_basis]
                    break
        finally:
            for future, _ in ahead.values():   # not needed any more
                future.cancel()
            stack.close()
        self.pending = []
        if self.V.shape[1] == 0:
            raise AnalysisError("the reduced model has no basis: A(w) is singular at every "
                                "expansion point tried; use a direct method")

    def evaluate(self) -> int | None:
        """Solve the reduced model at every frequency, estimate the errors; the index of
        the frequency to validate next (None: nothing left to validate)."""
        w = self.w
        products = self.projection.update(self.V)
        Kr, Mr, Cr = self.projection.reduced
        red = _Reduced(Kr, Mr, Cr, _real_times(self.V.T, self.b))
        self.Y = red.solve(w, self.deadline)
        # an undamped resonance (condition number beyond SINGULAR_CONDITION and a response
        # the damping does not act on, as in the kernel) has no response to estimate: such
        # points are singular, not errors.  (The condition number alone calls a damped
        # but ill-conditioned structure resonant: a fine beam mesh, cond(K) ~ n^4.)
        with np.errstate(all="ignore"):
            condition = self.a_norm(w) * np.linalg.norm(self.Y, axis=1) / self.b_norm
        finite = np.all(np.isfinite(self.Y), axis=1)
        resonant = ~(condition <= SINGULAR_CONDITION) & finite
        if resonant.any():
            # z = V y with V real and orthonormal: z^H C z = y^H Cr y and ||z|| = ||y||
            fraction = damping_fraction(Cr, self.Y[resonant], self.norms[2])
            resonant[resonant] = fraction < DAMPED_FRACTION
        self.finite = finite & ~resonant
        # the rounding floor: no solution in doubles is known better than about eps times
        # the condition number (the exact solves of the validation included)
        self.floor = np.where(self.finite, np.finfo(float).eps * condition, 0.0) * \
            self.floor_scale()
        self.rho = np.full(w.shape[0], np.inf)
        self.residual.extend(products, self.V.shape[1])
        del products
        if self.finite.any():
            self.rho[self.finite] = self.residual.norms(
                w[self.finite], self.Y[self.finite], deadline=self.deadline) / self.b_norm
        self.estimate = np.maximum(SAFETY * self.gamma() * self.rho, self.floor)
        self._measured_at_expansion()
        # validate where the residual is largest (the expansion points themselves are exact)
        candidates = np.where(self.finite & ~np.isin(w, self.expansion), self.rho, -np.inf)
        worst = int(np.argmax(candidates))
        return worst if np.isfinite(candidates[worst]) else None

    def _keep_exact(self, lu: Solver, s: float, x: np.ndarray) -> None:
        """Keep the exact solve at an expansion point that is a frequency of the sweep,
        with the estimate of its rounding error (:meth:`solve_error`), while the kept
        solves take at most a tenth of the memory budget."""
        at = np.flatnonzero(self.w == s)
        if at.size and 16.0 * x.size * (len(self.exact) + 1) <= 0.1 * budget():
            self.exact[int(at[0])] = x
            self.exact_error[int(at[0])] = self.solve_error(lu, s, x)

    def _measured_at_expansion(self) -> None:
        """At the expansion points that are frequencies of the sweep the exact solve is
        known and is the response returned there (:meth:`result`): its error is that
        solve's rounding error (:meth:`solve_error`, at least the floor), not the
        residual's estimate.

        Near a sharp resonance the reduced response is not the exact one even where its
        basis holds it: the reduced matrices carry the rounding of V^T K V, which the
        resonance amplifies, and the residual overstates the error (the basis holds x
        to about 1e-10 of its norm in the stiff directions, which ||A|| multiplies
        while A^-1 hardly acts on them).  A 2,000-row chain with damping ratios of 1e-5
        whose peak was an expansion point: the reduced response there 6e-8 off, its
        estimate 1.2e-6, where the exact solve was at hand; that one point kept the band
        above the tolerance (tests/test_reduced_band.py)."""
        for i, error in self.exact_error.items():
            if self.finite[i]:
                self.estimate[i] = max(self.floor[i], error)

    def gamma(self) -> float:
        """How far the true error has been seen above the residual, recently."""
        return max([1.0] + self.ratios[-RECENT:])

    def validate(self, worst: int) -> Any:
        """The exact solve at ``w[worst]``: calibrates the estimate; its factorization
        (None where A is singular: nothing to validate there)."""
        side, self.ops.side = self.ops.side, None
        if side is not None and self.ops.n >= PARALLEL_FACTOR_SIZE:
            # the factorization in a helper thread, the side work (the adjoints' moments)
            # here meanwhile, one BLAS thread (a core each)
            made: dict[float, Any] = {}
            future = self.ops.helper().submit(_factor_near, self.ops, float(self.w[worst]),
                                              0.0, made)
            try:
                with blas_threads(0.0):
                    side()
                lu, s = future.result()
            finally:
                future.cancel()   # (side() failed: not needed)
            if self.ops.cache is not None:
                self.ops.cache.update(made)
        else:
            lu, s = _factor_near(self.ops, float(self.w[worst]), 0.0)
        if lu is None:
            return None
        exact = lu.solve(self.b)
        solver = lu
        if not backward_stable(self.ops.matrix(s), exact, self.b):  # pivots grew too much
            solver = self.ops.factor(s, partial=True)
            exact = solver.solve(self.b)
        approx = _real_times(self.V, self.Y[worst])
        true = float(np.linalg.norm(approx - exact)) / max(float(np.linalg.norm(exact)),
                                                            1e-300)
        self.checks.append((s, true))
        if self.rho[worst] > 0:
            self.ratios.append(true / self.rho[worst])
        # the exact solve's own rounding error (componentwise, where it is known) calibrates
        # the normwise floor eps * condition at every frequency
        normwise = self.floor / self.floor_scale()   # eps * condition
        if normwise[worst] > 0:
            self.floor_ratios.append(
                min(1.0, self.solve_error(solver, s, exact) / normwise[worst]))
            self.floor = normwise * self.floor_scale()
        self.estimate = np.maximum(SAFETY * self.gamma() * self.rho, self.floor)
        self._measured_at_expansion()
        self.estimate[worst] = max(true + self.floor[worst], self.estimate[worst])
        return lu

    def floor_scale(self) -> float:
        """The largest ratio of componentwise to normwise rounding floor seen at the
        validations (1 before any)."""
        return max(self.floor_ratios) if self.floor_ratios else 1.0

    def solve_error(self, lu: Solver, s: float, x: np.ndarray) -> float:
        """An estimate of the relative error of the exact solve x = A(s)^-1 b from rounding:
        ``FLOOR_SAFETY`` eps || |A^-1| (|A| |x| + |b|) || / ||x|| (Skeel's componentwise
        bound, Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., Sect. 7.2),
        its |A^-1| estimated by two solves with random signs.  A stiff local spring
        makes the normwise condition number huge and this small; a fine beam mesh keeps
        both large."""
        ops = self.ops
        if ops.abs is None:
            ops.abs = tuple(abs(a) for a in (ops.K, ops.M, ops.C))
        aK, aM, aC = ops.abs
        ax = np.abs(x)
        weight = aK @ ax + (s * s) * (aM @ ax) + abs(s) * (aC @ ax) + np.abs(self.b)
        rng = np.random.default_rng(1)
        worst = 0.0
        for _ in range(2):
            phase = np.exp(2j * np.pi * rng.random(ops.n))
            worst = max(worst, float(np.linalg.norm(lu.solve(weight * phase))))
        eps = np.finfo(float).eps
        return FLOOR_SAFETY * eps * worst / max(float(np.linalg.norm(x)), 1e-300) + eps

    def at_floor(self) -> str:
        """Why enriching further cannot meet the tolerance: the last validation's error is
        within the rounding floor of the model's conditioning there ("" otherwise)."""
        if not self.checks or not self.finite.any():
            return ""
        top = float(np.max(self.floor))
        if top <= self.tol or self.checks[-1][1] > FLOOR_REACHED * top:
            return ""
        return (f"the model's conditioning limits the accuracy of any solution in double "
                f"precision to about {top:.2g} (condition number at least "
                f"{top / np.finfo(float).eps:.2g}): ask for a larger tolerance")

    def done(self) -> bool:
        """The estimate and the last exact check both within the tolerance."""
        top = float(np.max(self.estimate[self.finite], initial=0.0))
        return top <= self.tol and self.checks[-1][1] <= self.tol

    def stalled(self) -> str:
        """Why the enrichment stops: neither the largest residual over the band nor its
        median halved over the last :data:`STALL` steps ("" while either does).  Over a
        wide band with many modes the largest residual wanders from one frequency to
        the next while each expansion point settles its neighbourhood (the median falls
        a hundredfold where the largest stays near 10: a 2,500-coordinate grid over 17
        times its first natural frequency); at the rounding floor both stop."""
        rho = self.rho[self.finite]
        self.history.append(float(np.max(rho, initial=0.0)))
        self.medians.append(float(np.median(rho)) if rho.size else 0.0)
        if len(self.history) > STALL and self.history[-1] > 0.5 * self.history[-1 - STALL] \
                and self.medians[-1] > 0.5 * self.medians[-1 - STALL]:
            return (f"the residual stopped decreasing at {self.history[-1]:.2g} (rounding "
                    "floor: ask for a larger tolerance)")
        return ""

    def result(self, keep: np.ndarray, seconds: float) -> ReducedResponse:
        finite, N = self.finite, self.w.shape[0]
        estimate = np.where(finite, self.estimate, np.nan)
        top = float(np.nanmax(estimate)) if np.any(finite) else float("inf")
        converged = top <= self.tol
        reason = self.reason or "the estimated error stayed above the tolerance"
        Z = np.full((N, len(keep)), np.nan + 0j)
        Z[finite] = self.Y[finite] @ self.V[keep].T
        norm_z = np.where(finite, np.linalg.norm(np.where(finite[:, None], self.Y, 0), axis=1),
                          np.inf)
        for i, x in self.exact.items():   # the exact solves of the expansion points
            if finite[i]:
                Z[i], norm_z[i] = x[keep], float(np.linalg.norm(x))
        return ReducedResponse(Z, norm_z, np.where(finite, self.rho, np.nan), estimate, top,
                               converged, tuple(self.expansion), int(self.V.shape[1]),
                               tuple(self.checks), ~finite, "" if converged else reason,
                               seconds)


def _factor_near(ops: _Operators, s: float, width: float,
                 made: dict[float, Any] | None = None) -> tuple[Any, float]:
    """The LU of A(s), or of A at a nearby frequency when A(s) is exactly singular.
    Where the factorizations are kept (``ops.cache``), a new one goes into ``made``
    if given (a helper thread's: the caller adds it to the cache, which is not changed
    under another thread's iteration then), else into the cache."""
    keep = ops.cache if made is None or ops.cache is None else made
    for shift in (0.0, 1e-3, -1e-3, 1e-2):
        t = s + shift * max(width, abs(s), 1e-12)
        if t in ops.given:  # taken: its memory goes with the point's moments
            found = ops.given.pop(t)
            if isinstance(found, Future):   # made for this model (FactorizationsAhead)
                try:
                    found = found.result()
                except RuntimeError:
                    continue
                if keep is not None:   # kept as one made here would be
                    keep[t] = found
            return found, t
        if ops.cache is not None and t in ops.cache:
            return ops.cache[t], t
        try:
            lu = ops.factor(t)
            if keep is not None:
                keep[t] = lu
            return lu, t
        except RuntimeError:  # "Factor is exactly singular"
            continue
    return None, s


@dataclass(frozen=True)
class ReducedModel:
    """A reduced-order model of (K - w^2 M + i w C) z = B u for several loads over a band.

    One real orthonormal basis V (n, r) serves every load column of B; the reduced
    matrices are its Galerkin projections.  The transfer from the loads to any
    coordinate at any frequency is then an r x r solve
    (:meth:`transfer`).

    Attributes
    ----------
    V : ndarray
        (n, r) basis.
    Mr, Cr, Kr : ndarray
        (r, r) reduced matrices Vᵀ M V, Vᵀ C V, Vᵀ K V.
    Br : ndarray
        (r, p) reduced loads Vᵀ B (complex).
    estimated_error : ndarray
        (p,) the estimated largest relative error of each load's response over the
        band (an estimate, not a bound: see the module docstring).
    checks : tuple of (float, float)
        Validation solves: frequency and true relative error there.
    converged : bool
        Whether every load met the tolerance.
    reason : str
        Why not ("" when converged).
    expansion : tuple of float
    seconds : float
    adjoint_residuals : ndarray
        (q,) the largest relative residual ||A(w) V y(w) - c|| / ||c|| over the band of
        each column c of ``adjoints`` (computed, not estimated; empty without).
    floor : float
        The largest rounding floor of the model's conditioning over the band: the
        accuracy of any double-precision solve there, exact ones included (an estimate).
    """

    V: np.ndarray
    Mr: np.ndarray
    Cr: np.ndarray
    Kr: np.ndarray
    Br: np.ndarray
    estimated_error: np.ndarray
    checks: tuple[tuple[float, float], ...]
    converged: bool
    reason: str
    expansion: tuple[float, ...]
    seconds: float
    adjoint_residuals: np.ndarray = field(default_factory=lambda: np.zeros(0))
    floor: float = 0.0

    def __post_init__(self) -> None:
        for name in ("V", "Mr", "Cr", "Kr", "Br", "estimated_error", "adjoint_residuals"):
            array = np.array(getattr(self, name))
            array.flags.writeable = False
            object.__setattr__(self, name, array)

    def transfer(self, w: float, rows: np.ndarray, loads: np.ndarray | None = None
                 ) -> np.ndarray:
        """z at the coordinates ``rows`` for each reduced load column, shape (rows, p).

        ``loads``: (r, c) reduced loads instead of :attr:`Br`.
        """
        A = self.Kr - w * w * self.Mr + 1j * w * self.Cr
        rhs = self.Br if loads is None else loads
        result: np.ndarray = self.V[rows] @ np.linalg.solve(A, rhs)
        return result

    def responses(self, w: np.ndarray, rows: np.ndarray, columns: int | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
        """z at the coordinates ``rows`` for every load column at many frequencies, and
        the norm of the whole response vector.

        The reduced system is diagonalized once per load (as in :func:`reduced_response`),
        so a frequency costs O(r) per coordinate.

        Parameters
        ----------
        w : ndarray
            Frequencies (rad/s), shape (N,).
        rows : ndarray of int
            The coordinates.
        columns : int, optional
            Only the first ``columns`` loads (default all).

        Returns
        -------
        Z : ndarray
            (N, rows, p) complex; inf or NaN where the reduced system is singular.
        norms : ndarray
            (N, p): ||z(w)||_2 over all n coordinates (= ||y(w)||_2, V being orthonormal).

        Examples
        --------
        >>> import numpy as np
        >>> M, K, C = np.eye(3), np.diag([2.0, 3.0, 4.0]), 0.01 * np.eye(3)
        >>> B = np.eye(3)[:, :2].astype(complex)
        >>> rom = reduced_model(M, C, K, B, np.linspace(0, 2, 30))
        >>> Z, norms = rom.responses(np.array([0.5, 1.5]), np.arange(3))
        >>> exact = np.linalg.solve(K - 2.25 * M + 0.015j * np.eye(3), B)
        >>> bool(np.abs(Z[1] - exact).max() < 1e-10), Z.shape, norms.shape
        (True, (2, 3, 2), (2, 2))
        """
        w = np.abs(np.asarray(w, dtype=float)).ravel()
        rows = np.asarray(rows, dtype=int)
        p = self.Br.shape[1] if columns is None else int(columns)
        Z = np.empty((len(w), len(rows), p), dtype=complex)
        norms = np.empty((len(w), p))
        for j in range(p):
            Y = _Reduced(self.Kr, self.Mr, self.Cr, self.Br[:, j]).solve(w)
            with np.errstate(all="ignore"):
                Z[:, :, j] = Y @ self.V[rows].T
                norms[:, j] = np.linalg.norm(Y, axis=1)
        return Z, norms


def reduced_model(M: Matrix, C: Matrix, K: Matrix, B: np.ndarray, w: np.ndarray, *,
                  tol: float = DEFAULT_TOL, deadline: Deadline = NO_DEADLINE,
                  budget: float | None = None, max_points: int | None = None,
                  moments: int = MOMENTS, adjoints: np.ndarray | None = None,
                  factorizations: dict[float, Any] | None = None) -> ReducedModel:
    """One reduced basis for the responses to every column of B at the frequencies w.

    The enrichment of :func:`reduced_response` runs for each load in turn on the
    basis the previous ones built (factorizations are shared), so later loads
    mostly find their response already in the span.

    ``adjoints`` (n, q), optional: further loads, typically unit loads at the
    coordinates whose responses matter, that are not enriched to ``tol``: the basis
    gets :data:`ADJOINT_MOMENTS` moments of each at the factorized expansion point
    nearest the band's middle, and the largest relative residual of each over ``w``
    is computed (``adjoint_residuals``).  For symmetric M, C, K (A^T = A) the Galerkin
    orthogonality V^T A (z - z_exact) = 0 gives e_i^T (z - z_exact) = r_i^T (z - z_exact)
    with r_i the residual of the unit load at i: the error of coordinate i is at most
    that residual times ||z - z_exact|| (the dual-weighted residual of Becker &
    Rannacher).  The loads' ``estimated_error`` is from before these vectors joined
    the basis (as for the earlier loads of B).

    Parameters
    ----------
    M, C, K : sparse matrix or ndarray
        Real (n, n).
    B : ndarray
        (n, p) complex loads.
    w : ndarray
        Frequencies (rad/s) where each response must meet ``tol``.
    tol, deadline, budget, max_points, moments, factorizations
        As for :func:`reduced_response`.
    adjoints : ndarray, optional
        (n, q) loads whose residuals are computed (see above).

    Returns
    -------
    ReducedModel

    Examples
    --------
    >>> import numpy as np
    >>> M, K, C = np.eye(3), np.diag([2.0, 3.0, 4.0]), 0.01 * np.eye(3)
    >>> K[0, 1] = K[1, 0] = -1.0
    >>> rom = reduced_model(M, C, K, np.eye(3)[:, :2].astype(complex), np.linspace(0, 2, 30))
    >>> z = rom.transfer(1.0, np.arange(3))
    >>> exact = np.linalg.solve(K - M + 0.01j * np.eye(3), np.eye(3)[:, :2])
    >>> bool(np.abs(z - exact).max() < 1e-10), rom.converged
    (True, True)
    """
    start = time.monotonic()
    if not tol > 0:
        raise AnalysisError(f"the tolerance must be positive, not {tol}")
    w = np.abs(np.asarray(w, dtype=float)).ravel()
    B = np.asarray(B, dtype=complex).reshape(np.shape(B)[0], -1)
    ops = _Operators(M, C, K)
    ops.cache = {}
    ops.given = factorizations if factorizations is not None else {}
    V = np.zeros((ops.n, 0))
    stop = _Limits(MAX_POINTS if max_points is None else max_points, budget, start)
    early: dict[float, list[np.ndarray]] = {}   # the adjoints' moments, made ahead
    if adjoints is not None and np.shape(adjoints)[1]:
        unit = np.asarray(adjoints, dtype=complex)

        def side() -> None:   # (at the first validation, while it is factorized)
            if ops.cache:
                s = _adjoint_point(ops, w)
                early[s] = _adjoint_moments(ops, unit, s, deadline)

        ops.side = side
    errors, checks, expansion, reasons = [], [], [], []
    floor = 0.0
    shared: tuple[_Projection, _Residual] | None = None
    model: _Enrichment | None = None
    try:
        for j in range(B.shape[1]):
            if not np.any(B[:, j]):
                errors.append(0.0)
                continue
            model = _Enrichment(ops, B[:, j], w, tol, moments, deadline, V, shared)
            with blas_threads(_largest_call(ops.n)):
                _grow(model, stop)
            V = model.V
            shared = (model.projection, model.residual)
            errors.append(float(np.nanmax(np.where(model.finite, model.estimate, np.nan)))
                          if model.finite.any() else float("inf"))
            checks += model.checks
            expansion += model.expansion
            floor = max(floor, float(np.max(model.floor, initial=0.0)))
            if model.reason:
                reasons.append(model.reason)
        residuals = np.zeros(0)
        if adjoints is not None and np.shape(adjoints)[1] and shared is not None and ops.cache:
            V, residuals = _adjoints(ops, shared, np.asarray(adjoints, dtype=complex), V, w,
                                     deadline, early)
    finally:
        # the factorizations go (a helper thread's freed there): the model's last one too
        model = None
        early.clear()
        ops.release()
    if shared is not None and shared[0].size == V.shape[1] and ops.damped:
        Kr, Mr, Cr = shared[0].reduced     # kept up to date while the basis grew
    else:
        Kr, Mr, Cr = (V.T @ np.asarray(a @ V) for a in (ops.K, ops.M, ops.C))
    err = np.array(errors)
    converged = bool(np.all(err <= tol))
    reason = "" if converged else (reasons[0] if reasons else
                                   "the estimated error stayed above the tolerance")
    return ReducedModel(V, Mr, Cr, Kr, _real_times(V.T, B), err, tuple(checks),
                        converged, reason, tuple(sorted(set(expansion))),
                        time.monotonic() - start, residuals, floor)


def _adjoint_point(ops: _Operators, w: np.ndarray) -> float:
    """The cached factorization's frequency nearest the band's middle."""
    assert ops.cache
    middle = float(np.sqrt(max(w.min(), 1e-300) * w.max())) if w.min() > 0 else \
        float(w.mean())
    return min(ops.cache, key=lambda t: abs(t - middle))


def _adjoint_moments(ops: _Operators, C: np.ndarray, s: float, deadline: Deadline
                     ) -> list[np.ndarray]:
    """:data:`ADJOINT_MOMENTS` moments of each column of C about s (cached there)."""
    assert ops.cache is not None
    lu = ops.cache[s]
    moments = []
    for j in range(C.shape[1]):
        deadline.check("while building the reduced basis", analysis=True)
        moments.append(_krylov(ops, lu, C[:, j], s, ADJOINT_MOMENTS, deadline))
    return moments


def _adjoints(ops: _Operators, shared: tuple[_Projection, _Residual], C: np.ndarray,
              V: np.ndarray, w: np.ndarray, deadline: Deadline,
              early: dict[float, list[np.ndarray]] | None = None
              ) -> tuple[np.ndarray, np.ndarray]:
    """The basis with :data:`ADJOINT_MOMENTS` moments of each column of C at the cached
    factorization nearest the band's middle, and each column's largest relative residual
    over w on it (:func:`reduced_model`).  ``early``: moments made before, by point
    (used if made at that point)."""
    s = _adjoint_point(ops, w)
    moments = (early or {}).pop(s, None) or _adjoint_moments(ops, C, s, deadline)
    # one extension and one residual update for all of them (each pass over the n x r
    # basis and the residual's n x 2r directions costs as much for one column as for ten)
    V = _extend(V, np.hstack(moments), 1e-8)
    del moments
    projection, residual = shared
    products = projection.update(V)
    residual.extend(products, V.shape[1])
    del products
    Kr, Mr, Cr = projection.reduced
    residual.replace_loads(C)
    out = np.empty(C.shape[1])
    for j in range(C.shape[1]):
        c = C[:, j]
        Y = _Reduced(Kr, Mr, Cr, _real_times(V.T, c)).solve(w)
        with np.errstate(all="ignore"):
            rho = residual.norms(w, Y, which=j) / float(np.linalg.norm(c))
        out[j] = float(np.max(rho)) if np.all(np.isfinite(rho)) else np.inf
    return V, out


# -- the modal fallback: modes and load-dependent Ritz vectors, checked by exact solves --

#: most modes in the modal fallback's basis; frequencies where it is checked exactly
MAX_MODES = 400
CHECKS = 7


def _scaling(M: Matrix, K: Matrix) -> np.ndarray:
    """D = diag(K)^(-1/2) where the stiffness diagonal is positive (else diag(M)^(-1/2),
    else 1): a symmetric scaling that gives every coordinate unit diagonal stiffness."""
    k = np.asarray(K.diagonal() if hasattr(K, "diagonal") else np.diag(K), dtype=float)
    m = np.asarray(M.diagonal() if hasattr(M, "diagonal") else np.diag(M), dtype=float)
    d = np.where(k > 0, k, np.where(m > 0, m, 1.0))
    return np.asarray(1.0 / np.sqrt(d))


def _sparse_diagonal(d: np.ndarray) -> Any:
    import scipy.sparse as sp

    return sp.diags(d, format="csr")


def symmetric(a: Matrix) -> bool:
    """Whether ``a`` (dense or sparse) equals its transpose to 1e-12 of its largest entry."""
    diff = a - a.T
    size = abs(diff).max() if hasattr(diff, "toarray") else np.abs(diff).max(initial=0.0)
    scale = abs(a).max() if hasattr(a, "toarray") else np.abs(a).max(initial=0.0)
    return bool(size <= 1e-12 * scale)


def _ritz_basis(M: Matrix, K: Matrix, B: np.ndarray, cut: float, levels: int, lu: SuperLU,
                deadline: Deadline = NO_DEADLINE) -> np.ndarray:
    """The modes below ``cut`` and ``levels`` load-dependent Ritz blocks
    (K^-1 B, K^-1 M K^-1 B, ...: the static and quasi-static response of the modes
    above), orthonormalized."""
    phi = modes_below(K, M, lu, cut, MAX_MODES, deadline) if M.shape[0] > 2 else \
        np.zeros((M.shape[0], 0))
    loads = np.hstack([B.real, B.imag])
    X = lu.solve(loads[:, np.abs(loads).max(axis=0) > 0])
    blocks = [phi]
    for _ in range(levels):
        X = X - phi @ (phi.T @ (M @ X))
        blocks.append(X)
        X = lu.solve(M @ X)
    Q, R = np.linalg.qr(np.hstack(blocks))
    d = np.abs(np.diag(R))
    return np.asarray(Q[:, d > 1e-12 * d.max()])


def modal_ritz_basis(M: Matrix, C: Matrix, K: Matrix, B: np.ndarray, top: float, rows: list[int],
                 tol: float, deadline: Deadline) -> tuple[np.ndarray, float] | None:
    """A basis of modes and load-dependent Ritz vectors whose transfer to ``rows`` meets
    ``tol`` at check frequencies over the band (exact sparse solves there); the largest
    error seen, or None when no basis of at most :data:`MAX_MODES` modes meets it."""
    D = _scaling(M, K)  # deflections and slopes of a beam differ in scale by far
    Ds = _sparse_diagonal(D)
    M, K, B = Ds @ M @ Ds, Ds @ K @ Ds, D[:, None] * B
    C = None if C is None else Ds @ C @ Ds
    lu = factor_stiffness(K, M, top)
    checks = np.linspace(0.0, top, CHECKS)
    exact = [transfer_at(M, C, K, B, w)[rows] for w in checks]
    scale = max(float(np.abs(t).max()) for t in exact)
    previous = np.inf
    for cut, levels in ((4 * top, 2), (8 * top, 3), (16 * top, 4)):
        deadline.check("while building the reduced model of the linear part", analysis=True)
        V = _ritz_basis(M, K, B, cut, levels, lu, deadline)
        Mr, Kr, Br = V.T @ (M @ V), V.T @ (K @ V), V.T @ B
        Cr = V.T @ (C @ V) if C is not None else np.zeros_like(Mr)
        error = max(float(np.abs(V[rows] @ np.linalg.solve(Kr - w * w * Mr + 1j * w * Cr, Br)
                                 - t).max()) for w, t in zip(checks, exact)) / scale
        # met, or a larger basis no longer helps: the rounding floor of the exact solves
        # of an ill-conditioned K (then accepted up to 100 tol, said in the warning)
        if error <= tol or (error >= 0.5 * previous and error <= 100 * tol):
            return D[:, None] * V, error
        previous = error
    return None


def transfer_at(M: Matrix, C: Matrix | None, K: Matrix, B: np.ndarray, w: float,
                refine: int = 0, residuals: Residuals | None = None) -> np.ndarray:
    """(K - w^2 M + i w C)^-1 B at one frequency by one sparse LU: the exact reference a
    reduced basis is checked against.

    ``refine`` steps of iterative refinement with residuals in extended precision
    (:meth:`~resonant.analyses.forward_error.Residuals.extended`, from ``residuals`` when
    given; Higham 2002, ch. 12) make the answer accurate to about the unit roundoff
    where the LU's own error, of the order of the condition number times it, would vary
    from one frequency to the next.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> K, M = sp.diags([4.0, 9.0]), sp.identity(2)
    >>> transfer_at(M, None, K, np.eye(2), 1.0).real.diagonal().round(6).tolist()
    [0.333333, 0.125]
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    A = sp.csc_matrix(K - w * w * M + (1j * w * C if C is not None else 0 * M))
    lu = splu(A)
    X = np.asarray(lu.solve(B))
    if refine:
        B = np.asarray(B, dtype=complex).reshape(X.shape)
        res = residuals or Residuals(K, M, C if C is not None else 0 * M)
        real = not np.iscomplexobj(A.data)
        for _ in range(refine):
            R = np.column_stack([res.extended(w, X[:, j], B[:, j]) for j in range(X.shape[1])])
            X = X + (lu.solve(R.real) + 1j * lu.solve(R.imag) if real else lu.solve(R))
    return X


__all__ = ["reduced_response", "ReducedResponse", "reduced_model", "ReducedModel",
           "DEFAULT_TOL", "sparse_lu_options", "backward_stable", "probe_frequency",
           "off_diagonal_pivots", "damping_fraction", "damping_norm", "DampingFraction",
           "DAMPED_FRACTION", "ScaledLU",
           "symmetric_scale", "FactorizationsAhead", "FactorThread", "SuperLUOptions"]
