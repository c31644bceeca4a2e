"""The forward error of the kernel's solves, and the one warning where digits are gone.

Every exact solve of :func:`resonant.analyses.kernel.solve_harmonic` is followed by one
step of iterative refinement that is *not* applied: the residual
``r = b - A x`` of the computed ``x`` and the correction ``d = A^-1 r`` from the same
factorization.  ``||d|| / ||x||`` (infinity norms over all coordinates) estimates the
relative forward error of ``x`` (Higham, *Accuracy and Stability of Numerical
Algorithms*, 2nd ed., 2002, ch. 12).  The residual is computed in double precision
from the matrix the solve used, so its own rounding (of the order u |A| |x|) is that of
a perturbation of the matrix at the level of its last digit: the estimate is the error
of the answer against the model as the matrices hold it to double precision, of the
order of the Oettli-Prager/Skeel bound ``u || |A^-1| |A| |x| || / ||x||`` -- small where
only the normwise condition number is large (a stiff spring in series with a soft one),
large where the rounding really reaches the answer (a fine beam mesh near its first
resonance, a stiff spring between two softly held masses).  The lower bound of the
condition number the kernel kept before (``||A|| ||x|| / ||b||``) could not tell these
apart.

The cost is one residual and one solve with an existing factorization per point
(docs/performance.md measures it).  :func:`accuracy_warning` is the one message the
sweep, the stationary solution and the random response give where fewer than
:data:`DIGITS_WANTED` digits are left.

Examples
--------
>>> import numpy as np
>>> K, M, C = np.array([[2.0, 1.0], [1.0, 3.0]]), np.eye(2), np.zeros((2, 2))
>>> b = np.array([1.0, 2.0])
>>> A = K - M                                    # at w = 1
>>> x = np.linalg.solve(A, b)
>>> d = np.linalg.solve(A, Residuals(K, M, C).double(1.0, x, b))
>>> bool(relative_error(d, x) < 1e-15)
True
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..arrays import Matrix

#: digits an answer must keep before a warning says it may be wrong
DIGITS_WANTED = 3
#: ... that is, the largest estimated relative forward error without a warning
ERROR_LIMIT = 10.0 ** -DIGITS_WANTED
#: a point whose double-precision estimate exceeds this gets the extended-precision one
#: (the double residual's own rounding makes its estimate noisy: in tests it fell up to
#: 1000 times below the true error, never 10^5 times)
EXTENDED_ABOVE = 1e-8


class Residuals:
    """``b - (K - w^2 M + i w C) x`` of one system from its three matrices.

    Computed from K, M and C separately (never from the matrix a solve formed, whose
    own rounding is part of the error to find): :meth:`double` in double precision,
    one sparse product of the stacked matrices (cheap; its rounding is of the order of
    the error it measures, so its estimate is a screen), :meth:`extended` in
    ``numpy.longdouble`` (64-bit mantissa on x86: 2^11 times finer than double; where
    ``longdouble`` is double, the estimate keeps the screen's accuracy).

    Parameters
    ----------
    K, M, C : ndarray or scipy.sparse matrix
        (n, n), fixed.

    Examples
    --------
    >>> K, M, C = np.array([[2.0, -1.0], [-1.0, 1.0]]), np.eye(2), 0.1 * np.eye(2)
    >>> x = np.linalg.solve(K - 4 * M + 2j * C, [1.0, 0.0])
    >>> res = Residuals(K, M, C)
    >>> bool(np.abs(res.double(2.0, x, np.array([1.0, 0.0]))).max() < 1e-15)
    True
    """

    def __init__(self, K: Matrix, M: Matrix, C: Matrix) -> None:
        import scipy.sparse as sp

        self.n = K.shape[0]
        self.stacked = sp.csr_matrix(sp.vstack([sp.csr_matrix(a) for a in (K, M, C)]))
        self._extended: tuple[Any, ...] | None = None

    def double(self, w: float, x: np.ndarray, b: np.ndarray) -> np.ndarray:
        """The residual in double precision."""
        n = self.n
        with np.errstate(all="ignore"):
            P = self.stacked @ np.stack([x.real, x.imag], axis=1)
            Kx, Mx, Cx = (P[k * n:(k + 1) * n, 0] + 1j * P[k * n:(k + 1) * n, 1]
                          for k in range(3))
            return np.asarray(b - Kx + (w * w) * Mx - (1j * w) * Cx)

    def extended(self, w: float, x: np.ndarray, b: np.ndarray) -> np.ndarray:
        """The residual in extended precision (rounded to complex double at the end)."""
        if self._extended is None:
            S = self.stacked
            rows = np.flatnonzero(np.diff(S.indptr))
            self._extended = (S.data.astype(np.longdouble), S.indices, S.indptr[rows], rows)
        data, indices, starts, rows = self._extended
        n = self.n
        ld = np.longdouble
        W = ld(w)
        out = []
        with np.errstate(all="ignore"):
            for part in (x.real, x.imag):
                y = np.zeros(3 * n, dtype=ld)
                if rows.size:
                    y[rows] = np.add.reduceat(data * part.astype(ld)[indices], starts)
                out.append(y)
            (yr, yi) = out
            Kr, Mr, Cr = yr[:n], yr[n:2 * n], yr[2 * n:]
            Ki, Mi, Ci = yi[:n], yi[n:2 * n], yi[2 * n:]
            rr = np.real(b).astype(ld) - Kr + W * W * Mr + W * Ci
            ri = np.imag(b).astype(ld) - Ki + W * W * Mi - W * Cr
            return rr.astype(float) + 1j * ri.astype(float)


def dense_residuals(K: np.ndarray, M: np.ndarray, C: np.ndarray, w: np.ndarray,
                    X: np.ndarray, B: np.ndarray, extended: bool = False) -> np.ndarray:
    """``b - (K - w^2 M + i w C) x`` at N points from the three matrices (each (n, n) or a
    stack (N, n, n)), X and B (N, n); in ``numpy.longdouble`` when ``extended``.

    Examples
    --------
    >>> K, M, C = np.array([[2.0, -1.0], [-1.0, 1.0]]), np.eye(2), np.zeros((2, 2))
    >>> dense_residuals(K, M, C, np.array([1.0]), np.array([[1.0, 1.0]]),
    ...                 np.array([[0.0, 0.0]])).real.tolist()
    [[0.0, 1.0]]
    """
    dtype = np.longdouble if extended else float
    w = np.asarray(w, dtype=dtype)[:, None]
    with np.errstate(all="ignore"):
        products = []
        for a in (K, M, C):
            a = np.asarray(a, dtype=dtype)
            parts = []
            for part in (X.real, X.imag):
                part = part.astype(dtype)
                parts.append(part @ a.T if a.ndim == 2 else np.matmul(a, part[..., None])[..., 0])
            products.append(parts)
        (Kr, Ki), (Mr, Mi), (Cr, Ci) = products
        rr = np.real(B).astype(dtype) - Kr + w * w * Mr + w * Ci
        ri = np.imag(B).astype(dtype) - Ki + w * w * Mi - w * Cr
        residual: np.ndarray = rr.astype(float) + 1j * ri.astype(float)
        return residual


def relative_error(d: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``||d|| / ||x||`` (infinity norms) of one vector or of each row of a stack.

    0 where both are zero; infinite where the correction is not finite or x is zero
    while d is not.

    Examples
    --------
    >>> relative_error(np.array([[1e-3, 0.0], [0.0, 0.0]]), np.array([[2.0, 1.0], [0.0, 0.0]]))
    array([0.0005, 0.    ])
    """
    size_d = np.abs(d).max(axis=-1, initial=0.0)
    size_x = np.abs(x).max(axis=-1, initial=0.0)
    with np.errstate(all="ignore"):
        ratio = np.where(size_d == 0, 0.0, size_d / size_x)
    return np.where(np.isfinite(ratio), ratio, np.inf)


def accuracy_warning(errors: np.ndarray, values: np.ndarray, where: str,
                     skipped: np.ndarray | None = None, what: str = "points") -> str | None:
    """The warning where the estimated forward error leaves fewer than
    :data:`DIGITS_WANTED` digits, or None.

    Parameters
    ----------
    errors : ndarray
        The estimated relative forward error at each point (NaN: not estimated).
    values : ndarray
        The value of each point (a swept parameter, a frequency), to name the range.
    where : str
        How a value is named: ``"omega = {:.6g}"`` or ``"f = {:.6g} Hz"``.
    skipped : ndarray of bool, optional
        Points that have no answer (skipped, said elsewhere).
    what : str
        What the points are ("points", "frequencies").

    Returns
    -------
    str or None

    Examples
    --------
    >>> text = accuracy_warning(np.array([1e-9, 0.2, 0.02]), np.array([1.0, 2.0, 3.0]),
    ...                         "omega = {:.6g}")
    >>> print(text[:96])
    fewer than 3 correct digits at 2 of 3 points (omega = 2 to omega = 3): the estimated relative
    """
    errors = np.asarray(errors, dtype=float)
    with np.errstate(invalid="ignore"):
        lost = errors > ERROR_LIMIT
    if skipped is not None:
        lost &= ~skipped
    if not lost.any():
        return None
    picked = values[lost]
    worst = int(np.flatnonzero(lost)[np.argmax(np.where(np.isfinite(errors[lost]),
                                                        errors[lost], np.inf))])
    error = float(errors[worst])
    left = max(0, int(math.floor(-math.log10(error)))) if 0 < error < math.inf else 0
    size = "no digit" if left == 0 else f"about {left} digit{'s' if left > 1 else ''}"
    span = (where.format(picked.min()) if picked.min() == picked.max() else
            f"{where.format(picked.min())} to {where.format(picked.max())}")
    return (f"fewer than {DIGITS_WANTED} correct digits at {int(lost.sum())} of {len(values)} "
            f"{what} ({span}): the estimated relative error of the solve reaches "
            f"{error:.2g} at {where.format(values[worst])} ({size} left); the values there may "
            "be wrong. The cause is the conditioning of the dynamic stiffness, not a "
            "resonance: a fine mesh, or stiffnesses or units many orders of magnitude apart; "
            "coarsen the mesh or rescale the model")


__all__ = ["Residuals", "EXTENDED_ABOVE", "dense_residuals", "relative_error",
           "accuracy_warning", "ERROR_LIMIT", "DIGITS_WANTED"]
