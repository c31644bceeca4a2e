"""Natural frequencies and stability from M, C, K (the numeric core of ``modes``).

Examples
--------
>>> import numpy as np
>>> M, K = np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]])
>>> np.round(natural_frequencies(M, K), 6)
array([1.      , 1.732051])
>>> from resonant.modal import point_state_eigenvalues
>>> classify(point_state_eigenvalues(M, np.zeros((2, 2)), K))
'marginally stable'
"""

from __future__ import annotations

import math

import numpy as np

from ..arrays import Matrix
from ..errors import AnalysisError
from ..modal import (
    clean_zeros,
    frequencies_from_eigenvalues,
    marginal,
    symmetric_eigenvalues,
    undamped_eigen,
    undamped_eigenvalues,
    unstable,
)

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
    eig = symmetric_eigenvalues(M)
    if eig[0] >= 0:
        return None
    kind = "negative definite" if eig[-1] < 0 else "indefinite (not positive definite)"
    return (f"the mass matrix M is {kind} (eigenvalues from {eig[0]:.4g} to {eig[-1]:.4g}): "
            "a negative mass or inertia, so the kinetic energy is not positive; the natural "
            "frequencies and the results are not physical (check the signs in T or M)")


def natural_frequencies(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Undamped natural angular frequencies in rad/s, ascending (stable modes only)."""
    return frequencies_from_eigenvalues(undamped_eigen(M, K)[0])


def classify(eigenvalues: np.ndarray) -> str:
    """Stability of x' = A x from the eigenvalues of A (the modal kernel's tolerance).

    Zero eigenvalues (rigid-body modes) count as marginal.
    """
    if eigenvalues.size == 0:
        return ASYMPTOTIC
    if unstable(eigenvalues):
        return UNSTABLE
    return MARGINAL if marginal(eigenvalues) else ASYMPTOTIC


def _definite(a: Matrix) -> bool:
    """Whether a dense symmetric matrix is positive definite by a margin above its round-off:
    a Cholesky factor of ``a - tau I``, tau = 10 n eps max|a| (a rigid-body mode's computed
    eigenvalue, of the order of eps max|a|, does not pass)."""
    if not isinstance(a, np.ndarray) or a.ndim != 2 or a.size == 0 or not is_symmetric(a) \
            or not np.all(np.isfinite(a)):
        return False
    tau = 10 * a.shape[0] * np.finfo(float).eps * float(np.abs(a).max())
    try:
        np.linalg.cholesky(a - tau * np.eye(a.shape[0]))
    except np.linalg.LinAlgError:
        return False
    return True


def stiffness_eigenvalues(lam: np.ndarray, K: Matrix) -> np.ndarray:
    """The eigenvalues omega^2 of K x = omega^2 M x with round-off zeros set to 0
    (:func:`~resonant.modal.clean_zeros`), unless K is positive definite above its round-off
    (then none is zero: a soft mode below 1e-12 of the stiffest one, beside a stiff link, was
    shown as a rigid-body mode of 0 rad/s).

    Examples
    --------
    >>> K = np.array([[1e13 + 1, -1e13], [-1e13, 1e13]])
    >>> lam = undamped_eigen(np.eye(2), K)[0]
    >>> float(clean_zeros(lam)[0]), round(float(stiffness_eigenvalues(lam, K)[0]), 2)
    (0.0, 0.5)
    """
    return np.asarray(lam, dtype=float) if _definite(K) else clean_zeros(lam)


def stability(eigenvalues: np.ndarray, M: Matrix, C: Matrix, K: Matrix) -> str:
    """:func:`classify`, with the definite case decided exactly: symmetric M, C and K that are
    all positive definite make every eigenvalue's real part negative (Thomson and Tait's
    theorem: x^H (s^2 M + s C + K) x = 0 has roots with Re s < 0), however small the damping
    ratios are against the eigenvalues' tolerance (a soft mode beside a stiff one: Re s of
    the soft one is below 1e-9 of the largest |s|, and was called marginally stable).

    Examples
    --------
    >>> from resonant.modal import point_state_eigenvalues
    >>> M, C, K = np.eye(2), 1e-3 * np.eye(2), np.array([[1e13 + 500, -1e13], [-1e13, 1e13]])
    >>> s = point_state_eigenvalues(M, C, K)
    >>> classify(s), stability(s, M, C, K)
    ('marginally stable', 'asymptotically stable')
    """
    verdict = classify(eigenvalues)
    if verdict == MARGINAL and all(_definite(a) for a in (M, C, K)):
        return ASYMPTOTIC
    return verdict


def rayleigh(M: Matrix, C: Matrix, K: Matrix) -> tuple[float, float] | None:
    """(a, b) with C = a M + b K to relative accuracy 1e-9, else None."""
    def dot(x: Matrix, y: Matrix) -> float:
        if isinstance(x, np.ndarray):
            return float(np.sum(x * y))
        return float(x.multiply(y).sum())

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



__all__ = ["natural_frequencies", "frequencies_from_eigenvalues", "undamped_eigen",
           "classify", "stability", "stiffness_eigenvalues", "undamped_eigenvalues", "rayleigh",
           "check_mass_matrix",
           "is_symmetric", "ASYMPTOTIC", "MARGINAL", "UNSTABLE"]
