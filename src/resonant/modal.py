"""The modal kernel: eigenvalues of M q'' + C q' + K q = 0 for one or many parameter points.

Every modal computation of the package comes through here: ``modes`` (one point), the
stability checks of the analyses and the study quantities (stacks of samples,
``(N, n, n)``), so that they share one ordering rule, one zero threshold and one
stability tolerance:

- the undamped eigenvalues lambda = omega^2 of K x = lambda M x are ascending; a
  |lambda| below :data:`ZERO_EIGENVALUE` times the largest |lambda| of its point is a
  round-off zero (a rigid-body mode) and counts as 0;
- the complex eigenvalues s of the state matrix are ordered by |s| (compared to 12
  significant digits of the largest |s|), then by Im s;
- a point is unstable when some Re s exceeds :data:`STABILITY_TOLERANCE` times
  max(1, max |s|), except an s with |s| below :data:`ZERO_STATE` times that: the round-off
  of a multiple zero eigenvalue (a rigid-body mode makes a Jordan block at 0, computed
  only to about sqrt(eps) of the matrix's size), which counts as 0.

Large sparse models have their lowest modes from :func:`lowest_modes` (shift-invert
Lanczos, refined with residuals computed in twice the working precision) and every mode
an error bound from its residual (:func:`eigenvalue_bounds`); their complex modes from
:func:`lowest_state_eigenvalues`.  The rest of the package's eigen-solves are here too:
one point (:func:`point_state_eigenvalues`), the first-order modes with their vectors
(:func:`state_modes`), the modes below a frequency of a reduced model's basis
(:func:`modes_below`), and the exponents of periodic systems (:func:`eigenvalues` of
Hill's or the monodromy matrix, :func:`fundamental_strip`).  No module outside the
kernels calls an eigensolver or a sparse factorization (tests/test_architecture.py).

Examples
--------
>>> M = np.eye(2)[None]
>>> K = np.array([[[2.0, -1.0], [-1.0, 2.0]]])
>>> undamped_lambdas(M, K).round(12).tolist()
[[1.0, 3.0]]
>>> unstable(state_eigenvalues(M, np.zeros((1, 2, 2)), K)).tolist()
[False]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .arrays import Matrix
from .deadline import NO_DEADLINE, Deadline
from .errors import AnalysisError, ResonantError
from .memory import dense_matrix

#: |lambda| < ZERO_EIGENVALUE * max |lambda| of the point is a round-off zero
ZERO_EIGENVALUE = 1e-12
#: Re s > STABILITY_TOLERANCE * max(1, max |s|) is an unstable eigenvalue
STABILITY_TOLERANCE = 1e-9
#: |s| <= ZERO_STATE * max(1, max |s|) is a zero state eigenvalue (about sqrt(eps))
ZERO_STATE = 1.5e-8
#: Im s >= -UPPER_TOLERANCE * max(1, |s|) counts as an eigenvalue of the upper half plane
UPPER_TOLERANCE = 1e-12
#: |Im s| <= REAL_TOLERANCE * |s| is a real eigenvalue (an overdamped mode, zeta >= 1)
REAL_TOLERANCE = 1e-8
#: a relative error bound above this is reported as limited by the conditioning
LIMITED_ACCURACY = 1e-8


# -- stacks of small dense matrices ---------------------------------------------------------

def largest_abs(a: np.ndarray) -> np.ndarray:
    """``np.abs(a).max(axis=-1)`` (NaN where an entry is NaN); for a stack of short rows
    (N, m <= 8) by a loop over the columns, several times faster than a reduction over
    the short axis.

    Examples
    --------
    >>> largest_abs(np.array([[1.0, -3.0], [2.0, 0.5j]])).tolist()
    [3.0, 2.0]
    """
    if a.ndim != 2 or not 0 < a.shape[1] <= 8:
        result: np.ndarray = np.abs(a).max(axis=-1)
        return result
    out: np.ndarray = np.abs(a[:, 0])
    for j in range(1, a.shape[1]):
        np.maximum(out, np.abs(a[:, j]), out=out)
    return out


def largest_entry(a: np.ndarray) -> np.ndarray:
    """max |a_ij| of each matrix of a stack (N, n, n) (NaN where an entry is NaN)."""
    return largest_abs(a.reshape(a.shape[0], -1))


def close(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``np.isclose(x, y, rtol=1e-12, atol=0)``, its formula without its overhead."""
    with np.errstate(invalid="ignore"):
        result: np.ndarray = ((np.abs(x - y) <= 1e-12 * np.abs(y)) & np.isfinite(y)) | (x == y)
        return result


def symmetric_stack(a: np.ndarray) -> bool:
    """``np.allclose(a, a.swapaxes(1, 2), rtol=1e-12, atol=0)`` on the entries that can
    differ: each pair across the diagonal, both ways (a NaN on the diagonal fails)."""
    n = a.shape[-1]
    if np.isnan(np.diagonal(a, axis1=1, axis2=2)).any():
        return False
    i, j = np.triu_indices(n, 1)
    upper, lower = a[:, i, j], a[:, j, i]
    return bool(close(upper, lower).all() and close(lower, upper).all())


def singular_mass(M: np.ndarray) -> np.ndarray:
    """Samples of a stack whose mass matrix is singular (smallest singular value below
    1e-13 of the largest), as ``check_mass_matrix`` judges one point."""
    if M.shape[-1] == 0:
        return np.zeros(M.shape[0], dtype=bool)
    with np.errstate(all="ignore"):
        s = np.linalg.svd(M, compute_uv=False)
    return ~(s[:, -1] > 1e-13 * s[:, 0]) | ~np.isfinite(s).all(axis=1)


def require_finite(what: str, *arrays: np.ndarray) -> None:
    """AnalysisError (exit 3) instead of a LinAlgError or NaN results further on."""
    if not all(np.all(np.isfinite(a)) for a in arrays):
        raise AnalysisError(
            f"{what} is not finite: the parameter values span too many orders of magnitude "
            "(an overflow to infinity); use units in which the masses and stiffnesses are "
            "nearer to 1")


def _symmetric(a: np.ndarray, rtol: float = 1e-12) -> bool:
    return bool(np.allclose(a, a.T, rtol=rtol, atol=rtol * (np.abs(a).max() if a.size else 0)))


