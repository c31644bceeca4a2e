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

import numpy as np
import scipy.linalg

from .errors import AnalysisError

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


def _require_finite(what: str, *arrays: np.ndarray) -> None:
    """AnalysisError (exit 3) instead of a LinAlgError or NaN results further on."""
    if not all(np.all(np.isfinite(a)) for a in arrays):
        raise AnalysisError(
            f"{what} is not finite: the parameter values span too many orders of magnitude "
            "(an overflow to infinity); use units in which the masses and stiffnesses are "
            "nearer to 1")


def undamped_eigen(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues lambda = omega^2 (ascending) and mode shapes (columns) of K x = lambda M x."""
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


__all__ = ["natural_frequencies", "frequencies_from_eigenvalues", "undamped_eigen", "state_matrix", "state_eigenvalues",
           "classify", "check_mass_matrix", "is_symmetric", "ASYMPTOTIC", "MARGINAL", "UNSTABLE"]
