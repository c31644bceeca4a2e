"""The one harmonic kernel: (K - w^2 M + i w C) z = F_C - i F_S for every w of a batch.

The stationary solution is the kernel at the excitation frequencies, a sweep
the kernel at every value of the swept parameter.  The complex systems are
solved by the cheapest exact method for their structure:

``"dense"``
    a stack of complex matrices, one ``numpy.linalg.solve`` per chunk of points
    (equilibrated first, with exact condition numbers where they are cheap);
``"banded"``
    LAPACK ``gbsv`` (``gtsv`` for tridiagonal) per point, when M, C, K do not
    depend on the parameter and their bandwidth is small;
``"sparse"``
    a sparse LU (SuperLU) per point, for large sparse matrices with a wide band;
``"modal"``
    superposition of *all* undamped modes, exact only when the damping is
    proportional (``K M^-1 C = C M^-1 K``); its accuracy is checked against a
    direct solve at a few points, with a direct method as the fallback;
``"reduced"``
    a reduced-order model (:mod:`resonant.analyses.reduced`: multi-point
    second-order Krylov basis from a few sparse factorizations, a posteriori
    error estimate, adaptive enrichment) for large models and many
    frequencies, accurate to the tolerance ``tol`` rather than exact.

``"direct"`` is the cheapest exact method among dense, banded and sparse by
their estimated costs (:func:`direct_costs`: the band's work n kl (kl + ku)
against the measured factorization of a sparse LU with a fill-reducing
ordering); ``"auto"`` tries ``"reduced"`` where the direct sweep would be long
and keeps it only when its estimated error is below ``tol``, and otherwise
uses :func:`choose_method`.  The measured factorization is made at a frequency
of the sweep inside its band (:func:`resonant.analyses.reduced.probe_frequency`)
and reused, by the reduced model as its first expansion point or by the sparse
sweep at that frequency: choosing costs no factorization beyond those the chosen
method makes (docs/sweeps.md).

Every point gets a condition number (exact, or the lower bound
``||A|| ||z|| / ||F||``); above :data:`SINGULAR_CONDITION` the point is an
exact resonance (singular), above :data:`LOSS_CONDITION` digits are lost.
The callers decide what a singular point means: an error for the stationary
solution, a skipped point for a sweep.

Examples
--------
>>> import numpy as np
>>> from resonant.system import NumericEOM, NumericHarmonic
>>> eom = NumericEOM(("x",), np.eye(1), np.zeros((1, 1)), 4 * np.eye(1),
...                  (NumericHarmonic(1.0, np.array([3.0]), np.array([0.0])),))
>>> batch = eom.batch("omega", np.array([1.0, 3.0]))
>>> result = solve_harmonic(batch, batch.harmonics[0], "dense")
>>> result.Z.round(12).tolist()     # z = L - i N: N = 3/(4 - w^2)
[[-1j], [(-0+0.6j)]]
"""

from __future__ import annotations

import math
import sys
import time
import warnings as _warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any, TypeAlias

import numpy as np

from ..arrays import Matrix
from ..deadline import NO_DEADLINE, Deadline, DeadlineExceeded
from ..errors import AnalysisError
from ..memory import dense_matrix, require
from ..modal import largest_abs
from ..model.options import SOLVE_METHODS, SWEEP_METHODS
from ..system.batch import Batch, BatchHarmonic
from ..system.stability import check_mass_matrix
from . import reduced as reduced_module
from .bands import (
    CALL_OVERHEAD,
    BandOrdering,
    band_lu_seconds,
    band_ordering,
    band_storage,
    dense_bandwidths,
    sparse_lu_floor,
)
from .forward_error import (
    EXTENDED_ABOVE,
    Residuals,
    Sampling,
    dense_residuals,
    relative_error,
)
from .reduced import (
    DAMPED_FRACTION,
    DEFAULT_TOL,
    DampingFraction,
    ScaledLU,
    backward_stable,
    damping_fraction,
    damping_norm,
    probe_frequency,
    reduced_response,
    sparse_lu_options,
    symmetric_scale,
)
from .threads import blas_threads

METHODS = SWEEP_METHODS
#: a point whose condition number exceeds this is an exact resonance
SINGULAR_CONDITION = 1e13
#: condition number that earns a "digits lost" warning
LOSS_CONDITION = 1e8
#: agreement required of modal superposition with a direct solve at the check points
MODAL_TOLERANCE = 1e-10
#: bytes of complex matrices built at once by the modal method
CHUNK_BYTES = 64 * 2**20
#: bytes of the stack of dynamic matrices K - w^2 M + i w C the dense method builds and
#: solves at once: about a core's cache, since building the stack is memory-bound (a stack
#: of 64 MiB made the sweeps of 100 and 300 coordinates 1.5x and 1.4x a loop of zgesv, one
#: of 2 MiB 1.26x and 1.15x; docs/performance.md)
DENSE_STACK_BYTES = 2 * 2**20
#: points of a banded sweep whose solutions are stored at once
BAND_CHUNK = 64
#: exact condition numbers (an SVD per point) up to this many coordinates ...
EXACT_CONDITION = 64
#: ... or, for a single point (the stationary solution), up to this many
EXACT_CONDITION_SINGLE = 1500
#: ``auto`` tries a reduced model only when the direct solves are estimated to take longer
#: than this (seconds) ...
REDUCED_WORTH = 1.0
#: ... for at least this many coordinates and distinct frequencies
REDUCED_MIN_SIZE = 500
REDUCED_MIN_POINTS = 20
#: the reduced model may spend this fraction of the direct solves' estimated time before
#: ``auto`` gives up on it (at least REDUCED_MIN_BUDGET seconds); both are *modelled*
#: seconds, turned into a number of expansion points by :func:`reduced_points`
REDUCED_BUDGET = 0.3
REDUCED_MIN_BUDGET = 1.0
#: modelled cost of one expansion point of the reduced model: this many factorizations
#: (its own, its moments' solves and the validation's) ...
REDUCED_POINT_FACTORS = 2.0
#: ... plus the dense work on the basis (orthogonalization, the residual's QR), seconds
#: per coordinate (about 24 new columns against 100 at 5 GFLOP/s)
REDUCED_POINT_DENSE = 4e-7
#: ... plus its evaluation at every frequency, seconds per frequency and squared basis
#: column (the residual's norms and the reduced solves; measured 1.6e-9 on one thread
#: with 10^4 frequencies, where 14 points of a 20,000-coordinate chain took 17 s)
REDUCED_POINT_EVALUATE = 1.6e-9
#: cost model of the direct solves (seconds): dense LU and banded LAPACK rates (real
#: FLOP/s of the complex factorizations) and the per-point overhead of a Python call
DENSE_RATE = 2e10
#: SuperLU's rate on the FLOPs counted from the structure of its factors (measured here
#: 0.9-2.2 GFLOP/s on 2-D grids of 900 to 40,000 DOF)
SPARSE_RATE = 1.5e9


@dataclass(frozen=True)
class KernelResult:
    """The responses of one harmonic at every point of a batch.

    Attributes
    ----------
    Z : ndarray
        z = L - i N of the kept coordinates, shape (N, kept); NaN at singular points.
    singular : ndarray of bool
        Points where the system is singular (undamped resonance), shape (N,).
    condition : ndarray
        Condition number (exact or a lower bound) per point, shape (N,).
    exact : bool
        Whether ``condition`` holds exact condition numbers.
    """

    Z: np.ndarray
    singular: np.ndarray
    condition: np.ndarray
    exact: bool
    #: the method used ("dense", "banded", "sparse", "modal", "reduced")
    method: str = ""
    #: the estimated largest relative error (reduced), None for the exact methods
    error: float | None = None
    #: the estimated relative forward error of each point's solve, shape (N,), NaN where
    #: singular (:mod:`resonant.analyses.forward_error`); None when not estimated (the
    #: reduced model, which has ``error``, or ``forward_error=False``)
    forward_error: np.ndarray | None = None