def undamped_eigen(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues lambda = omega^2 (ascending) and mode shapes (columns) of K x = lambda M x
    at one point (symmetric-definite LAPACK solver, else the general one).

    Examples
    --------
    >>> lam, vec = undamped_eigen(np.eye(2), np.diag([4.0, 1.0]))
    >>> lam.tolist(), np.abs(vec).tolist()
    ([1.0, 4.0], [[0.0, 1.0], [1.0, 0.0]])
    """
    import scipy.linalg  # not at import: a study of a small model needs no scipy

    require_finite("M or K", M, K)
    if _symmetric(M) and _symmetric(K):
        try:
            lam, vec = scipy.linalg.eigh(K, M)
            require_finite("an eigenvalue K x = lambda M x", lam)
            return lam, vec
        except np.linalg.LinAlgError:
            pass  # M not positive definite: fall back to the general problem
    with np.errstate(all="ignore"):
        lam, vec = scipy.linalg.eig(K, M)
    require_finite("an eigenvalue K x = lambda M x", lam)
    order = np.argsort(lam.real)
    return lam[order].real, vec[:, order].real


def undamped_eigenvalues(M: Matrix, K: Matrix) -> np.ndarray:
    """omega^2 of K x = omega^2 M x, ascending, without eigenvectors.

    A diagonal M and a banded symmetric K use LAPACK's banded symmetric
    eigensolver on M^-1/2 K M^-1/2 (cost n b^2); anything else the dense one.
    """
    import scipy.linalg

    Md, Kd = (dense_matrix(a) for a in (M, K))
    diag = np.diag(Md)
    lower = 0
    rows, cols = np.nonzero(Kd)
    if rows.size:
        lower = int(np.abs(rows - cols).max())
    symmetric = np.allclose(Kd, Kd.T, rtol=1e-12, atol=1e-12 * np.abs(Kd).max(initial=0))
    if symmetric and np.all(diag > 0) and np.count_nonzero(Md - np.diag(diag)) == 0 and \
            lower + 1 <= max(8, Kd.shape[0] // 20):
        scale = 1 / np.sqrt(diag)
        S = Kd * scale[:, None] * scale[None, :]
        band = np.zeros((lower + 1, S.shape[0]))
        for d in range(lower + 1):  # lower band storage: band[d, j] = S[j + d, j]
            band[d, :S.shape[0] - d] = np.diagonal(S, -d)
        banded: np.ndarray = scipy.linalg.eig_banded(band, lower=True, eigvals_only=True)
        return banded
    try:
        result: np.ndarray = scipy.linalg.eigh(Kd, Md, eigvals_only=True)
        return result
    except (np.linalg.LinAlgError, ValueError):
        return np.sort(scipy.linalg.eigvals(Kd, Md).real)


def cholesky_lambdas(M: np.ndarray, K: np.ndarray) -> np.ndarray | None:
    """omega^2 of a stack by Cholesky of M, ascending (None when some M is not symmetric
    positive definite or some K not symmetric)."""
    if not (symmetric_stack(M) and symmetric_stack(K)):
        return None
    if M.shape[-1] == 2:
        return pencil_roots_2x2(M, K)
    try:
        L = np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        return None
    Linv = np.linalg.inv(L)
    A = Linv @ K @ Linv.swapaxes(1, 2)
    return np.linalg.eigvalsh((A + A.swapaxes(1, 2)) / 2)


def pencil_roots_2x2(M: np.ndarray, K: np.ndarray) -> np.ndarray | None:
    """omega^2 of a symmetric 2 x 2 pencil in closed form, ascending (None when some M is
    not positive definite): the roots of det(K - lambda M) = 0, the smaller one as
    det K / (det M * larger), which keeps it as accurate as a batched eigvalsh (and
    ten times faster).  M and K are stacks (N, 2, 2) or (1, 2, 2) (the same for every
    sample: what depends on it alone is computed once)."""
    with np.errstate(all="ignore"):
        # scaled to entries of order 1, so that squares neither overflow nor underflow
        m_scale, k_scale = largest_entry(M), largest_entry(K)
        k_scale = np.where((k_scale > 0) & np.isfinite(k_scale), k_scale, 1.0)
        # entry by entry: dividing the stacks by broadcasting is several times slower
        m11, m12, m22 = (M[:, i, j] / m_scale for i, j in ((0, 0), (0, 1), (1, 1)))
        k11, k12, k22 = (K[:, i, j] / k_scale for i, j in ((0, 0), (0, 1), (1, 1)))
        det_m = m11 * m22 - m12 * m12
        if not ((m11 > 0) & (det_m > 1e-14 * m11 * m22)).all():
            return None
        b = k11 * m22 + k22 * m11 - 2.0 * k12 * m12
        det_k = k11 * k22 - k12 * k12
        q = 0.5 * (b + np.copysign(np.sqrt(np.maximum(b * b - 4.0 * det_m * det_k, 0.0)), b))
        big = q / det_m
        small = np.where(q != 0.0, det_k / np.where(q != 0.0, q, 1.0), 0.0)
        ratio = k_scale / m_scale
        roots = np.empty((len(big), 2))
        np.multiply(ratio, np.minimum(big, small), out=roots[:, 0])
        np.multiply(ratio, np.maximum(big, small), out=roots[:, 1])
        return roots


def general_lambdas(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    """omega^2 of a stack one point at a time by :func:`undamped_eigen` (NaN where it
    fails): the route where some M is not positive definite."""
    count = max(M.shape[0], K.shape[0])
    M, K = (np.broadcast_to(a, (count, *a.shape[1:])) for a in (M, K))
    out = np.full(M.shape[:2], np.nan)
    for i in range(count):
        try:
            out[i] = undamped_eigen(M[i], K[i])[0]
        except (ResonantError, np.linalg.LinAlgError, ValueError):
            pass
    return out


def undamped_lambdas(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    """omega^2 of K x = omega^2 M x for every sample of a stack, ascending, shape (N, n)."""
    lam = cholesky_lambdas(M, K)
    return lam if lam is not None else general_lambdas(M, K)


def clean_zeros(lam: np.ndarray) -> np.ndarray:
    """lambda with the round-off zeros (:data:`ZERO_EIGENVALUE`) set to 0, per point
    (the last axis).

    Examples
    --------
    >>> clean_zeros(np.array([1e-14, 4.0])).tolist()
    [0.0, 4.0]
    """
    lam = np.asarray(lam, dtype=float)
    with np.errstate(invalid="ignore"):
        scale = np.maximum(np.nanmax(np.abs(lam), axis=-1, initial=0.0), 1e-300)
        return np.where(np.abs(lam) < ZERO_EIGENVALUE * scale[..., None], 0.0, lam)


def frequencies_from_eigenvalues(lam: np.ndarray) -> np.ndarray:
    """sqrt of the eigenvalues lambda = omega^2 of one point that are >= 0 (round-off zeros
    count as 0)."""
    lam = clean_zeros(lam)
    result: np.ndarray = np.sqrt(lam[lam >= 0])
    return result


def natural_frequency(lam: np.ndarray, index: int) -> np.ndarray:
    """The ``index``-th (from 1) of the frequencies sqrt(lambda >= 0) of each sample (N, n),
    as ``modes`` lists them; NaN where there is no such mode."""
    lam = clean_zeros(lam)
    position = (lam < 0).sum(axis=1) + index - 1
    inside = position < lam.shape[1]
    picked = np.take_along_axis(lam, np.minimum(position, lam.shape[1] - 1)[:, None], 1)[:, 0]
    return np.where(inside & np.isfinite(picked), np.sqrt(np.abs(picked)), np.nan)


# -- the state eigenvalues ------------------------------------------------------------------

def state_matrix(minv_k: np.ndarray, minv_c: np.ndarray) -> np.ndarray:
    """The state matrix A = [[0, I], [-M^-1 K, -M^-1 C]] of x' = A x, x = [q, q'], from
    M^-1 K and M^-1 C (one point (n, n) or a stack (..., n, n)): the one place the
    first-order form is written.

    Examples
    --------
    >>> state_matrix(4 * np.eye(1), 0.5 * np.eye(1)).tolist()
    [[0.0, 1.0], [-4.0, -0.5]]
    """
    n = minv_k.shape[-1]
    A = np.zeros((*minv_k.shape[:-2], 2 * n, 2 * n))
    A[..., :n, n:] = np.eye(n)
    A[..., n:, :n], A[..., n:, n:] = -minv_k, -minv_c
    return A


def quadratic_eigenvalues(K0: np.ndarray, K1: np.ndarray, K2: np.ndarray) -> np.ndarray:
    """The finite eigenvalues s of (s^2 K2 + s K1 + K0) x = 0 (dense; K2 may be singular),
    by the companion pencil [[0, I], [-K0, -K1]] - s [[I, 0], [0, K2]].

    Examples
    --------
    >>> s = quadratic_eigenvalues(4 * np.eye(1), np.zeros((1, 1)), np.eye(1))
    >>> sorted(s.imag.round(12).tolist())
    [-2.0, 2.0]
    """
    size = K0.shape[0]
    eye, zero = np.eye(size), np.zeros((size, size))
    return eigenvalues(np.block([[zero, eye], [-K0, -K1]]), np.block([[eye, zero], [zero, K2]]))


def state_eigenvalues(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Eigenvalues of the state matrix [[0, I], [-M^-1 K, -M^-1 C]] per sample (N, 2n)
    (NaN for a sample whose state matrix is not finite)."""
    n = M.shape[1]
    with np.errstate(all="ignore"):
        minv = np.linalg.solve(M, np.concatenate([K, C], axis=2))
    A = state_matrix(minv[..., :n], minv[..., n:])
    finite = np.isfinite(A).all(axis=(1, 2))
    A[~finite] = 0.0
    eigenvalues = np.linalg.eigvals(A)
    eigenvalues[~finite] = np.nan
    return eigenvalues


