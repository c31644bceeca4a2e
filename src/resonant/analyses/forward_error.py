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

The cost is one residual and one solve with an existing factorization per estimated
point, as much as the solve itself for a banded system.  So not every point of a sweep
is estimated (:class:`Sampling`): every :data:`STRIDE`-th point and the last; every point
whose a-priori screen -- ``u ||A|| ||x|| / ||b||``, the unit roundoff times a lower bound
of the condition number -- exceeds :data:`SCREEN_ABOVE`; and,
once an estimate exceeds :data:`ALERT` (a thousand times below the warning), every point
after it and every point skipped since the previous estimate, until an estimate falls
below :data:`ALERT` again.  A point left out (NaN) lies between two estimated points
with at least six digits each, and its screen says nothing is lost: three more digits
lost there would need a direction the load does not excite turning a thousand times
worse within :data:`STRIDE` points (docs/sweeps.md).  docs/performance.md measures the
cost.  :func:`accuracy_warning` is the one message the sweep, the stationary solution
and the random response give where fewer than :data:`DIGITS_WANTED` digits are left.

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
from collections.abc import Callable
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
#: the unit roundoff of double precision
UNIT_ROUNDOFF = float(np.finfo(float).eps) / 2
#: every STRIDE-th point of a sweep is estimated (and the last) ...
STRIDE = 16
#: ... and every point while the estimates exceed this (a thousand times below
#: :data:`ERROR_LIMIT`), with the points skipped before the first of them ...
ALERT = 1e-3 * ERROR_LIMIT
#: ... and every point whose a-priori screen ``u ||A|| ||x|| / ||b||`` (u times a lower
#: bound of the condition number) exceeds this: fewer than six digits could remain (it
#: fell up to 1,200 times below the estimate in docs/performance.md's sweeps, in chains
#: of 10,000 masses that kept nine digits; at most 40 times in the others)
SCREEN_ABOVE = 1e-6


class Sampling:
    """Which points of a sweep get the forward-error estimate (the module docstring).

    Parameters
    ----------
    errors : ndarray
        (N,), NaN: filled with the estimates, NaN where a point is left out.
    scale : ndarray
        (N,): ``||A|| / ||b||`` at each point (infinity norms); times ``||x||`` the
        lower bound of the condition number the screen uses.

    Examples
    --------
    >>> sampling = Sampling(np.full(40, np.nan), np.ones(40))
    >>> for i in range(40):
    ...     sampling.point(i, 1.0, lambda: 1e-12, lambda j: 1e-12)
    >>> np.flatnonzero(np.isfinite(sampling.errors)).tolist()
    [0, 16, 32, 39]
    >>> sampling = Sampling(np.full(40, np.nan), np.ones(40))
    >>> for i in range(40):   # an estimate above ALERT: every point, skipped ones too
    ...     sampling.point(i, 1.0, lambda: 1e-5 if i >= 16 else 1e-12, lambda j: 2e-5)
    >>> int(np.isfinite(sampling.errors).sum()), float(sampling.errors[3])
    (40, 2e-05)
    """

    def __init__(self, errors: np.ndarray, scale: np.ndarray) -> None:
        self.errors = errors
        with np.errstate(all="ignore"):
            self.screen = UNIT_ROUNDOFF * np.asarray(scale, dtype=float)
        self._screen = self.screen.tolist()   # (point by point: without numpy's overhead)
        self.last = len(errors) - 1
        self.alert = False
        self.skipped: list[int] = []

    def wanted(self, points: np.ndarray, sizes: np.ndarray) -> np.ndarray:
        """Which of ``points`` (their ``||x||``: ``sizes``) the rule estimates now."""
        with np.errstate(all="ignore"):
            screened = ~(self.screen[points] * sizes <= SCREEN_ABOVE)
        return np.asarray(self.alert | (points % STRIDE == 0)
                          | (points == self.last) | screened)

    def point(self, i: int, size: float, estimate: Callable[[], float],
              revisit: Callable[[int], float]) -> None:
        """Point ``i`` (``||x||``: ``size``), solved: ``estimate()`` its error if the rule
        wants it; ``revisit(j)`` the error of a skipped point j (solved again)."""
        if not (self.alert or i % STRIDE == 0 or i == self.last
                or not self._screen[i] * size <= SCREEN_ABOVE):
            self.skipped.append(i)
            return
        self.errors[i] = error = estimate()
        self.alert = bool(error > ALERT)
        if self.alert:
            for j in self.skipped:
                self.errors[j] = revisit(j)
        self.skipped = []

    def chunk(self, points: np.ndarray, sizes: np.ndarray,
              estimate: Callable[[np.ndarray], np.ndarray]) -> None:
        """Points solved together (a dense chunk): ``estimate(at)`` the errors of the
        chunk's rows ``at``; every row when one of them exceeds :data:`ALERT`."""
        want = self.wanted(points, sizes)
        rows = np.arange(points.size)
        self.errors[points[want]] = estimate(rows[want])
        if not want.all() and bool(np.any(self.errors[points[want]] > ALERT)):
            self.errors[points[~want]] = estimate(rows[~want])
        self.alert = bool(np.any(self.errors[points] > ALERT))


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
        self._complex: Any = None

    def double(self, w: float, x: np.ndarray, b: np.ndarray) -> np.ndarray:
        """The residual in double precision."""
        n = self.n
        if self._complex is None:   # (a real entry times a complex one rounds as in reals)
            self._complex = self.stacked.astype(complex)
        with np.errstate(all="ignore"):
            P = self._complex @ np.asarray(x, dtype=complex)
            residual = b - P[:n]
            residual += (w * w) * P[n:2 * n]
            residual -= (1j * w) * P[2 * n:]
            return np.asarray(residual)

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
    >>> print(text[:93])
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


__all__ = ["Residuals", "Sampling", "STRIDE", "ALERT", "SCREEN_ABOVE", "UNIT_ROUNDOFF",
           "EXTENDED_ABOVE", "dense_residuals", "relative_error",
           "accuracy_warning", "ERROR_LIMIT", "DIGITS_WANTED"]