def check_batch_mass(batch: Batch, values: np.ndarray | None = None, param: str = "",
                     warnings: list[str] | None = None) -> None:
    """The mass-matrix check at every point of a batch (the one check, as for one point).

    Parameters
    ----------
    batch : Batch
    values : ndarray, optional
        The swept values, to name the failing one.
    param : str
        The swept parameter's name.
    warnings : list of str, optional
        Receives a warning for each point where M is not positive definite.

    Raises
    ------
    AnalysisError
        If M is singular at some point (the message names the value).
    """
    M = batch.M
    names = tuple(batch.coordinates)
    if hasattr(M, "tocsr"):
        rows = np.asarray(abs(M).sum(axis=1)).ravel()
        if (rows == 0).any():
            row = int(np.argmax(rows == 0))
            raise AnalysisError(f"the mass matrix M is singular ({names[row]} has no inertia)")
        return
    stack = M if np.ndim(M) == 3 else M[None]
    if stack.shape[-1] > EXACT_CONDITION_SINGLE:
        return
    for i, Mi in enumerate(stack):
        where = f" at {param} = {values[i]:.6g}" if values is not None and np.ndim(M) == 3 \
            else ""
        try:
            check_mass_matrix(Mi, names)
        except AnalysisError as exc:
            raise AnalysisError(str(exc).replace("the mass matrix M is singular",
                                                 f"the mass matrix M is singular{where}", 1)
                                ) from None
        if warnings is not None and np.allclose(Mi, Mi.T):
            lowest = float(np.linalg.eigvalsh(Mi)[0])
            if lowest < 0:
                warnings.append(f"the mass matrix M is not positive definite{where}: a "
                                "negative mass or inertia; the results there are not physical")