def order(eigenvalues: np.ndarray) -> np.ndarray:
    """Complex eigenvalues of each point (last axis) by |s|, then Im s (|s| compared to 12
    significant digits of the point's largest |s|).

    Examples
    --------
    >>> order(np.array([2j, -2j, 1 + 0j])).imag.tolist()
    [0.0, -2.0, 2.0]
    """
    s = np.asarray(eigenvalues)
    size = np.abs(s)
    scale = np.maximum(np.nanmax(size, axis=-1, initial=0.0), 1.0)[..., None]
    key = np.round(size / scale, 12)
    index = np.lexsort((s.imag, key), axis=-1)
    return np.take_along_axis(s, index, -1)


def unstable(eigenvalues: np.ndarray) -> np.ndarray:
    """Whether each point (last axis) has an eigenvalue with Re s above the tolerance (and
    |s| above the zero threshold :data:`ZERO_STATE`).

    Examples
    --------
    >>> unstable(np.array([[-1.0 + 0j, 1e-8 + 0j], [-1.0 + 0j, 1e-3 + 0j]])).tolist()
    [False, True]
    """
    s = np.asarray(eigenvalues)
    size = np.abs(s)
    scale = np.maximum(1.0, size.max(axis=-1, initial=0.0))[..., None]
    growing = (s.real > STABILITY_TOLERANCE * scale) & (size > ZERO_STATE * scale)
    return np.asarray(growing.any(axis=-1))


def marginal(eigenvalues: np.ndarray) -> np.ndarray:
    """Whether some Re s of each point (last axis) is not below minus the tolerance."""
    s = np.asarray(eigenvalues)
    scale = np.maximum(1.0, np.abs(s).max(axis=-1, initial=0.0))
    return np.asarray(~(s.real < -STABILITY_TOLERANCE * scale[..., None]).all(axis=-1))


def clean_state_zeros(eigenvalues: np.ndarray) -> np.ndarray:
    """The state eigenvalues of each point (last axis) with those below the zero threshold
    :data:`ZERO_STATE` set to 0 (a rigid-body mode's round-off).

    Examples
    --------
    >>> clean_state_zeros(np.array([1e-9 - 2e-9j, -1 + 3j])).tolist()
    [0j, (-1+3j)]
    """
    s = np.asarray(eigenvalues)
    with np.errstate(invalid="ignore"):
        scale = np.maximum(np.nanmax(np.abs(s), axis=-1, initial=0.0), 1.0)[..., None]
        return np.where(np.abs(s) <= ZERO_STATE * scale, 0.0, s)


def upper_half(eigenvalues: np.ndarray) -> np.ndarray:
    """The ordered eigenvalues of one point with Im s >= 0 (one of each conjugate pair),
    round-off zeros set to 0."""
    s = order(clean_state_zeros(eigenvalues))
    result: np.ndarray = s[s.imag >= -UPPER_TOLERANCE * np.maximum(1.0, np.abs(s))]
    return result


