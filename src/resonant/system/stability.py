"""Natural frequencies and stability from M, C, K (the numeric core of ``modes``).

Examples
--------
>>> import numpy as np
>>> M, K = np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]])
>>> np.round(natural_frequencies(M, K), 6)
array([1.      , 1.732051])
>>> classify(state_eigenvalues(M, np.zeros((2, 2)), K))
'marginally stable'
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import AnalysisError

#: relative tolerance of the proportional-damping and Rayleigh tests
PROPORTIONAL_TOLERANCE = 1e-9

ASYMPTOTIC = "asymptotically stable"
MARGINAL = "marginally stable"
UNSTABLE = "unstable"


def is_symmetric(a: np.ndarray, rtol: float = 1e-12) -> bool:
    return bool(np.allclose(a, a.T, rtol=rtol, atol=rtol * (np.abs(a).max() if a.size else 0)))


def check_mass_matrix(M: np.ndarray, names: tuple[str, ...] = ()) -> None:
    """Raise AnalysisError (exit 3) if M is singular; name the massless coordinate."""
    if M.size == 0:
        return
    s = np.linalg.svd(M, compute_uv=False)
    if s[-1] <= 1e-13 * s[0] or s[0] == 0:
        # a zero row names the coordinate with no inertia
        empty = [names[i] if i < len(names) else f"q{i + 1}"
                 for i in range(M.shape[0]) if not np.any(M[i])]
        which = f" ({', '.join(empty)} has no inertia)" if empty else ""
        raise AnalysisError(
            f"the mass matrix M is singular{which}: every coordinate needs mass or inertia "
            "(a zero mass, or a coordinate that does not appear in T?)")


def mass_warning(M: np.ndarray) -> str | None:
    """A warning naming M when the (dense, symmetric) mass matrix is not positive definite.

    Examples
    --------
    >>> mass_warning(-np.eye(2))[:40]
    'the mass matrix M is negative definite ('
    >>> mass_warning(np.eye(2)) is None
    True
    """
    if M.size == 0 or M.ndim != 2 or not np.all(np.isfinite(M)) or not np.allclose(M, M.T):
        return None
    eig = np.linalg.eigvalsh(M)
    if eig[0] >= 0:
        return None
    kind = "negative definite" if eig[-1] < 0 else "indefinite (not positive definite)"
    return (f"the mass matrix M is {kind} (eigenvalues from {eig[0]:.4g} to {eig[-1]:.4g}): "
            "a negative mass or inertia, so the kinetic energy is not positive; the natural "
            "frequencies and the results are not physical (check the signs in T or M)")


def _require_finite(what: str, *arrays: np.ndarray) -> None:
    """AnalysisError (exit 3) instead of a LinAlgError or NaN results further on."""
    if not all(np.all(np.isfinite(a)) for a in arrays):
        raise AnalysisError(
            f"{what} is not finite: the parameter values span too many orders of magnitude "
            "(an overflow to infinity); use units in which the masses and stiffnesses are "
            "nearer to 1")


def undamped_eigen(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues lambda = omega^2 (ascending) and mode shapes (columns) of K x = lambda M x."""
    import scipy.linalg  # not at import: a study of a small model needs no scipy

    _require_finite("M or K", M, K)
    if is_symmetric(M) and is_symmetric(K):
        try:
            lam, vec = scipy.linalg.eigh(K, M)
            _require_finite("an eigenvalue K x = lambda M x", lam)
            return lam, vec
        except np.linalg.LinAlgError:
            pass  # M not positive definite: fall back to the general problem
    with np.errstate(all="ignore"):
        lam, vec = scipy.linalg.eig(K, M)
    _require_finite("an eigenvalue K x = lambda M x", lam)
    order = np.argsort(lam.real)
    return lam[order].real, vec[:, order].real