def _is_proportional(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> bool:
    """C M^-1 K = K M^-1 C (Caughey & O'Kelly): the undamped modes diagonalize C."""
    if not np.any(C):
        return True
    minv_k = np.linalg.solve(M, K)
    minv_c = np.linalg.solve(M, C)
    lhs, rhs = C @ minv_k, K @ minv_c
    scale = np.linalg.norm(C) * np.linalg.norm(minv_k) + 1e-300
    return bool(np.linalg.norm(lhs - rhs) <= 1e-9 * scale)


def direct_costs(batch: Batch, omega: np.ndarray | None = None) -> dict[str, float]:
    """Estimated seconds per frequency of the exact direct methods for fixed M, C, K.

    ``dense``: (32/3) n^3 real FLOPs of a complex LU at :data:`DENSE_RATE`;
    ``banded``: 8 n kl (kl + ku + 1) FLOPs of LAPACK ``gbtrf`` at
    :data:`resonant.analyses.bands.BANDED_RATE` (less for narrow bands) plus the band
    storage (:func:`resonant.analyses.bands.band_lu_seconds`);
    ``sparse`` (sparse matrices only): from one *measured* SuperLU factorization
    (fill-reducing ordering, :func:`resonant.analyses.reduced.sparse_lu_options`)
    of A(s) at a frequency s inside the band
    (:func:`resonant.analyses.reduced.probe_frequency`, the middle of the band):
    the FLOPs sum_k 8 |L_k| |U_k| counted from the structure of its factors at
    :data:`SPARSE_RATE`, plus the solve and the assembly; its fill nnz(L + U) is
    returned as ``"sparse_fill"``.  (Not its wall time: on a shared machine that
    varies tenfold.)  The probe is skipped when the band is so narrow that no
    sparse LU can beat it, and when no frequency is known.

    Parameters
    ----------
    batch : Batch
        With ``constant`` matrices.
    omega : ndarray, optional
        The frequencies to be solved (default: those of the batch's harmonics).

    Returns
    -------
    dict
        Method -> seconds per frequency (and ``"sparse_fill"`` when measured).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from resonant.system import NumericEOM, NumericHarmonic
    >>> n = 400
    >>> K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")
    >>> load = NumericHarmonic(1.0, np.zeros(n), np.ones(n))
    >>> eom = NumericEOM(tuple(f"q{i}" for i in range(n)), sp.identity(n, format="csr"),
    ...                  sp.csr_matrix((n, n)), K, (load,))
    >>> costs = direct_costs(eom.batch("omega", np.array([1.0])))
    >>> min(costs, key=costs.get)     # a chain: the band wins
    'banded'
    """
    return _measured_costs(batch, omega)[0]


def _band_costs(batch: Batch) -> dict[str, float]:
    """The modelled costs of the dense and banded LU per frequency (seconds)."""
    n = len(batch.coordinates)
    band = band_ordering(batch.M, batch.C, batch.K)
    lower, upper = band.lower, band.upper
    return {
        "dense": 32.0 / 3.0 * n ** 3 / DENSE_RATE + 16.0 * n * n * 4 / DENSE_RATE
        + CALL_OVERHEAD,
        "banded": band_lu_seconds(n, lower, upper),
    }


def _batch_frequencies(batch: Batch, omega: np.ndarray | None) -> np.ndarray:
    if omega is not None:
        result: np.ndarray = np.abs(np.asarray(omega, dtype=float)).ravel()
        return result
    parts = [np.abs(np.asarray(h.omega, dtype=float)).ravel() for h in batch.harmonics]
    out = np.concatenate(parts) if parts else np.zeros(0)
    return out[np.isfinite(out)]


def _measured_costs(batch: Batch, omega: np.ndarray | None
                    ) -> tuple[dict[str, float], tuple[float, Any] | None]:
    """:func:`direct_costs` and the probe's factorization (s, SuperLU), kept for reuse
    (None when no sparse factorization was made)."""
    costs = _band_costs(batch)
    if not any(hasattr(a, "tocsr") for a in (batch.M, batch.C, batch.K)):
        return costs, None
    import scipy.sparse as sp

    n = len(batch.coordinates)
    M, C, K = (sp.csc_matrix(a) for a in (batch.M, batch.C, batch.K))
    pattern = (abs(K) + abs(M) + abs(C)).tocsc()
    # no sparse LU can do with less than its nonzeros and a call into SuperLU
    floor = sparse_lu_floor(pattern.nnz)
    w = _batch_frequencies(batch, omega)
    if costs["banded"] <= floor or w.size == 0:
        return costs, None
    s = probe_frequency(w)
    try:
        lu = ScaledLU((K - (s * s) * M + (1j * s) * C).tocsc(),
                      _sparse_scale(K, M, C, s), **sparse_lu_options(pattern))
    except RuntimeError:  # exactly singular there: the fill is not known
        return costs, None
    # the factorization's work from its structure: column k of L times row k of U
    # (each access to lu.L or lu.U copies the factor out of SuperLU: 0.4 s at 250,000 DOF)
    L, U = lu.L, lu.U
    lower_counts = np.diff(L.indptr) - 1
    upper_counts = np.bincount(U.indices, minlength=n) - 1
    flops = 8.0 * float(np.dot(lower_counts, upper_counts)) + 8.0 * float(lower_counts.sum())
    fill = float(L.nnz + U.nnz)
    del L, U
    costs["sparse"] = flops / SPARSE_RATE + 2e-8 * fill + 5e-8 * pattern.nnz + 1e-4
    costs["sparse_fill"] = fill
    return costs, (s, lu)


def choose_direct(batch: Batch, omega: np.ndarray | None = None,
                  costs: dict[str, float] | None = None) -> str:
    """The cheapest exact direct method (``dense``, ``banded`` or ``sparse``) by
    :func:`direct_costs` (``costs`` when measured already, else measured with the
    probe in ``omega``'s band, default the batch's frequencies); ``dense`` for
    matrices that change with the parameter."""
    if not batch.constant:
        return "dense"
    if len(batch.coordinates) <= 40:
        return "dense"
    costs = dict(direct_costs(batch, omega) if costs is None else costs)
    costs.pop("sparse_fill", None)
    return min(costs, key=lambda k: costs[k])


def choose_method(batch_or_matrices: Batch, n_points: int = 1,
                  costs: dict[str, float] | None = None,
                  omega: np.ndarray | None = None) -> str:
    """The exact method ``method="auto"`` uses for a sweep (when no reduced model is tried
    or it misses the tolerance).

    Matrices that change with the parameter: ``dense`` (stacked solve).
    Fixed matrices: ``dense`` for n <= 40 (one batched LAPACK call beats a
    Python loop); for sparse matrices the cheaper of ``banded`` and ``sparse``
    by their estimated costs (:func:`direct_costs`: band work against the
    measured sparse LU, not the band alone) where the pattern is narrow or sparse, else
    (after ``modal``, below) the cheapest of the three; ``banded`` for dense arrays whose
    total bandwidth is at most n/10; ``modal`` for dense symmetric,
    proportionally damped systems with n <= 3000 (one eigendecomposition, then
    n^2 per point); ``dense`` otherwise.  ``costs``: :func:`direct_costs` when
    already measured (no second probe); ``omega``: the frequencies to be solved
    (where :func:`direct_costs` probes; default the batch's).
    """
    b = batch_or_matrices
    if not b.constant:
        return "dense"
    n = len(b.coordinates)
    if n <= 40:
        return "dense"
    band = band_ordering(b.M, b.C, b.K)
    lower, upper = band.lower, band.upper
    sparse = any(hasattr(a, "tocsr") for a in (b.M, b.C, b.K))
    if sparse:
        nnz = sum(a.nnz if hasattr(a, "nnz") else np.count_nonzero(a) for a in (b.M, b.C, b.K))
        if lower + upper + 1 <= max(3, n // 10) or nnz < 0.05 * n * n or n > 3000:
            costs = direct_costs(b, omega) if costs is None else costs
            return "sparse" if costs.get("sparse", np.inf) < costs["banded"] else "banded"
    elif lower + upper + 1 <= max(3, n // 10):
        return "banded"
    if n <= 3000:
        M, C, K = (dense_matrix(a) for a in (b.M, b.C, b.K))
        if _symmetric(M) and _symmetric(K) and _symmetric(C) and _is_proportional(M, C, K):
            return "modal"
    if sparse:   # dense enough to consider the dense LU: the cheapest by the cost model
        return choose_direct(b, omega, costs)
    return "dense" if n <= 3000 else "sparse"


def _symmetric(a: np.ndarray) -> bool:
    return bool(np.allclose(a, a.T, rtol=1e-12, atol=1e-12 * (np.abs(a).max() if a.size else 0)))


class _Progress:
    """A plain text progress bar on standard error (no dependency)."""

    def __init__(self, total: int, enabled: bool, label: str = "sweep") -> None:
        self.total, self.enabled, self.label = max(total, 1), enabled, label
        self.last = 0.0
        self.done = 0

    def advance(self, count: int = 1) -> None:
        self.done += count
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self.last < 0.2 and self.done < self.total:
            return
        self.last = now
        frac = min(1.0, self.done / self.total)
        bar = "#" * int(30 * frac)
        sys.stderr.write(f"\r{self.label} [{bar:<30}] {100 * frac:5.1f}%")
        if self.done >= self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


#: the points of a sweep a store's row index picks: one, a range or a boolean mask
_Index: TypeAlias = int | slice | np.ndarray


class _Store:
    """The responses kept from the solves: only the columns ``keep`` (memory stays
    bounded for large models), plus the largest |component| of every full solution."""

    def __init__(self, N: int, keep: np.ndarray, batch: Batch | None = None,
                 bound: np.ndarray | None = None) -> None:
        self.keep = keep
        self.values = np.empty((N, len(keep)), dtype=complex)
        self.largest = np.zeros(N)
        #: the estimated relative forward error of each point (NaN: not estimated)
        self.error = np.full(N, np.nan)
        #: how much the damping acts on the response at each point
        #: (:func:`resonant.analyses.reduced.damping_fraction`; 0 without damping)
        self.damped = np.zeros(N)
        self._damping: Any = None
        #: ||C|| of a damping matrix that is one for every point (computed once), or None
        self._c_norm: float | None = None
        #: ||A|| / ||b|| per point: where the largest |x| times it stays within
        #: SINGULAR_CONDITION, the point is no resonance and needs no damping fraction
        #: (None: every point gets one)
        self._bound = bound
        self._single: DampingFraction | None = None
        if batch is not None:
            C = batch.C
            if hasattr(C, "nnz") and C.nnz or not hasattr(C, "nnz") and np.any(C):
                self._damping = C
                if hasattr(C, "nnz") or np.ndim(C) == 2:
                    self._c_norm = damping_norm(C)

    def _fraction(self, index: _Index, x: np.ndarray) -> None:
        C = self._damping
        if C is None:
            return
        if self._bound is not None and isinstance(index, (int, np.integer)) and (
                self.largest[index] * self._bound[index] <= SINGULAR_CONDITION):
            return   # (one point, well conditioned: the common case, made fast)
        rows = np.atleast_1d(np.arange(len(self.damped))[index])
        X = np.atleast_2d(x)
        if self._bound is not None:
            with np.errstate(invalid="ignore"):
                suspect = ~(self.largest[rows] * self._bound[rows] <= SINGULAR_CONDITION)
            if not suspect.all():
                rows, X = rows[suspect], X[suspect]
            if not rows.size:
                return
        if self._c_norm is None:   # one C for each point (it changes with the parameter)
            self.damped[rows] = damping_fraction(C[rows], X)
        elif rows.size == 1:   # (a stiff structure may need it at every point)
            if self._single is None:
                self._single = DampingFraction(C, self._c_norm)
            self.damped[rows[0]] = self._single(X[0])
        else:
            self.damped[rows] = damping_fraction(C, X, self._c_norm)

    def __setitem__(self, index: _Index, x: np.ndarray | complex) -> None:
        x = np.asarray(x, dtype=complex)
        if x.ndim == 0:
            self.values[index] = x
            self.largest[index] = abs(x)
            return
        self.values[index] = x[..., self.keep]
        with np.errstate(invalid="ignore"):
            self.largest[index] = largest_abs(x)
        self._fraction(index, x)

    def __getitem__(self, index: _Index) -> np.ndarray:
        result: np.ndarray = self.values[index]
        return result


def solve_harmonic(batch: Batch, h: BatchHarmonic, method: str, *,
                   progress: _Progress | None = None, warnings: list[str] | None = None,
                   keep: np.ndarray | None = None, deadline: Deadline = NO_DEADLINE,
                   tol: float = DEFAULT_TOL, exact_condition: bool = True,
                   forward_error: bool = True) -> KernelResult:
    """Complex responses z = L - i N of one harmonic at every point of a batch.

    Parameters
    ----------
    batch : Batch
        The system at N points.
    h : BatchHarmonic
        The harmonic: omega (N,), F_S, F_C.
    method : {"auto", "direct", "dense", "banded", "sparse", "modal", "reduced"}
        See the module docstring; ``direct`` uses :func:`choose_direct`, ``auto``
        a reduced model where it pays and meets ``tol``, else :func:`choose_method`.
    progress : _Progress, optional
    warnings : list of str, optional
        Receives the modal fallback's warning.
    keep : ndarray of int, optional
        The coordinates to keep (default all).
    deadline : Deadline, optional
        Checked between points.
    tol : float
        Relative tolerance of the reduced model (``reduced``, ``auto``).
    exact_condition : bool
        Compute exact condition numbers where they are cheap (small dense systems);
        False keeps the lower bound ||A|| ||z|| / ||F|| (a study, where only the
        singular points matter).
    forward_error : bool
        Estimate each exact solve's relative forward error (one residual and one solve
        with the same factorization per point: :mod:`resonant.analyses.forward_error`);
        False skips it (``KernelResult.forward_error`` is then None).

    Returns
    -------
    KernelResult

    Notes
    -----
    The dense linear algebra runs with the BLAS threads that pay off for its size
    (:func:`resonant.analyses.threads.blas_threads`: one thread for small matrices and
    never more than the idle cores).
    """
    if method not in SOLVE_METHODS:
        raise AnalysisError(f"unknown method '{method}'; choose one of "
                            f"{', '.join(SWEEP_METHODS)}")
    n = len(batch.coordinates)
    if n <= 2:  # closed forms, a 2 x 2 LU at most: no thread limit to set (nor, once per
        # process, 10-30 ms of finding the BLAS libraries for it: a small study's share)
        return _solve_harmonic(batch, h, method, progress=progress, warnings=warnings,
                               keep=keep, deadline=deadline, tol=tol,
                               exact_condition=exact_condition, forward_error=forward_error)
    # the largest dense call: an n x n LU (dense, modal) or the reduced basis' products
    with blas_threads(8.0 * min(float(n) ** 3, float(n) * 1e4)):
        return _solve_harmonic(batch, h, method, progress=progress, warnings=warnings,
                               keep=keep, deadline=deadline, tol=tol,
                               exact_condition=exact_condition, forward_error=forward_error)


def require_kept(N: int, keep: np.ndarray) -> None:
    """Every method returns the kept responses at every point: refused (above the memory
    budget) before any solve."""
    require(16.0 * N * len(keep), f"the responses kept ({N} frequencies x {len(keep)} "
            "coordinates)", "ask for fewer frequencies (points, lines) or fewer "
            "coordinates (the names to report)")


def _solve_harmonic(batch: Batch, h: BatchHarmonic, method: str, *,
                    progress: _Progress | None = None, warnings: list[str] | None = None,
                    keep: np.ndarray | None = None, deadline: Deadline = NO_DEADLINE,
                    tol: float = DEFAULT_TOL, exact_condition: bool = True,
                    forward_error: bool = True) -> KernelResult:
    """:func:`solve_harmonic` within its BLAS thread limit."""
    w = h.omega
    N = w.shape[0]
    n = len(batch.coordinates)
    keep = np.arange(n) if keep is None else keep
    require_kept(N, keep)
    progress = progress or _Progress(N, False)
    warnings = [] if warnings is None else warnings
    rhs = h.complex_load
    if not np.any(rhs):
        progress.advance(N)
        return KernelResult(np.zeros((N, len(keep)), dtype=complex), np.zeros(N, dtype=bool),
                            np.ones(N), False,
                            "dense" if SOLVE_METHODS[method].chooses else method,
                            forward_error=np.zeros(N) if forward_error else None)
    if rhs.ndim == 2 and np.all(rhs == rhs[:1]):
        rhs = rhs[0]
    if method == "reduced":
        if not batch.constant or rhs.ndim == 2:
            raise AnalysisError("method 'reduced' needs M, C, K and the load that do not "
                                "depend on the swept parameter; use 'direct'")
        result = _solve_reduced(batch, w, rhs, keep, tol, deadline, None)
        progress.advance(N)
        if result.error is not None and not result.error <= tol:
            warnings.append(f"the reduced model's estimated error {result.error:.2g} exceeds "
                            f"the tolerance {tol:.2g}; use method 'direct' for an exact solve")
        return result
    probe: dict[float, Any] = {}
    if SOLVE_METHODS[method].chooses:
        # one measured factorization (in the band, at a frequency of w) for the choice,
        # reused by the reduced model or the sparse direct sweep
        costs, probe = _costs_and_probe(batch, w)
        if method == "direct":
            method = choose_direct(batch, w, costs)
        else:
            attempt = _try_reduced(batch, w, rhs, keep, tol, deadline, costs, probe)
            if attempt is not None:
                progress.advance(N)
                return attempt
            method = choose_method(batch, N, costs=costs, omega=w)
    exact = exact_condition and method == "dense" and (
        n <= EXACT_CONDITION or (N == 1 and n <= EXACT_CONDITION_SINGLE))
    b_norm = largest_abs(rhs) * np.ones(N)
    # ||A|| / ||rhs||: times the largest |z|, a lower bound of the condition number
    norms = [_norm_inf(a) for a in (batch.K, batch.M, batch.C)]
    with np.errstate(all="ignore"):
        scale = (norms[0] + w**2 * norms[1] + w * norms[2]) / np.where(b_norm > 0, b_norm,
                                                                       np.inf)
    bound = None if exact else scale
    store = _Store(N, keep, batch, bound)
    errors = Sampling(store.error, scale) if forward_error else None
    condition = np.ones(N)
    if method == "dense":
        singular = _solve_dense(batch, w, rhs, progress, store, deadline,
                                condition if exact else None, errors)
    elif method == "banded":
        singular = _solve_banded(batch, w, rhs, progress, store, deadline, errors)
    elif method == "sparse":
        singular = _solve_sparse(batch, w, rhs, progress, store, deadline, probe, errors)
    else:
        singular = _solve_modal(batch, w, rhs, progress, warnings, store, deadline, errors)
    Z = store.values
    if bound is not None:
        # a lower bound of the condition number: ||A|| ||Z|| / ||rhs|| (exact resonance: huge)
        with np.errstate(all="ignore"):
            condition = bound * store.largest
    singular |= ~np.isfinite(store.largest) | (~(condition <= SINGULAR_CONDITION)
                                                & (store.damped < DAMPED_FRACTION))
    singular &= b_norm > 0
    Z[singular] = np.nan
    if errors is not None:
        errors.errors[singular] = np.nan
    return KernelResult(Z, singular, np.asarray(condition, dtype=float), exact, method,
                        forward_error=None if errors is None else errors.errors)


def reduced_budget(batch: Batch, w: np.ndarray, rhs: np.ndarray,
                   probe: dict[float, Any] | None = None) -> float | None:
    """Seconds a reduced model may take in ``auto``, or None when it is not worth trying:
    fixed sparse (or very large) matrices and load, many distinct frequencies, and
    direct solves estimated at more than :data:`REDUCED_WORTH` seconds.

    Parameters
    ----------
    batch : Batch
    w : ndarray
        The frequencies to solve at.
    rhs : ndarray
        The load F_C - i F_S, (n,) or (N, n).
    probe : dict, optional
        Receives the cost probe's factorization {s: LU} (for the ``factorizations`` of
        :func:`resonant.analyses.reduced.reduced_model`).

    Returns
    -------
    float or None
    """
    costs, made = _costs_and_probe(batch, w)
    if probe is not None:
        probe.update(made)
    return _reduced_budget(batch, w, rhs, costs)


def _costs_and_probe(batch: Batch, w: np.ndarray
                     ) -> tuple[dict[str, float] | None, dict[float, Any]]:
    """:func:`direct_costs` and the probe's factorization {s: LU} where ``auto`` or
    ``direct`` consult the costs: fixed matrices of more than 40 coordinates, sparse
    (or beyond 3000 coordinates); (None, {}) elsewhere."""
    n = len(batch.coordinates)
    sparse = any(hasattr(a, "tocsr") for a in (batch.M, batch.C, batch.K))
    if not batch.constant or n <= 40 or not (sparse or n > 3000):
        return None, {}
    costs, probe = _measured_costs(batch, w)
    return costs, dict([probe]) if probe is not None else {}


def _try_reduced(batch: Batch, w: np.ndarray, rhs: np.ndarray, keep: np.ndarray,
                 tol: float, deadline: Deadline, costs: dict[str, float] | None,
                 probe: dict[float, Any]) -> KernelResult | None:
    """``auto``'s reduced model, when worth trying (:func:`_reduced_budget`), if it meets
    ``tol``; None otherwise.  It takes the probe's factorization as an expansion point."""
    budget = _reduced_budget(batch, w, rhs, costs)
    if budget is None or costs is None:
        return None
    points = reduced_points(budget, costs, len(batch.coordinates), len(w))
    try:
        attempt = _solve_reduced(batch, w, rhs, keep, tol, deadline, None, probe, points)
    except DeadlineExceeded:
        raise
    except AnalysisError:  # no basis (A singular wherever tried): solve directly
        return None
    return attempt if attempt.error is not None and attempt.error <= tol else None


def _reduced_budget(batch: Batch, w: np.ndarray, rhs: np.ndarray,
                    costs: dict[str, float] | None) -> float | None:
    """Seconds a reduced model may take in ``auto``, or None when it is not worth trying:
    it needs fixed sparse (or very large) matrices and load, at least
    :data:`REDUCED_MIN_SIZE` coordinates and :data:`REDUCED_MIN_POINTS` distinct
    frequencies, and direct solves estimated (``costs``) at more than
    :data:`REDUCED_WORTH` seconds."""
    n = len(batch.coordinates)
    if costs is None or rhs.ndim == 2 or n < REDUCED_MIN_SIZE:
        return None
    if len(np.unique(w)) < REDUCED_MIN_POINTS:
        return None
    direct = min(v for k, v in costs.items() if k != "sparse_fill") * len(w)
    if direct < REDUCED_WORTH:
        return None
    return max(REDUCED_MIN_BUDGET, REDUCED_BUDGET * direct)


def reduced_points(budget: float, costs: dict[str, float], n: int, frequencies: int = 0
                   ) -> int:
    """The expansion points ``auto``'s reduced model may use: as many as the modelled
    seconds ``budget`` pay for, point k costing :data:`REDUCED_POINT_FACTORS`
    factorizations by :func:`direct_costs`, the basis' dense work
    :data:`REDUCED_POINT_DENSE` n and its evaluation at the ``frequencies``
    (:data:`REDUCED_POINT_EVALUATE` N r^2 on the basis of r = 24 k columns it then
    has); between ``INITIAL_POINTS + 1`` and ``MAX_POINTS``.  No wall-clock time
    enters: the choice is the same on a busy machine.

    Examples
    --------
    >>> reduced_points(1.0, {"sparse": 0.01, "banded": 0.1}, 10_000)
    40
    >>> reduced_points(1.0, {"sparse": 0.01, "banded": 0.1}, 10_000, frequencies=10**5)
    4
    >>> reduced_points(0.0, {"sparse": 0.01, "banded": 0.1}, 10_000)
    4
    """
    factor = min(v for k, v in costs.items() if k != "sparse_fill")
    point = REDUCED_POINT_FACTORS * factor + REDUCED_POINT_DENSE * n
    columns = 2 * reduced_module.MOMENTS
    spent, count = 0.0, 0
    while count < reduced_module.MAX_POINTS:
        spent += point + REDUCED_POINT_EVALUATE * frequencies * (columns * (count + 1)) ** 2
        if spent > budget:
            break
        count += 1
    return int(min(max(count, reduced_module.INITIAL_POINTS + 1), reduced_module.MAX_POINTS))


def _solve_reduced(batch: Batch, w: np.ndarray, rhs: np.ndarray, keep: np.ndarray,
                   tol: float, deadline: Deadline, budget: float | None,
                   probe: dict[float, Any] | None = None,
                   max_points: int | None = None) -> KernelResult:
    """The reduced model (:func:`resonant.analyses.reduced.reduced_response`) as a
    KernelResult; condition numbers are the lower bound ||A|| ||z||_2 / ||b||.
    ``probe``: factorizations {s: LU} of A(s) made before, taken (emptied) by it."""
    red = reduced_response(batch.M, batch.C, batch.K, rhs, w, tol=tol, keep=keep,
                           deadline=deadline, budget=budget, factorizations=probe,
                           max_points=max_points)
    norms = [_norm_inf(a) for a in (batch.K, batch.M, batch.C)]
    a_norm = norms[0] + w**2 * norms[1] + w * norms[2]
    b_norm = float(np.abs(rhs).max())
    with np.errstate(all="ignore"):
        condition = a_norm * red.norms / b_norm
    # the reduced model judged its undamped resonances (condition and damping fraction)
    singular = red.singular | ~np.isfinite(condition)
    Z = np.array(red.Z)
    Z[singular] = np.nan
    return KernelResult(Z, singular, np.asarray(condition, dtype=float), False, "reduced",
                        red.estimated_error)


def equilibration(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row and column scale factors (powers of 2) giving ``row A col`` entries of order 1.

    As LAPACK's ``xGEEQU``: each row scaled by its largest entry, then each column;
    powers of two make the scaling exact, so only the conditioning changes.  Works
    on a stack of matrices (..., n, n).

    Parameters
    ----------
    A : ndarray
        (..., n, n).

    Returns
    -------
    row, col : ndarray
        (..., n) each.

    Examples
    --------
    >>> A = np.array([[1e6, 1e3], [1e3, 4.0]])
    >>> row, col = equilibration(A)
    >>> scaled = row[:, None] * A * col[None, :]
    >>> bool(np.all((0.5 <= np.abs(scaled).max(axis=1)) & (np.abs(scaled).max(axis=1) <= 2)))
    True
    >>> float(np.linalg.cond(A)) > 1e5, float(np.linalg.cond(scaled)) < 10
    (True, True)
    """
    def power_of_two_inverse(largest: np.ndarray) -> np.ndarray:
        safe = np.where(largest > 0, largest, 1.0)  # an all-zero row or column stays
        # clipped: a subnormal entry (1e-320) would ask for 2^1063, which overflows
        return np.exp2(-np.clip(np.round(np.log2(safe)), -1000.0, 1000.0))

    magnitude = np.abs(A)
    row = power_of_two_inverse(magnitude.max(axis=-1, initial=0.0))
    col = power_of_two_inverse((row[..., :, None] * magnitude).max(axis=-2, initial=0.0))
    return row, col


def _norm_inf(a: Matrix) -> Any:
    """The infinity norm of a matrix, or of each of a stack (N, n, n) of them."""
    if hasattr(a, "tocsr") and not isinstance(a, np.ndarray):  # sparse
        return float(abs(a).sum(axis=1).max()) if a.nnz else 0.0
    if a.ndim == 3 and a.shape[-1] == 2:  # a stack of 2 x 2: without short reductions
        row = np.abs(a[:, :, 0]) + np.abs(a[:, :, 1])
        return np.maximum(row[:, 0], row[:, 1])
    return np.abs(a).sum(axis=-1).max(axis=-1)


def _solve_dense(batch: Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                 Z: _Store, deadline: Deadline, condition: np.ndarray | None,
                 errors: Sampling | None = None) -> np.ndarray:
    N, n = w.shape[0], len(batch.coordinates)
    M, C, K = (dense_matrix(a, None) for a in (batch.M, batch.C, batch.K))
    chunk = max(1, int(DENSE_STACK_BYTES // (16 * n * n)))
    singular = np.zeros(N, dtype=bool)
    # no damping: A = K - w^2 M real, made complex by the solve (not where the exact
    # condition numbers are wanted: a real SVD would round differently)
    undamped = condition is None and C.ndim == 2 and not C.any()
    for start in range(0, N, chunk):
        sl = slice(start, min(N, start + chunk))

        def pick(a: np.ndarray, sl: slice = sl) -> np.ndarray:
            return a[sl] if a.ndim == 3 else a
        deadline.check("while solving the harmonic systems", analysis=True)
        with np.errstate(all="ignore"):  # an overflow gives inf, caught as not finite
            A = _dynamic_matrix(pick(K), pick(M), pick(C), w[sl], undamped)
        b = np.broadcast_to(rhs[sl] if rhs.ndim == 2 else rhs, (A.shape[0], n))
        b_model = b
        # an overflow (inf) gives NaN in the solution: marked singular by the caller
        finite = np.ones(A.shape[0], dtype=bool)
        if condition is not None and not np.isfinite(A).all():
            finite = np.isfinite(A).all(axis=(-2, -1))
            A = np.where(finite[:, None, None], A, 0.0)  # cond() of inf raises
        col = None
        if condition is not None:
            # Equilibrate before solving and judging the condition: in badly scaled units
            # (mm with GPa, translations beside rotations) the raw condition number reflects
            # the units, not the physics, and would warn of digits that are not lost.
            row, col = equilibration(A)
            A = row[..., :, None] * A * col[..., None, :]
            b = row * b
        points = start + np.arange(A.shape[0])
        # the closed form (no condition number wanted); LAPACK where it is not trusted
        closed = condition is None and n <= 2
        X = (_closed_form_or_lapack if closed else _lapack_solve)(A, b, singular, points)
        if col is not None:
            X = col * X
        X[~finite] = np.nan
        Z[sl] = X
        if errors is not None:   # one refinement step's correction, not applied
            def correct(R: np.ndarray, at: np.ndarray, A: np.ndarray = A,
                        points: np.ndarray = points, closed: bool = closed) -> np.ndarray:
                # (the rows picked by the sampling: their LU again, a fraction of the sweep)
                solver = _closed_form_or_lapack if closed else _lapack_solve
                return solver(A[at], R, np.zeros(N, dtype=bool), points[at])

            def estimate(at: np.ndarray, sl: slice = sl, X: np.ndarray = X,
                         b: np.ndarray = b_model,
                         correct: Callable[[np.ndarray, np.ndarray], np.ndarray] = correct,
                         row: np.ndarray | None = row if col is not None else None,
                         col: np.ndarray | None = col) -> np.ndarray:
                return _dense_errors(pick(K, sl), pick(M, sl), pick(C, sl), w[sl], X, b,
                                     correct, row, col, at)
            errors.chunk(points, Z.largest[sl], estimate)
        if condition is not None:  # exact condition numbers, where they are cheap
            with np.errstate(all="ignore"):
                try:
                    condition[sl] = np.where(finite, np.linalg.cond(A), np.inf)
                except np.linalg.LinAlgError:  # the SVD failed: numbers beyond doubles
                    condition[sl] = np.inf
        progress.advance(A.shape[0])
    return singular


def _closed_form_or_lapack(A: np.ndarray, b: np.ndarray, singular: np.ndarray,
                           points: np.ndarray) -> np.ndarray:
    """:func:`closed_form_solve`, with LAPACK at the points it does not trust."""
    X, hard = closed_form_solve(A, b)
    if hard.any():
        where = np.flatnonzero(hard)
        X[where] = _lapack_solve(A[where], b[where], singular, points[where])
    return X


def _dense_errors(K: np.ndarray, M: np.ndarray, C: np.ndarray, w: np.ndarray, X: np.ndarray,
                  b: np.ndarray, correct: Callable[[np.ndarray, np.ndarray], np.ndarray],
                  row: np.ndarray | None, col: np.ndarray | None, at: np.ndarray
                  ) -> np.ndarray:
    """The estimated relative forward errors of the rows ``at`` of a chunk's solves X
    (:mod:`.forward_error`): residuals from K, M, C (one matrix or a stack each) in double
    precision, and in extended precision at the points where that estimate exceeds
    :data:`~resonant.analyses.forward_error.EXTENDED_ABOVE`; the corrections by
    ``correct`` (the chunk's matrices, in its equilibrated variables: ``row`` scales the
    residual, ``col`` the correction)."""
    if not at.size:
        return np.zeros(0)

    def estimate(R: np.ndarray, at: np.ndarray) -> np.ndarray:
        if row is not None:
            R = row[at] * R
        D = correct(R, at)
        if col is not None:
            D = col[at] * D
        return relative_error(D, X[at])

    def residuals(at: np.ndarray, extended: bool) -> np.ndarray:
        def pick(a: np.ndarray) -> np.ndarray:
            return a[at] if a.ndim == 3 else a
        return dense_residuals(pick(K), pick(M), pick(C), w[at], X[at], b[at], extended)

    with np.errstate(all="ignore"):
        errors = estimate(residuals(at, False), at)
        errors[~np.isfinite(X[at]).all(axis=-1)] = np.nan
        suspect = np.flatnonzero(errors > EXTENDED_ABOVE)
        if suspect.size:
            errors[suspect] = estimate(residuals(at[suspect], True), at[suspect])
    return errors


def _dynamic_matrix(K: np.ndarray, M: np.ndarray, C: np.ndarray, w: np.ndarray,
                    undamped: bool) -> np.ndarray:
    """K - w^2 M + i w C at the frequencies w, (N, n, n); real when ``undamped``.  For one
    or two coordinates entry by entry: the same numbers as by broadcasting, several times
    faster on a stack of small matrices."""
    N, n = len(w), K.shape[-1]
    if n > 2:
        ww = w[:, None, None]
        if undamped:
            result: np.ndarray = K - ww**2 * M
            return result
        # written into its real and imaginary parts: no complex temporaries (the stack's
        # memory traffic, not LAPACK, was the cost of small matrices); the numbers of
        # K - w^2 M + 1j w C, signed zeros too (+ 0.0: the complex product's zeros; they
        # differ only where K is -0.0, M and w C zero and C negative)
        result = np.empty(np.broadcast_shapes(ww.shape, K.shape, M.shape, C.shape),
                          dtype=complex)
        np.subtract(K, ww**2 * M, out=result.real)
        np.multiply(ww, C, out=result.imag)
        result.view(float)[...] += 0.0
        return result
    A = np.empty((N, n, n), dtype=float if undamped else complex)
    w2 = w**2
    for i in range(n):
        for j in range(n):
            entry = K[..., i, j] - w2 * M[..., i, j]
            A[:, i, j] = entry if undamped else entry + 1j * w * C[..., i, j]
    return A


def _lapack_solve(A: np.ndarray, b: np.ndarray, singular: np.ndarray, points: np.ndarray
                  ) -> np.ndarray:
    """Batched LAPACK solves of A x = b; an exactly singular point gets NaN and is marked
    in ``singular`` (at its index of ``points``)."""
    try:
        with np.errstate(all="ignore"):
            return np.linalg.solve(A, b[..., None])[..., 0]
    except np.linalg.LinAlgError:  # an exactly singular point: solve point by point
        X = np.empty(b.shape, dtype=complex)
        for i in range(A.shape[0]):
            try:
                X[i] = np.linalg.solve(A[i], b[i])
            except np.linalg.LinAlgError:
                X[i] = np.nan
                singular[points[i]] = True
        return X


#: the closed form of a 2 x 2 solve is trusted where |det A| is at least this fraction of
#: |a11 a22| + |a12 a21| (the determinant's own rounding error relative to it is then below
#: 1e-10); other points go to LAPACK
CLOSED_FORM_DETERMINANT = 1e-6
#: largest entries of A and b in this range at every point: the closed form needs no scaling
SAFE_RANGE = (2.0**-400, 2.0**400)


def closed_form_solve(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Stacked 1 x 1 or 2 x 2 systems A x = b (A real or complex, b complex) in closed
    form.

    Cramer's rule is forward stable for n = 2 (Higham, *Accuracy and Stability of
    Numerical Algorithms*, 2nd ed., sec. 1.10.1): its error is of the order of
    cond(A) u, as for LU with partial pivoting.  Where the entries of A or b are
    beyond 2^+-400 (:data:`SAFE_RANGE`), each point's A and b are scaled by powers of
    two to entries of order 1 first (exact), so that the products neither overflow nor
    underflow.  Points that are not trusted -- a determinant small against the
    products it comes from (:data:`CLOSED_FORM_DETERMINANT`), or a matrix or load that
    is not finite -- are returned in a mask for a LAPACK solve.

    Parameters
    ----------
    A : ndarray
        (N, n, n) real or complex, n = 1 or 2.
    b : ndarray
        (N, n).

    Returns
    -------
    x : ndarray
        (N, n) complex; not meaningful where ``hard``.
    hard : ndarray
        (N,) bool: the points to solve otherwise.

    Examples
    --------
    >>> A = np.array([[[2.0, 1.0], [1.0, 3.0]], [[1.0, 1.0], [1.0, 1.0]]], dtype=complex)
    >>> x, hard = closed_form_solve(A, np.array([[3.0, 5.0], [1.0, 2.0]]))
    >>> x[0].real.round(12).tolist(), hard.tolist()
    ([0.8, 1.4], [False, True])
    """
    n = A.shape[-1]
    with np.errstate(all="ignore"):
        if n == 1:
            a = A[:, 0, 0]
            x = (b[:, 0] / a)[:, None]
            return x, ~(np.isfinite(a) & (a != 0) & np.isfinite(x[:, 0]))
        # scale factors 2^-e with e the binary exponent of the largest entry, kept
        # normal (a subnormal matrix is scaled only up to 2^1021)
        N = A.shape[0]
        real = not np.iscomplexobj(A)
        A = np.ascontiguousarray(A, dtype=float if real else complex).reshape(N, 4)
        b = np.ascontiguousarray(b, dtype=complex).view(float)  # (N, 4): re, im of b1, b2
        size_a, size_b = largest_abs(A if real else A.view(float)), largest_abs(b)
        # entries within 2^+-400 of 1 everywhere (the usual case): the products can
        # neither overflow nor underflow against them, and no scaling is needed
        scaled = not all((s.min(initial=1.0) >= SAFE_RANGE[0]) and
                         (s.max(initial=1.0) <= SAFE_RANGE[1]) for s in (size_a, size_b))
        if scaled:
            e_a = np.clip(np.frexp(size_a)[1], -1021, 1021)
            e_b = np.clip(np.frexp(size_b)[1], -1021, 1021)
            A = A * np.ldexp(1.0, -e_a)[:, None]
            b = b * np.ldexp(1.0, -e_b)[:, None]
        a11, a12, a21, a22 = A[:, 0], A[:, 1], A[:, 2], A[:, 3]
        d1, d2 = a11 * a22, a12 * a21
        det = d1 - d2
        x = np.empty((N, 2), dtype=complex)
        flat = x.view(float)
        if real:  # a damping-free system: real arithmetic on the re, im parts of b
            # column by column: broadcasting over rows of two is several times slower
            for j in range(2):
                b1, b2 = b[:, j], b[:, 2 + j]
                np.divide(a22 * b1 - a12 * b2, det, out=flat[:, j])
                np.divide(a11 * b2 - a21 * b1, det, out=flat[:, 2 + j])
        else:
            b1, b2 = b.view(complex)[:, 0], b.view(complex)[:, 1]
            x[:, 0] = (a22 * b1 - a12 * b2) / det
            x[:, 1] = (a11 * b2 - a21 * b1) / det
        # back to the units of A and b: x = x' 2^(e_b - e_a), exactly (as long as the
        # factor is a normal number; ldexp otherwise)
        if scaled:
            shift = e_b - e_a
            if np.abs(shift).max(initial=0) <= 1000:
                flat *= np.ldexp(1.0, shift)[:, None]
            else:
                flat[:] = np.ldexp(flat, shift[:, None])
        trusted = np.abs(det) >= CLOSED_FORM_DETERMINANT * (np.abs(d1) + np.abs(d2))
        hard = ~(trusted & (det != 0) & np.isfinite(det) & np.isfinite(x[:, 0])
                 & np.isfinite(x[:, 1]))
    return x, hard


def _solve_banded(batch: Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                  Z: _Store, deadline: Deadline, errors: Sampling | None = None
                  ) -> np.ndarray:
    from scipy.linalg import lapack

    N = w.shape[0]
    band = band_ordering(batch.M, batch.C, batch.K)
    lower, upper, order, position = band.lower, band.upper, band.order, band.position
    singular = np.zeros(N, dtype=bool)
    varying_rhs = rhs.ndim == 2
    residuals = Residuals(batch.K, batch.M, batch.C) if errors is not None else None
    band_rhs = rhs if order is None else rhs[..., order]
    offset = 0
    if lower == upper == 1:  # tridiagonal: LAPACK gtsv (partial pivoting)
        storage = [band_storage(a, 1, 3, 0, position) for a in (batch.M, batch.C, batch.K)]
        gtsv = lapack.get_lapack_funcs("gtsv", (np.zeros(1, complex),))

        def solve(ab: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, int]:
            _, _, _, x, info = gtsv(ab[2, :-1], ab[1], ab[0, 1:], b)
            return x, info

        def correction(ab: np.ndarray, r: np.ndarray) -> np.ndarray:
            return solve(ab, r)[0]   # (no more than applying a tridiagonal LU again)
    else:
        rows = 2 * lower + upper + 1  # gbsv needs lower extra rows for the LU fill-in
        offset = lower
        storage = [band_storage(a, upper, rows, lower, position)
                   for a in (batch.M, batch.C, batch.K)]
        gbsv = lapack.get_lapack_funcs("gbsv", (np.zeros(1, complex),))
        gbtrs = lapack.get_lapack_funcs("gbtrs", (np.zeros(1, complex),))
        factors: list[Any] = []

        def solve(ab: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, int]:
            lub, piv, x, info = gbsv(lower, upper, ab, b, overwrite_ab=True)
            factors[:] = [lub, piv]
            return x, info

        def correction(ab: np.ndarray, r: np.ndarray) -> np.ndarray:
            d: np.ndarray = gbtrs(factors[0], lower, upper, r, factors[1])[0]
            return d
    Mb, Cb, Kb = storage

    def point(i: int) -> tuple[np.ndarray, np.ndarray, int]:
        """A at point i (its factors, for gbsv), the solution (the band's order), info."""
        wi = w[i]
        A = Kb - (wi * wi) * Mb + (1j * wi) * Cb
        x, info = solve(A, band_rhs[i] if varying_rhs else band_rhs)
        return A, x, info

    def error(i: int, A: np.ndarray, x: np.ndarray) -> float:
        # the residual in the band's order from the storage of M, C, K; extended: K, M, C
        assert residuals is not None
        wi, b = w[i], band_rhs[i] if varying_rhs else band_rhs

        def extended() -> np.ndarray:
            r = residuals.extended(wi, x if order is None else x[position],
                                   rhs[i] if varying_rhs else rhs)
            return r if order is None else r[order]
        return _point_error(lambda: _band_residual(storage, offset, lower, upper, wi, x, b),
                            extended, x, partial(correction, A))

    def revisit(j: int) -> float:   # a point skipped before: solved again, estimated
        A, x, info = point(j)
        return error(j, A, x) if info == 0 else math.nan

    _band_points(N, len(batch.coordinates), point, position if order is not None else None,
                 Z, singular, errors, error, revisit, progress, deadline)
    return singular


def _band_points(N: int, n: int, point: Callable[[int], tuple[np.ndarray, np.ndarray, int]],
                 position: np.ndarray | None, Z: _Store, singular: np.ndarray,
                 errors: Sampling | None, error: Callable[..., float],
                 revisit: Callable[[int], float], progress: _Progress,
                 deadline: Deadline) -> None:
    """Solve the band at every point (``point(i)``: A, x, info) and keep the solutions,
    in the coordinates' order (``x[position]``), 64 points at a time: storing each point
    alone (its largest component, its damping fraction) cost more than a small band's
    LAPACK solve."""
    chunk = np.empty((min(N, BAND_CHUNK), n), dtype=complex)
    for i in range(N):
        A, x, info = point(i)
        row = chunk[i % BAND_CHUNK]
        if info != 0:
            singular[i] = True
            row[:] = np.nan
        else:
            row[:] = x if position is None else x[position]   # (x[position[k]]: coordinate k)
            if errors is not None:
                errors.point(i, float(np.abs(row).max()), partial(error, i, A, x), revisit)
        if i % BAND_CHUNK == BAND_CHUNK - 1 or i == N - 1:
            start = i - i % BAND_CHUNK
            Z[start:i + 1] = chunk[:i + 1 - start]
            progress.advance(i + 1 - start)
            deadline.check("while solving the harmonic systems", analysis=True)


def _band_residual(storage: list[np.ndarray], offset: int, lower: int, upper: int,
                   w: float, x: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``b - (K - w^2 M + i w C) x`` from the LAPACK band storages of M, C and K
    (:func:`resonant.analyses.bands.band_storage`; x and b in the band's order), in double
    precision: each diagonal's products, summed."""
    n = x.shape[0]
    products = []
    with np.errstate(all="ignore"):
        for ab in storage:
            y = np.zeros(n, dtype=complex)
            for d in range(-upper, lower + 1):   # the diagonal i - j = d
                lo, hi = max(0, -d), min(n, n - d)
                y[lo + d:hi + d] += ab[offset + upper + d, lo:hi] * x[lo:hi]
            products.append(y)
        Mx, Cx, Kx = products
        residual = b - Kx
        residual += (w * w) * Mx
        residual -= (1j * w) * Cx
    return residual


def _point_error(double: Callable[[], np.ndarray], extended: Callable[[], np.ndarray],
                 x: np.ndarray, correct: Callable[[np.ndarray], np.ndarray]) -> float:
    """One point's estimated relative forward error (:mod:`.forward_error`): the
    correction ``correct(r)`` (the point's factorization) of its residual in double
    precision, and in extended precision where that exceeds
    :data:`~resonant.analyses.forward_error.EXTENDED_ABOVE`."""
    with np.errstate(all="ignore"):
        error = float(relative_error(correct(double()), x))
        if error > EXTENDED_ABOVE:
            error = float(relative_error(correct(extended()), x))
    return error


def _solve_sparse(batch: Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                  Z: _Store, deadline: Deadline, probe: dict[float, Any] | None = None,
                  errors: Sampling | None = None) -> np.ndarray:
    """A SuperLU per frequency (``probe``: factorizations made before, by frequency,
    taken where a frequency is one of them)."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    N = w.shape[0]
    M, C, K = (sp.csc_matrix(a) for a in (batch.M, batch.C, batch.K))
    options = sparse_lu_options(abs(K) + abs(M) + abs(C))
    row_norms = [_norm_inf(a) for a in (K, M, C)]
    singular = np.zeros(N, dtype=bool)
    residuals = Residuals(K, M, C) if errors is not None else None

    def point(i: int) -> tuple[Any, np.ndarray, np.ndarray]:
        """The LU at point i, the solution and the load (RuntimeError: singular)."""
        wi = w[i]
        A = (K - (wi * wi) * M + (1j * wi) * C).tocsc()
        b = np.asarray(rhs[i] if rhs.ndim == 2 else rhs, dtype=complex)
        lu = probe.pop(float(wi), None) if probe else None
        if lu is None:
            lu = ScaledLU(A, _sparse_scale(K, M, C, wi), **options)
        x = lu.solve(b)
        if "options" in options and not backward_stable(
                A, x, b, row_norms[0] + wi * wi * row_norms[1] + wi * row_norms[2]):
            lu = splu(A)  # threshold pivoting grew too much: partial pivoting
            x = lu.solve(b)
        return lu, x, b

    def revisit(j: int) -> float:   # a point skipped before: factored again, estimated
        assert residuals is not None
        try:
            lu, x, b = point(j)
        except RuntimeError:
            return math.nan
        return _sparse_error(residuals, w[j], x, b, lu.solve)

    for i in range(N):
        try:
            lu, x, b = point(i)
            Z[i] = x
            if errors is not None and residuals is not None:
                errors.point(i, float(Z.largest[i]),
                             partial(_sparse_error, residuals, w[i], x, b, lu.solve), revisit)
        except RuntimeError:  # "Factor is exactly singular"
            Z[i] = np.nan
            singular[i] = True
        progress.advance()
        deadline.check("while solving the harmonic systems", analysis=True)
    return singular


def _sparse_error(residuals: Residuals, w: float, x: np.ndarray, b: np.ndarray,
                  solve: Callable[[np.ndarray], np.ndarray]) -> float:
    """A sparse point's estimate: the residuals from K, M, C, the correction by its LU's
    ``solve``."""
    return _point_error(partial(residuals.double, w, x, b), partial(residuals.extended, w, x, b),
                        x, solve)


def _sparse_scale(K: Matrix, M: Matrix, C: Matrix, s: float) -> np.ndarray:
    """The symmetric scaling of A(s) for its sparse LU (:class:`ScaledLU`)."""
    return symmetric_scale(np.abs(K.diagonal()) + s * s * np.abs(M.diagonal())
                           + abs(s) * np.abs(C.diagonal()))


def _solve_modal(batch: Batch, w: np.ndarray, rhs: np.ndarray, progress: _Progress,
                 warnings: list[str], store: _Store, deadline: Deadline,
                 errors: Sampling | None = None) -> np.ndarray:
    """Superposition of all undamped modes (exact for proportional damping), checked."""
    import scipy.linalg

    M, C, K = (dense_matrix(a).astype(float) for a in (batch.M, batch.C, batch.K))
    if not (_symmetric(M) and _symmetric(K) and _symmetric(C)):
        raise AnalysisError("method 'modal' needs symmetric M, C and K (no gyroscopic or "
                            "circulatory terms); use 'dense', 'banded' or 'sparse'")
    try:
        lam, phi = scipy.linalg.eigh(K, M)
    except np.linalg.LinAlgError:
        raise AnalysisError("method 'modal' needs a positive definite mass matrix") from None
    modal_c = phi.T @ C @ phi
    diag_c = np.diag(modal_c).copy()
    off = modal_c - np.diag(diag_c)
    if np.abs(off).max(initial=0.0) > 1e-9 * max(np.abs(diag_c).max(initial=0.0), 1e-300):
        raise AnalysisError("method 'modal' needs proportional damping (C M^-1 K = K M^-1 C): "
                            "the undamped modes do not decouple C; use 'dense', 'banded' or "
                            "'sparse'")
    N, n = w.shape[0], len(batch.coordinates)
    forces = (rhs @ phi) if rhs.ndim == 2 else np.broadcast_to(rhs @ phi, (N, n))

    def modal(sl: slice, loads: np.ndarray | None = None) -> np.ndarray:
        ww = w[sl, None]
        with np.errstate(all="ignore"):
            modal_loads = forces[sl] if loads is None else loads @ phi
            result: np.ndarray = (modal_loads / (lam - ww**2 + 1j * ww * diag_c)) @ phi.T
            return result

    chunk = max(1, int(CHUNK_BYTES // (16 * n)))
    for start in range(0, N, chunk):
        sl = slice(start, min(N, start + chunk))
        X = modal(sl)
        if errors is not None:   # the residual from M, C, K, its modal correction
            ww = w[sl, None]
            with np.errstate(all="ignore"):
                R = (rhs[sl] if rhs.ndim == 2 else rhs) - (
                    X @ K.T - ww**2 * (X @ M.T) + 1j * ww * (X @ C.T))
            errors.errors[sl] = relative_error(modal(sl, R), X)
        store[sl] = X
        progress.advance(sl.stop - sl.start)
        deadline.check("while summing the modes", analysis=True)
    singular = ~np.isfinite(store.largest)
    # check: the same as a direct solve at the largest response and both ends
    check = sorted({0, N - 1, int(np.argmax(np.where(singular, -np.inf, store.largest)))})
    for i in check:
        if singular[i]:
            continue
        b = rhs[i] if rhs.ndim == 2 else rhs
        try:
            direct = np.linalg.solve(K - w[i]**2 * M + 1j * w[i] * C, b)
        except np.linalg.LinAlgError:
            continue
        error = np.abs(modal(slice(i, i + 1))[0] - direct).max() / max(
            np.abs(direct).max(), 1e-300)
        if error > MODAL_TOLERANCE:
            warnings.append(f"modal superposition differs from the direct solve by {error:.2g} "
                            f"at {w[i]:.6g} rad/s; solved directly instead")
            band = band_ordering(M, C, K)
            banded = band.lower + band.upper + 1 <= max(3, n // 10)
            if banded:
                return _solve_banded(batch, w, rhs, _Progress(N, False), store, deadline,
                                     errors)
            return _solve_dense(batch, w, rhs, _Progress(N, False), store, deadline, None,
                                errors)
    return singular


#: up to this many coordinates :class:`LineFactors` solves all lines as one stacked system
STACKED_LIMIT = 24


class LineFactors:
    """Z(w_l) = K - w_l^2 M + i w_l C factorized once at every line, for several
    right-hand sides that change from line to line (the response, then its derivatives:
    :mod:`resonant.analyses.frf_sensitivity`).

    Up to :data:`STACKED_LIMIT` coordinates the lines are one stacked dense system
    (``numpy.linalg.solve`` per call); above, each line keeps its LU: LAPACK's banded
    ``zgbtrf`` where the bandwidth of M, C, K is at most n / 4, else a dense one.

    Parameters
    ----------
    M, C, K : ndarray or sparse matrix
        (n, n).
    w : ndarray
        The lines (rad/s).
    stacked_limit : int, optional
        Overrides :data:`STACKED_LIMIT`.

    Raises
    ------
    AnalysisError
        Where Z is singular at a line (an undamped resonance).

    Examples
    --------
    >>> factors = LineFactors(np.eye(1), np.zeros((1, 1)), 4 * np.eye(1), np.array([1.0]))
    >>> factors.solve(np.array([[[3.0]]])).real.tolist()        # 3 / (4 - 1)
    [[[1.0]]]
    """

    def __init__(self, M: Matrix, C: Matrix, K: Matrix, w: np.ndarray,
                 stacked_limit: int | None = None) -> None:
        from scipy.linalg import lu_factor
        from scipy.linalg.lapack import zgbtrf

        Md, Cd, Kd = (dense_matrix(a) for a in (M, C, K))
        n = Kd.shape[0]
        self.w = np.asarray(w, dtype=float)
        w2 = (self.w ** 2)[:, None, None]
        iw = 1j * self.w[:, None, None]
        self.kind = "stacked" if n <= (STACKED_LIMIT if stacked_limit is None
                                       else stacked_limit) else "dense"
        self.lower, self.upper = dense_bandwidths((Md != 0) | (Cd != 0) | (Kd != 0))
        self.factors: list[Any] = []
        if self.kind == "stacked":
            self.Z = Kd[None] - w2 * Md[None] + iw * Cd[None]
            return
        if self.lower + self.upper + 1 <= n // 4:
            self.kind = "banded"
            lo, up = self.lower, self.upper

            def band(A: np.ndarray) -> np.ndarray:
                out = np.zeros((2 * lo + up + 1, n))
                for d in range(-lo, up + 1):         # A[i, j] at out[lo + up + i - j, j]
                    out[lo + up - d, max(d, 0):n + min(d, 0)] = np.diagonal(A, d)
                return out

            bands = band(Kd)[None] - w2 * band(Md)[None] + iw * band(Cd)[None]
            for line in range(len(self.w)):
                lu, pivots, info = zgbtrf(bands[line], lo, up)
                if info != 0:
                    self._singular(line)
                self.factors.append((lu, pivots))
            return
        for line in range(len(self.w)):
            Z = Kd - self.w[line] ** 2 * Md + 1j * self.w[line] * Cd
            with _warnings.catch_warnings():
                _warnings.simplefilter("ignore")              # a singular Z: refused below
                lu, pivots = lu_factor(Z, check_finite=False)
            if not (np.isfinite(lu).all() and (np.diagonal(lu) != 0).all()):
                self._singular(line)
            self.factors.append((lu, pivots))

    def _singular(self, line: int) -> None:
        raise AnalysisError(f"the system is singular at {self.w[line] / (2 * np.pi):.6g} Hz "
                            "(an undamped resonance): the response there is unbounded; add "
                            "damping")

    def solve(self, B: np.ndarray) -> np.ndarray:
        """Z(w_l)^-1 B_l at every line.

        Parameters
        ----------
        B : ndarray
            (lines, n, k).

        Returns
        -------
        ndarray
            (lines, n, k) complex.
        """
        from scipy.linalg import lu_solve
        from scipy.linalg.lapack import zgbtrs

        if self.kind == "stacked":
            return np.asarray(np.linalg.solve(self.Z, B))
        out = np.empty(B.shape, complex)
        for line, factor in enumerate(self.factors):
            if self.kind == "banded":
                out[line] = zgbtrs(factor[0], self.lower, self.upper, B[line], factor[1])[0]
            else:
                out[line] = lu_solve(factor, B[line], check_finite=False)
        return out


__all__ = ["solve_harmonic", "KernelResult", "choose_method", "choose_direct", "direct_costs",
           "band_ordering", "BandOrdering",
           "reduced_budget", "reduced_points", "largest_abs", "closed_form_solve",
           "check_batch_mass", "equilibration", "METHODS", "require_kept",
           "SINGULAR_CONDITION",
           "LOSS_CONDITION", "DEFAULT_TOL", "LineFactors", "STACKED_LIMIT"]