def damping_ratios(eigenvalues: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Damping ratio -Re s/|s| and damped frequency |Im s| of each eigenvalue of one point
    with Im s >= 0, in the order of :func:`order`.

    Examples
    --------
    >>> zeta, wd = damping_ratios(np.array([-1 + 2j, -1 - 2j]))
    >>> zeta.round(6).tolist(), wd.tolist()
    ([0.447214], [2.0])
    """
    upper = upper_half(eigenvalues)
    size = np.abs(upper)
    with np.errstate(invalid="ignore", divide="ignore"):
        zeta = np.where(size > 0, -upper.real / np.where(size > 0, size, 1), 0.0)
    return zeta, np.abs(upper.imag)


def damping_ratio(eigenvalues: np.ndarray, index: int) -> np.ndarray:
    """-Re s/|s| of the ``index``-th (from 1) eigenvalue with Im s >= 0 of each sample
    (N, 2n), in the order of :func:`order`, as :func:`damping_ratios` gives them; NaN
    where there is none."""
    count = eigenvalues.shape[0]
    if index > eigenvalues.shape[1]:
        return np.full(count, np.nan)
    s = clean_state_zeros(eigenvalues)
    size = np.abs(s)
    with np.errstate(invalid="ignore"):
        scale = np.maximum(np.nanmax(size, axis=-1, initial=0.0), 1.0)[:, None]
        upper = s.imag >= -UPPER_TOLERANCE * np.maximum(1.0, size)
    # the order of :func:`order`, the lower half plane last
    key = np.where(upper, np.round(size / scale, 12), np.inf)
    position = np.lexsort((s.imag, key), axis=-1)[:, index - 1]
    rows = np.arange(count)
    chosen, valid, magnitude = s[rows, position], upper[rows, position], size[rows, position]
    with np.errstate(all="ignore"):
        zeta = np.where(magnitude > 0, -chosen.real / np.where(magnitude > 0, magnitude, 1), 0.0)
    return np.where(valid & np.isfinite(chosen), zeta, np.nan)


def unstable_by_inertia(C: np.ndarray, K: np.ndarray, lam: np.ndarray, *,
                        symmetric_k: bool = False) -> np.ndarray | None:
    """Instability without the state eigenvalues, where a theorem decides it: for
    symmetric M > 0, C >= 0 and symmetric K the equilibrium is unstable exactly when K
    has a negative eigenvalue (Kelvin-Tait-Chetaev; damping neither makes a potential
    minimum unstable nor stabilizes a maximum).  The tolerance is that of
    :func:`unstable` on the undamped roots s = sqrt(-lambda) (``lam``, by Cholesky of M).
    None where the theorem does not apply.  ``symmetric_k``: K is known to be symmetric
    (``lam`` came from :func:`cholesky_lambdas`, which checked it)."""
    if not (symmetric_stack(C) and (symmetric_k or symmetric_stack(K))):
        return None
    if C.any():
        c = np.linalg.eigvalsh(C)
        if (c[:, 0] < -1e-12 * np.maximum(np.abs(c).max(axis=1), 1e-300)).any():
            return None
    size = np.sqrt(largest_abs(lam) if lam.shape[1] else np.zeros(len(lam)))
    with np.errstate(invalid="ignore"):
        unstable: np.ndarray = np.sqrt(np.maximum(-lam[:, 0], 0.0)) > \
            STABILITY_TOLERANCE * np.maximum(1.0, size)
    return unstable


# -- large sparse models: the lowest modes and their error bounds ---------------------------

_SPLITTER = 134217729.0  # 2**27 + 1: Veltkamp's split of a double into two halves


def _two_sum(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """s + e == a + b exactly, s = fl(a + b) (Knuth)."""
    s = a + b
    v = s - a
    return s, (a - (s - v)) + (b - v)


def _split(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    c = _SPLITTER * a
    hi = c - (c - a)
    return hi, a - hi


def _two_product(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """p + e == a b exactly, p = fl(a b) (Dekker)."""
    p = a * b
    a_hi, a_lo = _split(a)
    b_hi, b_lo = _split(b)
    return p, a_lo * b_lo - (((p - a_hi * b_hi) - a_lo * b_hi) - a_hi * b_lo)


def accurate_product(A: Matrix, X: np.ndarray) -> np.ndarray:
    """A @ X as if computed in twice the working precision, then rounded (the compensated
    dot product of Ogita, Rump and Oishi, SIAM J. Sci. Comput. 26, 2005): accurate to a
    few units in the last place of the result even where the sum cancels, as K x does
    for a smooth mode of a stiff structure.

    Examples
    --------
    >>> A = np.array([[1e16, 1.0, -1e16]])
    >>> float(accurate_product(A, np.ones((3, 1)))[0, 0]), float((A @ np.ones(3))[0])
    (1.0, 0.0)
    """
    import scipy.sparse as sp

    A = sp.csr_matrix(A)
    A.sum_duplicates()
    X = np.asarray(X, dtype=float)
    vector = X.ndim == 1
    X = X.reshape(X.shape[0], -1)
    n = A.shape[0]
    lengths = np.diff(A.indptr)
    rows = np.argsort(-lengths, kind="stable")          # longest rows first
    longest = lengths[rows]
    start = A.indptr[rows]
    s = np.zeros((n, X.shape[1]))
    c = np.zeros_like(s)
    for j in range(int(longest[0]) if n else 0):
        live = int(np.searchsorted(-longest, -j, side="left"))  # the rows longer than j
        at = start[:live] + j
        p, e = _two_product(A.data[at][:, None], X[A.indices[at]])
        s[:live], t = _two_sum(s[:live], p)
        c[:live] += t + e
    out = np.empty_like(s)
    out[rows] = s + c
    return out[:, 0] if vector else out


def eigenvalue_bounds(M: Matrix, K: Matrix, lam: np.ndarray, phi: np.ndarray,
                      accurate: bool = True, complete: bool = True) -> np.ndarray:
    """Bounds on |lambda_j - lambda| for an exact eigenvalue lambda of K x = lambda M x
    near each computed pair (lambda_j, phi_j) of a symmetric pencil with M > 0, the
    pairs ascending.

    With x = phi_j / ||phi_j||_M, its Rayleigh quotient rho_j = x^T K x and
    r = K x - rho_j M x, some eigenvalue lies within e_j = ||r||_{M^-1} =
    sqrt(r^T M^-1 r) of rho_j (the residual bound of the
    symmetric-definite pencil in the M inner product; Parlett, The Symmetric Eigenvalue
    Problem, 1998, Thm 4.5.1).  Where the other eigenvalues are at least d_j > e_j away
    (d_j from the neighbours and their bounds), the bound is e_j^2 / d_j (Kato-Temple,
    ibid. Thm 10.6.1): the eigenvalue of a Rayleigh-Ritz pair is accurate to the square
    of its residual.  Both add |lambda_j - rho_j|.  Without ``complete`` the pairs are
    the lowest ones only, so the last has no known neighbour above and keeps e_j.  The
    residual is computed by
    :func:`accurate_product` (or, without ``accurate``, in working precision, and e_j
    then adds the rounding error of that product, (w + 2) eps (|K| |x| + |lambda_j| |M|
    |x|) for w entries a row).

    Examples
    --------
    >>> M, K = np.eye(2), np.diag([1.0, 4.0])
    >>> eigenvalue_bounds(M, K, np.array([1.0, 4.0 + 1e-6]), np.eye(2)).round(12).tolist()
    [0.0, 1e-06]
    >>> phi = np.array([[1.0, -1e-4], [1e-4, 1.0]])
    >>> eigenvalue_bounds(M, K, np.array([1.0, 4.0]), phi).round(10).tolist()
    [6e-08, 6e-08]
    """
    import scipy.linalg
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    phi = np.asarray(phi, dtype=float)
    lam = np.asarray(lam, dtype=float)
    if phi.size == 0:
        return np.zeros(0)
    sparse = sp.issparse(M) or sp.issparse(K)
    if accurate:
        KX, MX = accurate_product(K, phi), accurate_product(M, phi)
        rounding: Any = 0.0
    else:
        KX, MX = K @ phi, M @ phi
        # |K| and |M| with their nonzeros only: a banded matrix costs its band
        absK, absM = (abs(sp.csr_matrix(a)) for a in (K, M))
        width = max(int(np.max(np.diff(a.indptr), initial=1)) for a in (absK, absM))
        gamma = (width + 2) * np.finfo(float).eps
        rounding = gamma * (absK @ np.abs(phi) + (absM @ np.abs(phi)) * np.abs(lam))
    mass = np.abs(np.einsum("ij,ij->j", phi, MX))
    with np.errstate(all="ignore"):
        rho = np.einsum("ij,ij->j", phi, KX) / mass      # the Rayleigh quotients
        moved = np.abs(lam - rho)
        if np.ndim(rounding):
            moved = moved + np.einsum("ij,ij->j", np.abs(phi), rounding) / mass
        R = KX - MX * rho
        diagonal = sp.csr_matrix(M).diagonal()
        if sp.csr_matrix(M).nnz == np.count_nonzero(diagonal):   # a lumped mass matrix
            def solve(b: np.ndarray) -> np.ndarray:
                result: np.ndarray = b / diagonal[:, None]
                return result
        elif sparse:
            solve = splu(sp.csc_matrix(M)).solve
        else:
            factor = scipy.linalg.cho_factor(np.asarray(M, dtype=float))

            def solve(b: np.ndarray) -> np.ndarray:
                return np.asarray(scipy.linalg.cho_solve(factor, b))
        e = np.sqrt(np.abs(np.einsum("ij,ij->j", R, solve(R))) / mass)
        if np.ndim(rounding):
            e = e + np.sqrt(np.abs(np.einsum("ij,ij->j", rounding, solve(rounding))) / mass)
        e = np.where(np.isfinite(e), e, np.inf)
        # the distance to the other eigenvalues: each lies within e_i of its lambda_i
        below = np.concatenate([[np.inf], lam[1:] - lam[:-1] - e[:-1] - moved[:-1]])
        above = np.concatenate([lam[1:] - lam[:-1] - e[1:] - moved[1:],
                                [np.inf if complete else 0.0]])
        gap = np.minimum(below, above)
        quadratic = np.where(gap > e, e * e / np.where(gap > 0, gap, 1.0), np.inf)
    bound = np.minimum(e, quadratic) + moved
    # the computed eigenvalue is a double: never claim more than its last bits
    bound = np.where(np.isfinite(bound), bound, np.inf)
    result: np.ndarray = bound + 2 * np.finfo(float).eps * np.abs(lam)
    return result


def frequency_bounds(lam: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """Bounds on the error of omega = sqrt(lambda) from bounds on the error of lambda.

    Examples
    --------
    >>> frequency_bounds(np.array([100.0]), np.array([2e-6])).round(12).tolist()
    [1e-07]
    """
    lam = np.maximum(np.asarray(lam, dtype=float), 0.0)
    root = np.sqrt(lam)
    result: np.ndarray = np.maximum(np.sqrt(lam + bounds) - root,
                                    root - np.sqrt(np.maximum(lam - bounds, 0)))
    return result


def _factor(M: Matrix, K: Matrix, shift: float) -> Any:
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    return splu(sp.csc_matrix(K - shift * M))


def lowest_modes(M: Matrix, K: Matrix, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The ``count`` lowest eigenpairs of K phi = lambda M phi (sparse, symmetric, M > 0),
    ascending, deterministic and accurate to the rounding of the given matrices, with a
    bound on the error of each eigenvalue (:func:`eigenvalue_bounds`).

    Shift-invert Lanczos (:func:`scipy.sparse.linalg.eigsh`, a fixed start vector) with
    the shift at 0 (or, when K is singular, just below 0) finds them with a few guard
    modes; subspace iteration with Rayleigh-Ritz then refines them, the residuals
    K X - M X Lambda computed by :func:`accurate_product`, so that the cancellation in
    K x of a smooth mode of a stiff structure does not limit them (iterative refinement
    of eigenpairs, Dongarra, Moler and Wilkinson, SIAM J. Numer. Anal. 20, 1983).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> n = 50
    >>> K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    >>> lam, phi, bounds = lowest_modes(sp.identity(n), K, 2)
    >>> exact = 4 * np.sin(np.arange(1, 3) * np.pi / (2 * n + 2)) ** 2
    >>> bool(np.allclose(lam, exact, rtol=1e-14, atol=0)), bool(np.all(bounds < 1e-14))
    (True, True)
    """
    import scipy.linalg
    import scipy.sparse as sp
    from scipy.sparse.linalg import LinearOperator, eigsh

    n = M.shape[0]
    M, K = sp.csc_matrix(M), sp.csc_matrix(K)
    shift = 0.0
    try:
        lu = _factor(M, K, shift)
        singular = not np.all(np.isfinite(lu.U.diagonal())) or \
            np.min(np.abs(lu.U.diagonal())) <= 1e-14 * np.max(np.abs(lu.U.diagonal()))
    except RuntimeError:
        singular = True
    if singular:  # rigid-body modes: a shift below 0, small against the stiffness
        shift = -1e-6 * float(np.mean(np.abs(K.diagonal())) / np.mean(np.abs(M.diagonal()))
                              or 1.0)
        lu = _factor(M, K, shift)
    wanted = min(n - 1, count + min(max(count, 2), 8))
    start = np.random.default_rng(0).standard_normal(n)  # the same every run
    op = LinearOperator((n, n), matvec=lu.solve, dtype=float)
    try:
        lam, phi = eigsh(K, k=wanted, M=M, sigma=shift, which="LM", OPinv=op, v0=start)
    except (RuntimeError, ValueError) as exc:
        raise AnalysisError(f"the sparse eigensolver failed: {exc}") from None
    lam, phi = lam[np.argsort(lam)], phi[:, np.argsort(lam)]
    positive = lam[clean_zeros(lam) > 0]
    if singular and positive.size:
        # a shift near the flexible modes: the refinement then converges fast
        try:
            lu = _factor(M, K, -1e-3 * float(positive[0]))
        except RuntimeError:
            pass
    for _ in range(4):
        R = accurate_product(K, phi) - accurate_product(M, phi) * lam
        phi = phi - lu.solve(R)
        KX, MX = accurate_product(K, phi), accurate_product(M, phi)
        gk, gm = phi.T @ KX, phi.T @ MX
        try:
            new, Y = scipy.linalg.eigh((gk + gk.T) / 2, (gm + gm.T) / 2)
        except (np.linalg.LinAlgError, ValueError):
            break
        phi = phi @ Y
        done = np.all(np.abs(new[:count] - lam[:count]) <=
                      4 * np.finfo(float).eps * np.abs(new[:count]))
        lam = new
        if done:
            break
    bounds = eigenvalue_bounds(M, K, lam, phi, complete=False)
    return lam[:count], phi[:, :count], bounds[:count]



# -- one point, the state space, periodic systems ---------------------------------------------

def symmetric_eigenvalues(A: np.ndarray) -> np.ndarray:
    """The ascending eigenvalues of a symmetric dense matrix (the definiteness of M).

    Examples
    --------
    >>> symmetric_eigenvalues(np.diag([2.0, -1.0])).tolist()
    [-1.0, 2.0]
    """
    return np.asarray(np.linalg.eigvalsh(A))


def mass_normalized_modes(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """lambda = omega^2 (ascending) and the M-orthonormal modes of K phi = lambda M phi for
    a symmetric K and a symmetric positive definite M (LinAlgError or ValueError else).

    Examples
    --------
    >>> lam, phi = mass_normalized_modes(np.diag([2.0, 2.0]), np.diag([2.0, 8.0]))
    >>> lam.round(12).tolist(), bool(np.allclose(phi.T @ np.diag([2.0, 2.0]) @ phi, np.eye(2)))
    ([1.0, 4.0], True)
    """
    import scipy.linalg

    lam, phi = scipy.linalg.eigh(K, M)
    return np.asarray(lam), np.asarray(phi)


def point_state_eigenvalues(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> np.ndarray:
    """The 2n state eigenvalues at one point (:func:`state_eigenvalues` of a stack of one);
    AnalysisError naming M^-1 K or M^-1 C where they are not finite.

    Examples
    --------
    >>> s = point_state_eigenvalues(np.eye(1), np.zeros((1, 1)), 4 * np.eye(1))
    >>> sorted(s.imag.round(12).tolist())
    [-2.0, 2.0]
    """
    require_finite("the state matrix (M^-1 K, M^-1 C)", np.linalg.solve(M, K),
                   np.linalg.solve(M, C))
    result: np.ndarray = state_eigenvalues(
        *(np.asarray(a, dtype=float)[None] for a in (M, C, K)))[0]
    return result


def state_modes(M: np.ndarray, C: np.ndarray, K: np.ndarray, what: str = "the analysis"
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The first-order modes of a small dense system: the poles mu, the modes X of the
    state matrix [[0, I], [-M^-1 K, -M^-1 C]] and X^-1 (``what`` needs them: the error
    messages name it).

    Raises
    ------
    AnalysisError
        If M is singular or the modes are not independent (a defective system).

    Examples
    --------
    >>> mu, X, Xinv = state_modes(np.eye(1), np.zeros((1, 1)), 4 * np.eye(1))
    >>> sorted(mu.imag.round(12).tolist()), bool(np.allclose(X @ Xinv, np.eye(2)))
    ([-2.0, 2.0], True)
    """
    import scipy.linalg

    r = M.shape[0]
    try:
        minv = np.linalg.solve(M, np.hstack([K, C]))
    except np.linalg.LinAlgError:
        raise AnalysisError(f"the mass matrix M is singular: {what} needs a positive "
                            "definite M") from None
    mu, X = scipy.linalg.eig(state_matrix(minv[:, :r], minv[:, r:]))
    if not np.all(np.isfinite(X)) or np.linalg.cond(X) > 1e10:
        raise AnalysisError("the linear part is defective (its modes are not independent): "
                            f"{what} cannot diagonalize it")
    return mu, X, np.linalg.inv(X)


def overdamped(eigenvalues: np.ndarray) -> np.ndarray:
    """Which eigenvalues of one point are real and not zero: overdamped modes (damping
    ratio 1 or more), which no damped frequency describes (|Im s| at most
    :data:`REAL_TOLERANCE` times |s|, |s| above the zero threshold :data:`ZERO_STATE`).

    Examples
    --------
    >>> overdamped(np.array([-400.0 + 1e-12j, -1 + 3j, 0j])).tolist()
    [True, False, False]
    """
    s = np.asarray(eigenvalues)
    size = np.abs(s)
    scale = max(1.0, float(np.max(size, initial=0.0)))
    result: np.ndarray = (np.abs(s.imag) <= REAL_TOLERANCE * size) & (size > ZERO_STATE * scale)
    return result


def lowest_by_frequency(eigenvalues: np.ndarray, count: int) -> np.ndarray:
    """The eigenvalues of one point that a request for ``count`` complex modes keeps: the
    ``count`` underdamped pairs of lowest damped frequency |Im s| (both of each pair) and
    every zero and overdamped (real) one, in the one order (:func:`order`).  Overdamped
    modes below the lowest structural modes (a strongly damped layer) thus never take the
    place of a mode a user asks for.

    Examples
    --------
    >>> s = np.array([-400.0, -401.0, -3 + 500j, -3 - 500j, -1 + 40j, -1 - 40j])
    >>> lowest_by_frequency(s, 1).tolist()
    [(-1-40j), (-1+40j), (-400+0j), (-401+0j)]
    """
    s = np.asarray(eigenvalues, dtype=complex)
    real = overdamped(s) | (np.abs(s) <= ZERO_STATE * max(1.0, float(np.max(np.abs(s),
                                                                               initial=0.0))))
    pairs = s[~real]
    upper = np.sort(np.abs(pairs.imag[pairs.imag > 0]))
    if upper.size > count:
        cut = upper[count - 1] if count > 0 else -1.0
        pairs = pairs[np.abs(pairs.imag) <= cut]
    result: np.ndarray = order(np.concatenate([pairs, s[real].real.astype(complex)]))
    return result


def _nearest_state_eigenvalues(M: Matrix, C: Matrix, K: Matrix, sigma: complex, wanted: int
                               ) -> np.ndarray:
    """The eigenvalues of s^2 M + s C + K nearest ``sigma`` (``wanted`` of them, or those
    that converged within a bounded number of restarts: the nearest ones, a cluster at the
    edge left out; possibly none); shift-invert Arnoldi
    on the state pencil A x = s B x, A = [[0, I], [-K, -C]], B = [[I, 0], [0, M]], whose
    operator (A - sigma B)^-1 B needs one sparse LU of the n x n matrix
    P(sigma) = sigma^2 M + sigma C + K: with x = (x1, x2), u = -P^-1 (M x2 + (C + sigma M)
    x1) and v = x1 + sigma u."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigs, splu

    n = M.shape[0]
    lu = splu(sp.csc_matrix(sigma * sigma * M + sigma * C + K, dtype=complex))
    shifted = sp.csr_matrix(C + sigma * M)

    def apply(x: np.ndarray) -> np.ndarray:
        x1, x2 = x[:n], x[n:]
        u = -lu.solve(M @ x2 + shifted @ x1)
        return np.concatenate([u, x1 + sigma * u])

    op = LinearOperator((2 * n, 2 * n), matvec=apply, dtype=complex)
    start = np.random.default_rng(0).standard_normal(2 * n).astype(complex)  # every run
    nu = np.zeros(0, dtype=complex)
    for restarts in (20, 200):
        try:
            nu = eigs(op, k=wanted, which="LM", v0=start, maxiter=restarts,
                      return_eigenvectors=False)
            break
        except ArpackNoConvergence as partial:
            # the nearest converge first; what is left is a cluster at the disk's edge
            # (the overdamped modes of a damping layer, nearly equal): the disk ends before
            nu = partial.eigenvalues
            if nu.size:
                break
    result: np.ndarray = sigma + 1.0 / nu
    return result


@dataclass(frozen=True)
class StateSearch:
    """The complex modes of a sparse model found by :func:`lowest_state_eigenvalues`.

    Attributes
    ----------
    eigenvalues : ndarray
        The ``count`` underdamped pairs of lowest damped frequency (both of each pair) and
        the zero and overdamped (real) eigenvalues found on the way, in the one order.
    shifts : ndarray
        The shifts sigma_j of the search (on the imaginary axis).
    radii : ndarray
        Each shift's disk |s - sigma_j| <= r_j: every eigenvalue in it was found.
    reach : float
        The largest damping ratio up to which every underdamped mode of damped frequency
        below the highest kept one is inside the disks (1.0: all of them).
    complete : bool
        Whether ``count`` underdamped pairs were found within the bounded number of shifts.
    """

    eigenvalues: np.ndarray
    shifts: np.ndarray
    radii: np.ndarray
    reach: float
    complete: bool


def _reach(shifts: np.ndarray, radii: np.ndarray, top: float) -> float:
    """The largest damping ratio zeta such that the wedge |Re s| <= zeta / sqrt(1 - zeta^2)
    Im s, 0 < Im s <= top, lies in the union of the disks |s - sigma_j| <= r_j."""
    if top <= 0:
        return 1.0
    y = np.linspace(top / 400, top, 400)
    reach = np.sqrt(np.maximum(radii[None, :] ** 2 - (y[:, None] - shifts.imag[None, :]) ** 2
                               - np.minimum(shifts.real, 0.0)[None, :] ** 2, 0.0)).max(axis=1)
    t = float(np.min(reach / y))
    return float(t / np.sqrt(1 + t * t))


def lowest_state_eigenvalues(M: Matrix, C: Matrix, K: Matrix, count: int) -> StateSearch:
    """The ``count`` complex modes of lowest damped frequency |Im s| of a sparse model,
    whatever the overdamped (real) modes below them: shift-invert Arnoldi of the state
    pencil at shifts along the imaginary axis.

    The first shift is near 0 (just left of it: a rigid-body mode makes the pencil
    singular at 0); each finds the m = max(count + 8, 16) eigenvalues nearest it
    (:func:`_nearest_state_eigenvalues`: one sparse LU of an n x n matrix), so that every
    eigenvalue in the disk of radius r_j (the farthest of them) is found; the next shift
    is i (y_j + 0.866 r_j), so that consecutive disks cover a band about the axis, until
    ``count`` underdamped pairs lie below the covered part of the axis, at most
    ``2 count + 8`` shifts.  A cluster of overdamped modes (a Kelvin-Voigt layer's, at
    s = -1/beta) fills a disk once and is passed.  The result keeps the modes
    :func:`lowest_by_frequency` keeps, and the reach of the search (the damping ratio up
    to which no mode could be missed).

    Raises
    ------
    AnalysisError
        If the eigensolver does not converge.

    Examples
    --------
    >>> M, K = np.eye(2), np.array([[2.0, -1.0], [-1.0, 1.0]])
    >>> C = np.array([[0.3, 0.0], [0.0, 0.0]])
    >>> found = lowest_state_eigenvalues(M, C, K, 1)
    >>> dense = point_state_eigenvalues(M, C, K)
    >>> lowest = dense[np.argsort(np.abs(dense.imag))][:2]
    >>> bool(all(np.min(np.abs(found.eigenvalues - v)) < 1e-10 for v in lowest))
    True
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import ArpackError

    n = M.shape[0]
    M, C, K = (sp.csc_matrix(a, dtype=float) for a in (M, C, K))
    scale = float(np.sqrt(abs(K).sum() / max(abs(M).sum(), 1e-300))) or 1.0
    wanted = min(2 * n - 2, max(count + 8, 16))
    sigma = complex(-1e-6 * scale, 0.0)
    found: list[np.ndarray] = []
    shifts: list[complex] = []
    radii: list[float] = []
    complete = False
    for _ in range(2 * count + 8):
        try:
            s = _nearest_state_eigenvalues(M, C, K, sigma, wanted)
            if not s.size:
                raise RuntimeError(f"no eigenvalue near {sigma:.6g} converged")
        except (RuntimeError, ValueError, ArpackError) as exc:
            raise AnalysisError(f"the sparse eigensolver for the complex modes failed: {exc}"
                                ) from None
        radius = float(np.max(np.abs(s - sigma)))
        s = s[s.imag >= -REAL_TOLERANCE * np.abs(s)]      # one of each pair
        seen = np.zeros(s.shape, dtype=bool)
        for center, r in zip(shifts, radii):                # found by an earlier disk
            seen |= np.abs(s - center) <= r * (1 + 1e-9)
        found.append(s[~seen])
        shifts.append(sigma)
        radii.append(radius)
        top = sigma.imag + 0.866 * radius
        every = np.concatenate(found)
        damped = np.sort(every.imag[~overdamped(every) & (every.imag > 0)])
        if np.sum(damped <= top) >= count or wanted >= 2 * n - 2:
            complete = True
            break
        sigma = complex(0.0, top)
    every = np.concatenate(found)
    every = np.concatenate([every, np.conj(every[every.imag > REAL_TOLERANCE * np.abs(every)])])
    kept = lowest_by_frequency(every, count)
    highest = float(np.max(kept.imag, initial=0.0))
    return StateSearch(kept, np.array(shifts), np.array(radii),
                       _reach(np.array(shifts), np.array(radii), highest), complete)


# -- gyroscopic systems: the complex modes with their shapes ---------------------------------

def _upper_modes(s: np.ndarray, X: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The eigenvalues with Im s >= 0 (one of each conjugate pair, a real one kept) in the
    one order (:func:`order`), with their displacement parts (the first n rows of the
    state vectors), each of unit norm with its largest entry real and positive."""
    scale = max(1.0, float(np.nanmax(np.abs(s), initial=0.0)))
    upper = s.imag >= -UPPER_TOLERANCE * np.maximum(scale, np.abs(s))
    s, X = s[upper], X[:n, upper]
    size = np.round(np.abs(s) / scale, 12)
    index = np.lexsort((s.imag, size))
    s, X = s[index], X[:, index]
    norms = np.linalg.norm(X, axis=0)
    X = X / np.where(norms > 0, norms, 1.0)
    largest = X[np.argmax(np.abs(X), axis=0), np.arange(X.shape[1])]
    X = X * np.where(largest != 0, np.conj(largest) / np.maximum(np.abs(largest), 1e-300), 1)
    return s, X


def gyroscopic_modes(M: np.ndarray, C: np.ndarray, K: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray]:
    """The complex modes of M q'' + C q' + K q = 0 at one point, where C may hold a
    gyroscopic part Omega G (skew) and K a circulatory part (cross-coupled bearings): the
    eigenvalues s with Im s >= 0 in the one order (|s|, then Im s; :func:`order`) and their
    shapes q (columns of unit norm, largest entry real and positive), so that a mode's
    motion is Re(q e^(s t)).  Dense: the state matrix by :func:`state_matrix`.

    Raises
    ------
    AnalysisError
        If M is singular or a matrix is not finite.

    Examples
    --------
    >>> G = np.array([[0.0, 1.0], [-1.0, 0.0]])          # a disc's tilts at Ip Omega = 1
    >>> s, q = gyroscopic_modes(np.eye(2), G, np.eye(2))
    >>> s.imag.round(6).tolist()                          # (sqrt(5) -+ 1) / 2
    [0.618034, 1.618034]
    """
    import scipy.linalg

    M, C, K = (dense_matrix(a) for a in (M, C, K))
    require_finite("M, C or K", M, C, K)
    n = M.shape[0]
    try:
        minv = np.linalg.solve(M, np.hstack([K, C]))
    except np.linalg.LinAlgError:
        raise AnalysisError("the mass matrix M is singular: the complex modes need a "
                            "positive definite M") from None
    s, X = scipy.linalg.eig(state_matrix(minv[:, :n], minv[:, n:]))
    return _upper_modes(s, X, n)


def lowest_gyroscopic_modes(M: Matrix, C: Matrix, K: Matrix, count: int,
                            shift: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` complex modes of smallest |s| of a large sparse M q'' + C q' + K q = 0
    (gyroscopic C, unsymmetric K), as :func:`gyroscopic_modes` gives them: the eigenvalues
    with Im s >= 0 in the one order and their unit shapes.

    Shift-invert Arnoldi (:func:`scipy.sparse.linalg.eigs`, a fixed start vector) on the
    pencil [[0, I], [-K, -C]] - s [[I, 0], [0, M]] with one sparse LU; the shift is a small
    negative number (a rigid-body mode makes the pencil singular at 0), or ``shift``.

    Raises
    ------
    AnalysisError
        If the eigensolver does not converge.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> n = 40
    >>> K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    >>> C = 0.01 * sp.identity(n)
    >>> s, q = lowest_gyroscopic_modes(sp.identity(n), C, K, 2)
    >>> dense, _ = gyroscopic_modes(np.eye(n), C.toarray(), K.toarray())
    >>> bool(np.allclose(s, dense[:2], rtol=1e-10)), q.shape
    (True, (40, 2))
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import LinearOperator, eigs, splu

    n = M.shape[0]
    M, C, K = (sp.csc_matrix(a) for a in (M, C, K))
    eye = sp.identity(n, format="csc")
    A = sp.bmat([[None, eye], [-K, -C]], format="csc")
    B = sp.bmat([[eye, None], [None, M]], format="csc")
    scale = float(np.sqrt(abs(K).sum() / max(abs(M).sum(), 1e-300))) or 1.0
    sigma = -1e-3 * scale if shift is None else shift
    wanted = min(2 * count + 6, 2 * n - 2)
    try:
        lu = splu((A - sigma * B).tocsc())
        op = LinearOperator((2 * n, 2 * n), matvec=lambda x: lu.solve(B @ x), dtype=float)
        start = np.random.default_rng(0).standard_normal(2 * n)  # the same every run
        nu, X = eigs(op, k=wanted, which="LM", v0=start)
    except (RuntimeError, ValueError) as exc:
        raise AnalysisError(f"the sparse eigensolver for the complex modes failed: {exc}"
                            ) from None
    s, q = _upper_modes(sigma + 1.0 / nu, X, n)
    return s[:count], q[:, :count]


def gyroscopic_modes_near(M: Matrix, C: Matrix, K: Matrix, target: complex, count: int = 6
                          ) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` complex modes of a sparse M q'' + C q' + K q = 0 whose eigenvalues are
    nearest ``target`` (those with Im s >= 0, in the one order, unit shapes, as
    :func:`gyroscopic_modes`): shift-invert Arnoldi with the complex shift ``target``, so
    that following one branch of a large rotor (a root finder's evaluations) costs a few
    modes, not the lowest dozens.

    Raises
    ------
    AnalysisError
        If the eigensolver does not converge or the shift is an eigenvalue.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> n = 40
    >>> K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    >>> C = 0.01 * sp.identity(n)
    >>> dense, _ = gyroscopic_modes(np.eye(n), C.toarray(), K.toarray())
    >>> s, q = gyroscopic_modes_near(sp.identity(n), C, K, dense[9] + 0.001j, 3)
    >>> bool(np.min(np.abs(s - dense[9])) < 1e-10 * abs(dense[9])), q.shape[0]
    (True, 40)
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigs, splu

    n = M.shape[0]
    M, C, K = (sp.csc_matrix(a) for a in (M, C, K))
    eye = sp.identity(n, format="csc")
    A = sp.bmat([[None, eye], [-K, -C]], format="csc")
    B = sp.bmat([[eye, None], [None, M]], format="csc")
    wanted = max(1, min(count, 2 * n - 2))
    try:
        lu = splu((A - complex(target) * B).astype(complex).tocsc())
        op = LinearOperator((2 * n, 2 * n), matvec=lambda x: lu.solve(B @ x), dtype=complex)
        start = np.random.default_rng(0).standard_normal(2 * n).astype(complex)
        try:
            nu, X = eigs(op, k=wanted, which="LM", v0=start)
        except ArpackNoConvergence:   # a cluster (rigid-body pairs, double modes): more room
            nu, X = eigs(op, k=wanted, which="LM", v0=start,
                         ncv=min(2 * n, max(4 * wanted + 8, 24)))
    except (RuntimeError, ValueError) as exc:
        raise AnalysisError(f"the sparse eigensolver for the complex modes near {target:.6g} "
                            f"failed: {exc}") from None
    return _upper_modes(complex(target) + 1.0 / nu, X, n)


def synchronous_speeds(M: Matrix, G: Matrix, K: Matrix, order: float = 1.0
                       ) -> tuple[np.ndarray, np.ndarray]:
    """The speeds Omega at which an undamped rotor M q'' + Omega G q' + K q = 0 has a mode
    of frequency ``order`` x Omega (its critical speeds of that order, forward and
    backward), and those modes: s = i r Omega turns the equation into the generalized
    eigenproblem K q = Omega^2 (r^2 M - i r G) q, whose real positive eigenvalues are the
    squared critical speeds.  Dense (scipy.linalg.eig); ascending; unit shapes.

    Examples
    --------
    >>> G = np.array([[0.0, 1.0], [-1.0, 0.0]])        # a disc's tilts, Ip = 1, It = 2
    >>> speeds, _ = synchronous_speeds(2 * np.eye(2), G, np.eye(2))
    >>> speeds.round(6).tolist()                         # 1 / sqrt(It -+ Ip)
    [0.57735, 1.0]
    """
    import scipy.linalg

    M, G, K = (dense_matrix(a) for a in (M, G, K))
    require_finite("M, G or K", M, G, K)
    lam, X = scipy.linalg.eig(K.astype(complex), order * order * M - 1j * order * G)
    scale = max(1.0, float(np.nanmax(np.abs(lam[np.isfinite(lam)]), initial=1.0)))
    real = np.isfinite(lam) & (np.abs(lam.imag) <= 1e-9 * scale) & (lam.real > 1e-12 * scale)
    speeds, X = np.sqrt(lam.real[real]), X[:, real]
    index = np.argsort(speeds)
    X = X[:, index]
    norms = np.linalg.norm(X, axis=0)
    return speeds[index], X / np.where(norms > 0, norms, 1.0)


def modal_assurance(A: np.ndarray, B: np.ndarray, weight: Matrix | None = None) -> np.ndarray:
    """The modal assurance criterion |a^H W b|^2 / (a^H W a b^H W b) of every column of A
    against every column of B (complex shapes), shape (columns of A, columns of B); W is
    ``weight`` (the mass matrix: distinct undamped modes are then orthogonal) or I.

    Examples
    --------
    >>> forward, backward = np.array([[1.0], [-1j]]), np.array([[1.0], [1j]])
    >>> modal_assurance(forward, np.hstack([forward, backward])).round(12).tolist()
    [[1.0, 0.0]]
    """
    WB = B if weight is None else np.asarray(weight @ B)
    WA = A if weight is None else np.asarray(weight @ A)
    dot = np.abs(np.conj(A).T @ WB) ** 2
    norms = np.outer(np.abs(np.einsum("ij,ij->j", np.conj(A), WA)),
                     np.abs(np.einsum("ij,ij->j", np.conj(B), WB)))
    with np.errstate(invalid="ignore", divide="ignore"):
        result: np.ndarray = np.where(norms > 0, dot / np.where(norms > 0, norms, 1), 0.0)
    return result


def eigenvalues(A: np.ndarray, B: np.ndarray | None = None) -> np.ndarray:
    """The finite eigenvalues of a dense matrix A (or of the pencil A x = s B x), for a
    system that is not M, C, K: Hill's matrix, a monodromy matrix.

    Examples
    --------
    >>> sorted(eigenvalues(np.array([[0.0, 1.0], [-4.0, 0.0]])).imag.round(12).tolist())
    [-2.0, 2.0]
    >>> eigenvalues(np.eye(2), np.diag([1.0, 0.0])).tolist()
    [(1+0j)]
    """
    import scipy.linalg

    if B is None:
        return np.asarray(np.linalg.eigvals(A))
    lam = scipy.linalg.eig(A, B, right=False)
    return np.asarray(lam[np.isfinite(lam)])


def matrix_polynomial_roots(coefficients: np.ndarray) -> np.ndarray:
    """The roots of a polynomial sum_r a_r z^r with matrix (or scalar) coefficients and
    a_n = I: the eigenvalues of its block companion matrix (the poles of a least-squares
    complex-frequency fit, :mod:`resonant.analyses.identify`).

    Parameters
    ----------
    coefficients : ndarray
        (n + 1,) scalars or (n + 1, p, p) matrices a_0 ... a_n, lowest order first; a_n is
        the identity (or 1).

    Returns
    -------
    ndarray
        The n p roots (complex).

    Examples
    --------
    >>> sorted(matrix_polynomial_roots(np.array([2.0, -3.0, 1.0])).real.round(12).tolist())
    [1.0, 2.0]
    """
    a = np.asarray(coefficients)
    if a.ndim == 1:
        a = a[:, None, None]
    n, p = a.shape[0] - 1, a.shape[1]
    if n < 1:
        return np.zeros(0, dtype=complex)
    companion = np.zeros((n * p, n * p), dtype=a.dtype)
    companion[p:, :-p] = np.eye((n - 1) * p)
    companion[:, -p:] = -np.concatenate([a[r] for r in range(n)], axis=0)
    return np.asarray(np.linalg.eigvals(companion.T).astype(complex))


def fundamental_strip(exponents: np.ndarray, count: int) -> np.ndarray:
    """The ``count`` Floquet exponents of smallest |Im s| (the fundamental strip, where
    Hill's method and the monodromy matrix give each exponent once), in that order.

    Examples
    --------
    >>> fundamental_strip(np.array([-1 + 3j, -1 + 0.5j, -1 - 0.5j]), 2).tolist()
    [(-1+0.5j), (-1-0.5j)]
    """
    strip = np.argsort(np.abs(exponents.imag), kind="stable")
    return np.asarray(exponents[strip[:count]])


def factor_stiffness(K: Matrix, M: Matrix, top: float) -> Any:
    """A sparse LU of K, or of K + (1e-3 top)^2 M where K is singular (a free body).

    Examples
    --------
    >>> lu = factor_stiffness(np.diag([2.0, 0.0]), np.eye(2), 10.0)   # K + 1e-4 M
    >>> lu.solve(np.ones(2)).round(6).tolist()
    [0.499975, 10000.0]
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    try:
        return splu(sp.csc_matrix(K))
    except RuntimeError:
        return splu(sp.csc_matrix(K + (1e-3 * top) ** 2 * M))


def modes_below(K: Matrix, M: Matrix, lu: Any, cut: float, limit: int,
                deadline: Deadline = NO_DEADLINE) -> np.ndarray:
    """The M-orthonormal modes with omega <= cut (shift-invert Lanczos about 0 with the
    factorization ``lu`` of :func:`factor_stiffness`), at most ``limit`` of them; the
    count asked of Lanczos doubles from 16 until the cut is passed, ``deadline`` checked
    at every Lanczos step (400 modes of a 20,000-coordinate chain took 48 s in six runs).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> K = sp.diags([1.0, 4.0, 9.0, 16.0, 25.0], format="csc")
    >>> phi = modes_below(K, sp.identity(5), factor_stiffness(K, sp.identity(5), 1.0), 2.5, 8)
    >>> phi.shape
    (5, 2)
    """
    from scipy.sparse.linalg import LinearOperator, eigsh

    n = K.shape[0]
    k = min(n - 2, 16)

    def solve(x: np.ndarray) -> np.ndarray:   # Lanczos' every step: the deadline too
        deadline.check(f"while computing {k} modes below {cut:.4g} rad/s", analysis=True)
        return np.asarray(lu.solve(x))

    op = LinearOperator(K.shape, matvec=solve, dtype=float)
    while True:
        vals, phi = eigsh(K, k=k, M=M, sigma=0.0, OPinv=op)
        if vals.max() > cut * cut or k >= min(n - 2, limit):
            return np.asarray(phi[:, vals <= cut * cut])
        k = min(2 * k, n - 2, limit)


__all__ = ["ZERO_EIGENVALUE", "ZERO_STATE", "STABILITY_TOLERANCE", "undamped_eigen",
           "undamped_lambdas", "cholesky_lambdas", "general_lambdas", "pencil_roots_2x2",
           "clean_zeros", "frequencies_from_eigenvalues", "natural_frequency",
           "state_eigenvalues", "state_matrix", "quadratic_eigenvalues", "order", "unstable",
           "marginal", "clean_state_zeros", "damping_ratios", "damping_ratio",
           "unstable_by_inertia", "singular_mass", "symmetric_stack", "undamped_eigenvalues",
           "require_finite", "largest_abs", "largest_entry", "accurate_product",
           "eigenvalue_bounds", "frequency_bounds", "lowest_modes", "mass_normalized_modes",
           "symmetric_eigenvalues", "point_state_eigenvalues", "state_modes",
           "lowest_state_eigenvalues", "StateSearch", "overdamped", "lowest_by_frequency",
           "REAL_TOLERANCE", "gyroscopic_modes", "lowest_gyroscopic_modes",
           "gyroscopic_modes_near", "synchronous_speeds",
           "modal_assurance", "eigenvalues", "fundamental_strip", "factor_stiffness",
           "modes_below", "matrix_polynomial_roots"]