def frequencies_from_eigenvalues(lam: np.ndarray) -> np.ndarray:
    """sqrt of the eigenvalues lambda = omega^2 that are >= 0 (round-off zeros count as 0)."""
    scale = max(float(np.abs(lam).max(initial=0.0)), 1e-300)
    lam = np.where(np.abs(lam) < 1e-12 * scale, 0.0, lam)
    return np.sqrt(lam[lam >= 0])


def natural_frequencies(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Undamped natural angular frequencies in rad/s, ascending (stable modes only)."""
    return frequencies_from_eigenvalues(undamped_eigen(M, K)[0])


def state_matrix(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> np.ndarray:
    """A = [[0, I], [-M^-1 K, -M^-1 C]] of x' = A x with x = [q, q']."""
    n = M.shape[0]
    minv_k = np.linalg.solve(M, K)
    minv_c = np.linalg.solve(M, C)
    _require_finite("the state matrix (M^-1 K, M^-1 C)", minv_k, minv_c)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-minv_k, -minv_c]])


def state_eigenvalues(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> np.ndarray:
    return np.linalg.eigvals(state_matrix(M, C, K))


def classify(eigenvalues: np.ndarray) -> str:
    """Stability of x' = A x from the eigenvalues of A.

    Zero eigenvalues (rigid-body modes) count as marginal.
    """
    if eigenvalues.size == 0:
        return ASYMPTOTIC
    scale = max(1.0, float(np.abs(eigenvalues).max()))
    tol = 1e-9 * scale
    re = eigenvalues.real
    if np.any(re > tol):
        return UNSTABLE
    if np.all(re < -tol):
        return ASYMPTOTIC
    return MARGINAL


def undamped_eigenvalues(M: Any, K: Any) -> np.ndarray:
    """omega^2 of K x = omega^2 M x, ascending, without eigenvectors.

    A diagonal M and a banded symmetric K use LAPACK's banded symmetric
    eigensolver on M^-1/2 K M^-1/2 (cost n b^2); anything else the dense one.
    """
    import scipy.linalg

    Md, Kd = (a.toarray() if hasattr(a, "toarray") else np.asarray(a, dtype=float)
              for a in (M, K))
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
        return scipy.linalg.eig_banded(band, lower=True, eigvals_only=True)
    try:
        return scipy.linalg.eigh(Kd, Md, eigvals_only=True)
    except (np.linalg.LinAlgError, ValueError):
        return np.sort(scipy.linalg.eigvals(Kd, Md).real)


def rayleigh(M: Any, C: Any, K: Any) -> tuple[float, float] | None:
    """(a, b) with C = a M + b K to relative accuracy 1e-9, else None."""
    def dot(x: Any, y: Any) -> float:
        return float(x.multiply(y).sum()) if hasattr(x, "tocsr") else float(np.sum(x * y))

    gram = np.array([[dot(M, M), dot(M, K)], [dot(K, M), dot(K, K)]])
    rhs = np.array([dot(M, C), dot(K, C)])
    if np.linalg.cond(gram) > 1e12:  # K proportional to M (one coordinate): take C = a M
        a, b = rhs[0] / gram[0, 0], 0.0
    else:
        a, b = np.linalg.solve(gram, rhs)
    size_c = math.sqrt(max(dot(C, C), 1e-300))
    # terms below the tolerance are rounding noise of an exact zero
    if abs(a) * math.sqrt(gram[0, 0]) <= PROPORTIONAL_TOLERANCE * size_c:
        a = 0.0
    if abs(b) * math.sqrt(gram[1, 1]) <= PROPORTIONAL_TOLERANCE * size_c:
        b = 0.0
    residual = C - a * M - b * K
    if math.sqrt(max(dot(residual, residual), 0.0)) <= PROPORTIONAL_TOLERANCE * size_c:
        return float(a), float(b)
    return None



__all__ = ["natural_frequencies", "frequencies_from_eigenvalues", "undamped_eigen", "state_matrix",
           "state_eigenvalues", "classify", "undamped_eigenvalues", "rayleigh", "check_mass_matrix",
           "is_symmetric", "ASYMPTOTIC", "MARGINAL", "UNSTABLE"]
