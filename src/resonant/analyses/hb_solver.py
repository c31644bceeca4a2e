"""The harmonic-balance equations of a :class:`~resonant.system.NonlinearSystem`.

For H harmonics of the base frequency W, in the time tau = W t::

    q(tau) = q_ref + a_0 + sum_{k=1..H} a_k cos(k tau) + b_k sin(k tau)

**Residual** by the alternating frequency-time method: q, q' = W dq/dtau and
q'' = W^2 d^2q/dtau^2 are sampled at N >= 4H + 4 (at least 32) points of one
period, the system's compiled equations E are evaluated there, and their first
H harmonics are taken with :func:`numpy.fft.rfft`.

**Jacobian** exact: from the system's dE/dq, dE/dq', dE/dq'' by the chain rule
through the Fourier basis, ``dR/dx = P [G0 Phi + W G1 Phi' + W^2 G2 Phi'']``
(P the projection, Phi the sampled basis).  Only the derivative with respect
to the continuation parameter is a central finite difference.

**Stability** by Hill's method (:meth:`HarmonicBalance.exponents`): the
quadratic eigenvalue problem ``(D0 + lambda D1 + lambda^2 D2) v = 0`` with
``D0`` the Jacobian, ``D1 = Gal(G1 + 2 W G2 d/dtau)``, ``D2 = Gal(G2)``; the 2n
eigenvalues with the smallest |Im lambda| are the Floquet exponents.

Examples
--------
>>> from resonant.model import loads
>>> from resonant.system import nonlinear_system
>>> system = nonlinear_system(loads('''
... [parameters]
... w = 2
... [coordinates]
... x = ""
... [signals]
... F = "cos(w*t)"
... [energy]
... T = "x'^2/2"
... U = "x^2/2"
... [[force]]
... generalized = { x = "F" }
... '''))
>>> hb = HarmonicBalance(system, "w", 1)
>>> x, ok = hb.newton(np.zeros(3), 2.0, 1.0)
>>> ok, np.round(x, 12).tolist() == [0.0, -0.333333333333, 0.0]  # x = cos(2t) / (1 - 4)
(True, True)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import AnalysisError
from ..modal import fundamental_strip, quadratic_eigenvalues
from ..system.nonlinear import NonlinearSystem
from .peaks import GRID, periodic_peak, series_peaks

#: the automatic choice of H (every balance that chooses H, full or condensed, shares it):
#: start at DEFAULT_HARMONICS, raise by HARMONICS_STEP while the highest harmonics carry more
#: than TRUNCATION_TOL of the amplitude (:func:`truncation`), at most MAX_HARMONICS
DEFAULT_HARMONICS = 7
TRUNCATION_TOL = 1e-6
HARMONICS_STEP = 4
MAX_HARMONICS = 40

#: Newton: relative step size that ends the iteration, and its iteration limit
NEWTON_TOL = 1e-11
NEWTON_MAX = 12
#: a converged point's residual, relative to the size of the equations' terms (polish below)
RESIDUAL_TOL = 1e-13


class HarmonicBalance:
    """Residual, Jacobian and Hill matrices for H harmonics and one continuation parameter.

    Parameters
    ----------
    system : NonlinearSystem
    param : str
        The continuation parameter.
    H : int
        Number of harmonics.
    free : bool
        The free, undamped system (backbone curves): no forcing, the dissipation off, the
        base frequency given to :meth:`evaluate`.
    """

    def __init__(self, system: NonlinearSystem, param: str, H: int, free: bool = False,
                 reference: np.ndarray | None = None) -> None:
        if param not in system.parameters:
            raise AnalysisError(f"'{param}' is not a parameter of the model (parameters: "
                                f"{', '.join(system.parameters)})")
        self.system, self.H, self.n, self.param, self.free = system, H, system.n, param, free
        self.reference = system.reference(system.parameter_values) if reference is None \
            else reference
        self.m = 2 * H + 1
        self.N = N = max(32, 4 * H + 4)
        self.tau = tau = 2 * np.pi * np.arange(N) / N
        self.phi, self.dphi, self.d2phi = basis(tau, H)
        k = np.arange(1, H + 1)
        c, s = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
        P = np.empty((self.m, N))
        P[0] = 1.0 / N
        P[1::2], P[2::2] = 2.0 / N * c.T, 2.0 / N * s.T
        self.P = P
        self._zero_forcing = np.zeros((system.forcing_size, N))
        self._grid = 2 * np.pi * np.arange(GRID) / GRID
        self._grid_basis = basis(self._grid, H)

    def pvals(self, p: float) -> np.ndarray:
        return self.system.parameter_point(self.param, p)

    def evaluate(self, X: np.ndarray, W: float, pv: np.ndarray, damping: float = 1.0
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """E, dE/dq, dE/dq', dE/dq'' at the samples of the series X (n, m) at frequency W."""
        q = self.reference[:, None] + X @ self.phi.T
        qd = W * (X @ self.dphi.T)
        qdd = W * W * (X @ self.d2phi.T)
        s = self._zero_forcing if self.free else self.system.forcing(self.tau / W, pv)
        return self.system.equations(q, qd, qdd, s, pv, damping)

    def samples(self, x: np.ndarray, p: float) -> tuple[Any, ...]:
        pv = self.pvals(p)
        W = self.system.base_frequency(pv)
        return (*self.evaluate(x.reshape(self.n, self.m), W, pv), W)

    def project(self, E: np.ndarray) -> np.ndarray:
        """The first H harmonics ``[c_0, a_1, b_1, ...]`` of each row of samples E, raveled."""
        F = np.fft.rfft(E, axis=1)
        R = np.empty((E.shape[0], self.m))
        N, H = self.N, self.H
        R[:, 0] = F[:, 0].real / N
        R[:, 1::2] = 2.0 / N * F[:, 1:H + 1].real
        R[:, 2::2] = -2.0 / N * F[:, 1:H + 1].imag
        return R.ravel()

    def residual(self, x: np.ndarray, p: float) -> np.ndarray:
        return self.project(self.samples(x, p)[0])

    def galerkin(self, *terms: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
        """Matrix of x -> P sum(G(tau) (basis x)) for (n, n, N) coefficients G."""
        T = sum(G[:, :, :, None] * phi for G, phi in terms)
        B = np.matmul(self.P, T)  # (n, n, m, m): row equation i, harmonic row; column j, k
        size = self.n * self.m
        return np.ascontiguousarray(B.transpose(0, 2, 1, 3)).reshape(size, size)

    def jacobian(self, x: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray, Any]:
        E, G0, G1, G2, W = self.samples(x, p)
        J = self.galerkin((G0, self.phi), (G1, W * self.dphi), (G2, W * W * self.d2phi))
        return self.project(E), J, (G0, G1, G2, W)

    def dp(self, x: np.ndarray, p: float) -> np.ndarray:
        h = 1e-6 * max(1.0, abs(p))
        return np.asarray((self.residual(x, p + h) - self.residual(x, p - h)) / (2 * h))

    def exponents(self, J: np.ndarray, blocks: Any) -> np.ndarray:
        """The 2n Floquet exponents of Hill's method (smallest |Im| of the QEP's)."""
        G0, G1, G2, W = blocks
        D1 = self.galerkin((G1, self.phi), (G2, 2 * W * self.dphi))
        D2 = self.galerkin((G2, self.phi))
        return fundamental_strip(quadratic_eigenvalues(J, D1, D2), 2 * self.n)

    def newton(self, x: np.ndarray, p: float, scale: float) -> tuple[np.ndarray, bool]:
        """Newton's method on R(x, p) = 0 at fixed p (converged: the step below 1e-11)."""
        return newton_at(self.jacobian, x, p, scale)

    def quantities(self, x: np.ndarray, p: float, tau: np.ndarray, outputs: bool = True
                   ) -> np.ndarray:
        """Deviations of the coordinates, then the outputs, at the times tau: (n + o, k)."""
        X = x.reshape(self.n, self.m)
        phi, dphi, d2phi = self._grid_basis if tau is self._grid else basis(tau, self.H)
        dev: np.ndarray = X @ phi.T
        if not (outputs and self.system.outputs):
            return dev
        pv = self.pvals(p)
        W = self.system.base_frequency(pv)
        s = np.zeros((self.system.forcing_size, tau.size)) if self.free else \
            self.system.forcing(tau / W, pv)
        out = self.system.output_values(self.reference[:, None] + dev, W * (X @ dphi.T),
                                        W * W * (X @ d2phi.T), s, pv)
        return np.vstack([dev, *(out[name][None] for name in self.system.outputs)])

    def output_coefficients(self, xs: Sequence[np.ndarray], ps: Sequence[float]) -> np.ndarray:
        """(points, outputs, 2H+1): the first H harmonics of every output's deviation."""
        count = len(self.system.outputs)
        out = np.empty((len(xs), count, self.m))
        with np.errstate(all="ignore"):
            for i, (x, p) in enumerate(zip(xs, ps)):
                out[i] = self.project(self.quantities(x, p, self.tau)[self.n:]).reshape(
                    count, self.m)
        return out

    def names(self) -> tuple[str, ...]:
        """The coordinates and the outputs, the rows of :meth:`quantities`."""
        return (*self.system.coordinates, *self.system.outputs)

    def amplitudes(self, x: np.ndarray, p: float, outputs: bool = True) -> np.ndarray:
        """Peak |deviation| over one period of every coordinate and (``outputs``) output,
        located to rounding."""
        return np.asarray(self.amplitudes_of([x], [p], outputs)[0])

    def amplitude(self, x: np.ndarray, p: float, j: int) -> float:
        """The amplitude of quantity ``j`` of :meth:`names`: a coordinate's from its own
        series, an output's with the others."""
        if j < self.n:
            series = np.reshape(np.asarray(x, dtype=float), (self.n, self.m))[j:j + 1]
            return float(np.asarray(series_peaks(series[None]))[0, 0])
        return float(self.amplitudes(x, p)[j])

    def amplitudes_of(self, xs: Sequence[np.ndarray], ps: Sequence[float],
                      outputs: bool = True) -> np.ndarray:
        """:meth:`amplitudes` of many points, (points, quantities): the coordinates' series
        at once (:func:`series_peaks`), each output by :func:`periodic_peak`."""
        coords = series_peaks(np.reshape(np.asarray(xs, dtype=float),
                                         (len(xs), self.n, self.m)))
        if not (outputs and self.system.outputs):
            return coords
        count = self.n + len(self.system.outputs)
        rows = []
        with np.errstate(all="ignore"):
            for x, p in zip(xs, ps):
                def outputs_at(tau: np.ndarray, x: np.ndarray = x, p: float = p) -> np.ndarray:
                    return self.quantities(x, p, tau)[self.n:]
                rows.append(periodic_peak(outputs_at, count - self.n, self._grid))
        return np.hstack([coords, np.array(rows)])


def newton_at(jacobian: Callable[[np.ndarray, float], tuple[Any, ...]], x: np.ndarray,
              p: float, scale: float, tol: float = NEWTON_TOL) -> tuple[np.ndarray, bool]:
    """Newton's method on R(x, p) = 0 at fixed p, ``jacobian(x, p)`` giving (R, dR/dx, ...):
    the last iterate and whether a step fell below ``tol`` times max(|x|, scale)."""
    for _ in range(NEWTON_MAX):
        R, J = jacobian(x, p)[:2]
        try:
            dx = np.linalg.solve(J, -R)
        except np.linalg.LinAlgError:
            return x, False
        x = x + dx
        if not np.all(np.isfinite(x)):
            return x, False
        if np.linalg.norm(dx) <= tol * max(float(np.linalg.norm(x)), scale):
            return x, True
    return x, False


def basis(tau: np.ndarray, H: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The Fourier basis [1, cos tau, sin tau, ..., sin H tau] and its two derivatives."""
    m = 2 * H + 1
    k = np.arange(1, H + 1)
    phi = np.ones((tau.size, m))
    dphi = np.zeros((tau.size, m))
    d2phi = np.zeros((tau.size, m))
    c, s = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
    phi[:, 1::2], phi[:, 2::2] = c, s
    dphi[:, 1::2], dphi[:, 2::2] = -k * s, k * c
    d2phi[:, 1::2], d2phi[:, 2::2] = -k ** 2 * c, -k ** 2 * s
    return phi, dphi, d2phi


def truncation(coefficients: np.ndarray, H: int) -> np.ndarray:
    """Relative amplitude of the highest harmonic pair, per point (max over coordinates)."""
    c = coefficients
    amps = np.concatenate([np.abs(c[..., :1]), np.hypot(c[..., 1::2], c[..., 2::2])], axis=-1)
    total = amps.sum(axis=-1)
    top = amps[..., -2:].sum(axis=-1) if H >= 2 else amps[..., -1]
    largest = total.max(axis=-1, keepdims=True)
    significant = total > 1e-6 * np.maximum(largest, 1e-300)
    ratio = np.where(significant, top / np.where(total > 0, total, 1.0), 0.0)
    return np.asarray(ratio.max(axis=-1))


def raise_harmonics(x: np.ndarray, n: int, H: int,
                    converge: Callable[[np.ndarray, int], tuple[np.ndarray, bool]],
                    share: Callable[[np.ndarray, int], float] | None = None,
                    limit: int = MAX_HARMONICS,
                    check: Callable[[], None] | None = None) -> tuple[int, np.ndarray]:
    """The automatic choice of H at one solution: H raised by :data:`HARMONICS_STEP` (at
    most ``limit``, itself at most :data:`MAX_HARMONICS`) while the highest harmonics of
    ``x`` carry more than :data:`TRUNCATION_TOL` of its amplitude, the point solved again
    at each H.

    Parameters
    ----------
    x : ndarray
        The solution with H harmonics, n rows of 2H+1 coefficients, raveled.
    n, H : int
    converge : callable
        ``converge(x_guess, H_new) -> (x_new, ok)``: the point solved with H_new harmonics
        from ``x`` padded with zeros (:func:`resize`).
    share : callable, optional
        ``share(x, H)``: the truncation measure of a solution (default: :func:`truncation`
        of x itself).
    limit : int
        The most harmonics to take.
    check : callable, optional
        Called before each raise (a deadline's check).

    Returns
    -------
    (int, ndarray)
        The H reached and the solution there: the last H whose point converged.

    Examples
    --------
    >>> x = np.array([0.0, 1.0, 0.0, 0.1, 0.0])  # H = 2: the highest pair is all of it
    >>> raise_harmonics(x, 1, 2, lambda x, H: (x, True))[0]  # once raised, zeros on top
    6
    """
    if share is None:
        def share(x: np.ndarray, H: int) -> float:
            return float(truncation(x.reshape(1, n, 2 * H + 1), H)[0])
    limit = min(limit, MAX_HARMONICS)
    while H < limit and share(x, H) > TRUNCATION_TOL:
        if check is not None:
            check()
        H_next = min(limit, H + HARMONICS_STEP)
        x_next, ok = converge(resize(x, n, H, H_next), H_next)
        if not ok:
            break
        x, H = x_next, H_next
    return H, x


def truncation_warning(share: float, H: int, given: bool, where: str = "",
                       stopped: str = "", cause: str = "") -> str:
    """The warning of a solution whose highest harmonics carry more than
    :data:`TRUNCATION_TOL` of the amplitude (one text for every balance).

    Parameters
    ----------
    share : float
        The truncation measure (:func:`truncation`).
    H : int
    given : bool
        Whether H was given (else the automatic choice ended there).
    where : str
        The point, e.g. ``"omega = 1.2"``.
    stopped : str
        Why the automatic choice ended at H (default: its largest H).
    cause : str
        What keeps the highest harmonics large, where known.

    Examples
    --------
    >>> truncation_warning(3e-4, 7, True, "w = 1.5")  # doctest: +NORMALIZE_WHITESPACE
    'the highest harmonics carry up to 0.0003 of the amplitude (w = 1.5) with 7 harmonics
    given: the result is less accurate than the truncation tolerance 1e-06; more harmonics
    give a more accurate one'
    """
    text = f"the highest harmonics carry up to {share:.2g} of the amplitude" \
           + (f" ({where})" if where else "") + f" with {H} harmonics"
    text += " given" if given else f", {stopped or 'the most the automatic choice takes'}"
    if cause:
        text += f"; {cause}"
    return text + f": the result is less accurate than the truncation tolerance " \
                  f"{TRUNCATION_TOL:g}" + ("; more harmonics give a more accurate one"
                                           if given else "")


def resize(x: np.ndarray, n: int, H_old: int, H_new: int) -> np.ndarray:
    """The coefficient vector of H_old harmonics as one of H_new (cut or padded with 0)."""
    X = x.reshape(n, 2 * H_old + 1)
    out = np.zeros((n, 2 * H_new + 1))
    k = min(H_old, H_new)
    out[:, :2 * k + 1] = X[:, :2 * k + 1]
    return out.ravel()


def start_coefficients(solution: Any, n: int, H: int, W: float) -> np.ndarray:
    """The series (n, 2H+1) of a linear stationary solution's harmonics (multiples of W)."""
    X = np.zeros((n, 2 * H + 1))
    for h in solution.harmonics:
        k = int(round(h.omega / W))
        if k == 0:
            X[:, 0] += h.L
        elif k <= H:
            X[:, 2 * k - 1] += h.L
            X[:, 2 * k] += h.N
    return X


__all__ = ["HarmonicBalance", "NEWTON_TOL", "NEWTON_MAX", "newton_at", "basis", "truncation",
           "resize", "start_coefficients", "raise_harmonics", "truncation_warning",
           "DEFAULT_HARMONICS", "TRUNCATION_TOL", "HARMONICS_STEP", "MAX_HARMONICS"]
