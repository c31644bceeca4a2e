"""Harmonic balance of large matrix models condensed onto their nonlinear coordinates.

A ``[matrices]`` model ``M q'' + C q' + K q + f_nl(q, q') = F(t)`` whose
nonlinear elements (``[[nonlinear]]``) touch only m of its n coordinates is
solved for periodic motions of the excitation's base frequency W with the m
coordinates' harmonics as the only unknowns:

**Condensation.**  With q = sum_k Re(z_k e^{i k W t}) the linear part gives,
harmonic by harmonic, z_k = H(kW) (F_k - B g_k) with H(w) = (K - w^2 M + i w
C)^-1 and g_k the harmonics of the elements' forces; restricted to the m
nonlinear coordinates u this is the residual

    r_k = u_k - H_uF(kW) F_k + H_uu(kW) g_k(u) = 0,    k = 0 ... H,

m(2H+1) real unknowns whatever n.  H_uu and H_uF come from one reduced-order
model of the whole band 0 ... H W_max (:func:`resonant.analyses.reduced.
reduced_model`, loads: F and a unit load at each nonlinear coordinate, its
error estimate reported; modes and load-dependent Ritz vectors checked against exact
solves where it does not converge; where neither reaches the tolerance, the exact
receptances by one sparse solve per frequency, :class:`ExactTransfers`, with a warning
of what they cost), or, for models of at most :data:`EXACT_SIZE`
coordinates or ``exact=True``, from the full matrices.  The reduced (or full)
system is diagonalized once (first-order form, poles mu_j), so each H(w) costs
O(r m^2).

**Forces** by the alternating frequency-time scheme
(:class:`resonant.system.nonlinear_elements.ElementForces`): the force of each
element at N samples of one period, its harmonics by the FFT; the Jacobian by
the chain rule along the harmonic basis (a friction element's derivative is
marched with it).

**Continuation** by pseudo-arclength in (x / s_x, p / s_p), Newton correctors,
step control from the iteration count and the change per step relative to the
present amplitude (``follow(..., relative=True)``); folds where the
parameter component of the tangent changes sign, refined by regula falsi.

**Stability** by Hill's method on the linearization about each point in the
modal coordinates of the (reduced) linear part: the modes with |Im mu| up to
:data:`DYNAMIC_FACTOR` W are kept dynamic (all of them where Hill's matrix has
at most :data:`SMALL_HILL` rows), the others enter as their static
flexibility at the nonlinear coordinates (a residual flexibility), so the
eigenvalue problem has 2s(2H+1) rows for s kept modes, not 2n(2H+1).  This is
an approximation where modes above the cutoff respond dynamically to the
perturbation; the tests check it against time simulations of the full
equations.  Where Hill's matrix would have more than :data:`MONODROMY_ROWS` rows
(many kept modes, many harmonics) the same linearization gives the exponents
through its monodromy matrix instead: the 2s x 2s state-transition matrix over
one period by fourth-order Magnus steps, its eigenvalues the multipliers (cost
linear in H, not cubic; equal verdicts, ``tests/test_condensed_monodromy.py``).
Where friction elements slip, the linearization also carries each slider's shift
(the element remembers it while it sticks again), and the exponents come from the
monodromy matrix over the time samples themselves (:func:`_slider_monodromy`); with
friction elements the modes kept dynamic are chosen by each point's own W
(:func:`_slider_modes`): the same exponents for one periodic motion whatever H and
wherever the sweep started.

Examples
--------
>>> from resonant.model import loads
>>> from resonant.system import nonlinear_system
>>> model = loads('''
... [parameters]
... w = 0.8
... [matrices]
... M = [[1, 0], [0, 1]]
... K = [[2, -1], [-1, 1]]
... C = [[0.05, 0], [0, 0.05]]
... [[harmonic]]
... omega = "w"
... F_C = [0, 0.05]
... [[nonlinear]]
... name = "spring"
... coordinates = ["q2"]
... force = "0.5*q2^3"
... ''')
>>> r = condensed_sweep(nonlinear_system(model), "w", 0.3, 0.5, harmonics=3, points=20,
...                     linear=False)
>>> bool(r.stable.all()), r.coordinates
(True, ('q2',))
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from ..arrays import Matrix
from ..deadline import NO_DEADLINE, AnalysisTimeout, Deadline, DeadlineExceeded
from ..errors import AnalysisError
from ..memory import budget, chunk_rows, dense_matrix
from ..modal import (
    eigenvalues,
    fundamental_strip,
    state_modes,
)
from ..model.nonlinear_elements import NonlinearElement
from ..model.options import BalanceOptions
from ..system.base import LinearSystem
from ..system.matrix_outputs import OutputSeries
from ..system.nonlinear import LocalElements, NonlinearSystem
from ..system.nonlinear_elements import ElementForces
from .continuation import Branch, follow
from .forward_error import Residuals
from .hb_solver import (
    DEFAULT_HARMONICS,
    MAX_HARMONICS,
    TRUNCATION_TOL,
    basis,
    newton_at,
    raise_harmonics,
    truncation,
    truncation_warning,
)
from .nonlinear_response import NonlinearResponse
from .peaks import periodic_peak, series_peaks
from .reduced import (
    DEFAULT_TOL,
    ReducedModel,
    modal_ritz_basis,
    reduced_model,
    symmetric,
    transfer_at,
)
from .special_points import STABILITY_TOL, classify, special_points
from .sweep import FrequencyResponse, sweep

if TYPE_CHECKING:
    pass

#: models up to this many coordinates use the full matrices (no reduced model)
EXACT_SIZE = 400
#: modes with |Im mu| up to this multiple of W stay dynamic in the stability analysis
DYNAMIC_FACTOR = 3.0
#: most modes kept dynamic in the stability analysis
MAX_DYNAMIC = 40
#: Hill matrices up to this many rows keep every mode dynamic (one eigenvalue problem
#: per branch point: 200 complex rows cost ~10 ms, 600 rows ~30 times as much)
SMALL_HILL = 200
#: Hill matrices of more rows give way to the monodromy matrix (:func:`_monodromy`: its
#: cost grows as H, Hill's as H^3: 600 rows cost ~1.4 s, the monodromy ~0.2 s)
MONODROMY_ROWS = SMALL_HILL
#: least steps per period of the monodromy matrix (fourth-order Magnus steps)
MONODROMY_STEPS = 128
#: the [7/7] Pade approximant of exp (:func:`_expm_small`): its coefficients and the
#: largest 1-norm it serves to the unit roundoff (Higham 2005, Table 2.3)
PADE7 = (17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0)
PADE7_THETA = 0.9504178996162932
#: the exponent (a multiple of W) that pads a branch point with fewer kept modes than
#: others: multiplier exp(-2 pi 1e6) = 0
PAD_EXPONENT = -1e6
#: least samples per period for elements with kinks (gap, friction)
NONSMOOTH_SAMPLES = 2048
#: with more samples than this many per harmonic coefficient the Jacobian's blocks come
#: from the tangent's spectrum (:meth:`_Basis.galerkin`), not from the samples
SPECTRAL_SAMPLES = 16
#: a harmonic k of the base frequency W resonates with a mode of natural frequency w_j
#: where |k W - w_j| <= RESONANCE_BAND w_j (named in the truncation warning)
RESONANCE_BAND = 0.05
NEWTON_TOL = 1e-10
#: frequencies per unit of the band where the reduced model's error is checked
BAND_POINTS = 400
#: frequencies whose exact receptances are kept (:class:`ExactTransfers`)
EXACT_CACHE = 512
#: exact solves per harmonic and per point asked of the branch, at the least (measured:
#: 14 on a chain, the continuation taking more points than asked and several Newton
#: iterations and a parameter derivative at each)
EXACT_SOLVES = 10
#: the exact solves timed before the branch's time is estimated
EXACT_PROBE = 8
#: steps of iterative refinement of each exact solve (a plain LU rounds differently at
#: each frequency, a residual not smooth in the frequency that stops the continuation)
EXACT_REFINEMENTS = 2


# -- the linear part ----------------------------------------------------------------------

class ExactTransfers:
    """Exact receptances of the kept rows, one sparse LU per frequency: what the condensed
    balance uses where the reduced model of the linear part did not reach its tolerance.

    ``self(w)`` is the (rows, m + p) transfer (K - w^2 M + i w C)^-1 B restricted to
    ``rows`` (:func:`~resonant.analyses.reduced.transfer_at`), kept for the last
    :data:`EXACT_CACHE` frequencies; ``solves`` and ``seconds`` count what it cost.

    Parameters
    ----------
    M, C, K : sparse matrix or ndarray
        (n, n).
    B : ndarray
        (n, m + p) unit loads at the nonlinear coordinates, then the external loads.
    rows : list of int
        The kept coordinates.
    why : str
        Why the reduced model was not used (named when the time runs out).
    deadline : Deadline, optional

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> exact = ExactTransfers(sp.identity(2), None, sp.diags([4.0, 9.0]), np.eye(2), [1], "")
    >>> exact(1.0).real.round(6).tolist(), exact.solves
    ([[0.0, 0.125]], 1)
    """

    def __init__(self, M: Matrix, C: Matrix | None, K: Matrix, B: np.ndarray,
                 rows: list[int], why: str, deadline: Deadline = NO_DEADLINE) -> None:
        self.M, self.C, self.K, self.B = M, C, K, B
        self.rows, self.why, self.deadline = rows, why, deadline
        self.solves, self.seconds = 0, 0.0
        #: the fewest solves the branch will need (set by the caller; 0: unknown)
        self.expected = 0
        self._cache: dict[float, np.ndarray] = {}
        self._residuals: Residuals | None = None

    def _refuse(self, needed: str) -> AnalysisTimeout:
        return AnalysisTimeout(
            f"the exact receptances of the linear part ({self.why}) {needed} the time limit "
            f"of {self.deadline.seconds:g} s: loosen the tolerance of the reduced model "
            "(--tol, tol), ask for fewer harmonics or points, or allow more time (--timeout)")

    def _check_time(self) -> None:
        """Refuse once the time is up, and early where the solves still to come (at least
        ``expected`` in all, at the mean time of the first :data:`EXACT_PROBE`) cannot fit."""
        if self.deadline.expired:
            raise self._refuse(f"exceeded, after {self.solves} sparse solves "
                               f"({self.seconds:.3g} s),")
        left = self.deadline.remaining()
        if self.solves == EXACT_PROBE and left is not None and self.expected > self.solves:
            need = self.seconds / self.solves * (self.expected - self.solves)
            if need > left:
                raise self._refuse(f"need at least {self.expected} sparse solves, about "
                                   f"{need:.3g} s more at {self.seconds / self.solves:.2g} s "
                                   f"each, {left:.3g} s left of")

    def __call__(self, w: float) -> np.ndarray:
        w = abs(float(w))
        found = self._cache.get(w)
        if found is not None:
            return found
        self._check_time()
        start = time.monotonic()
        try:
            with np.errstate(all="ignore"):
                if self._residuals is None:
                    self._residuals = Residuals(self.K, self.M,
                                                self.C if self.C is not None else 0 * self.M)
                result = transfer_at(self.M, self.C, self.K, self.B, w, EXACT_REFINEMENTS,
                                     self._residuals)[self.rows]
        except RuntimeError:    # exactly singular (an undamped resonance, a free body at 0)
            result = np.full((len(self.rows), self.B.shape[1]), np.inf, dtype=complex)
        self.solves += 1
        self.seconds += time.monotonic() - start
        if len(self._cache) >= EXACT_CACHE:
            self._cache.pop(next(iter(self._cache)))
        self._cache[w] = result
        return result


@dataclass(frozen=True)
class LinearPart:
    """The linear model's transfer to the kept coordinates, as poles and residues.

    ``transfer(w)`` is ``rows -> (nonlinear unit loads, external loads)`` at w:
    Lq diag(1/(i w - mu)) Rin.  ``rows`` are the nonlinear coordinates (first m)
    then the observed ones.  With ``exact`` (a reduced model that did not reach its
    tolerance) the transfers are its exact solves; the poles and residues, from that
    reduced model, serve the stability analysis only.
    """

    mu: np.ndarray          # (2r,) poles
    Lq: np.ndarray          # (rows, 2r) displacements of the kept coordinates
    Lv: np.ndarray          # (rows, 2r) their velocities
    Rin: np.ndarray         # (2r, m + p) inputs: unit loads at the nonlinear coordinates, loads
    m: int
    error: float            # the reduced model's estimated error (0 for the full matrices)
    size: int               # r
    seconds: float
    top: float = math.inf   # the highest frequency it holds for (a reduced model's band)
    exact: ExactTransfers | None = None
    why: str = ""           # why the exact transfers replace the reduced model's

    def transfer(self, w: float, rows: slice | np.ndarray = slice(None)) -> np.ndarray:
        """(rows, m + p) transfer at w (default: every kept row)."""
        if self.exact is not None:
            return self.exact(w)[rows]
        with np.errstate(all="ignore"):
            result: np.ndarray = (self.Lq[rows] / (1j * w - self.mu)) @ self.Rin
            return result


def linear_part(M: Matrix, C: Matrix, K: Matrix, loads: np.ndarray, nonlinear: Sequence[int],
                observed: Sequence[int], band: np.ndarray, *, exact: bool | None = None,
                tol: float = DEFAULT_TOL, deadline: Deadline = NO_DEADLINE) -> LinearPart:
    """The transfer of the linear model to the nonlinear and observed coordinates.

    Parameters
    ----------
    M, C, K : sparse matrix or ndarray
        (n, n), fixed.
    loads : ndarray
        (n, p) complex external loads (F_C - i F_S of each harmonic).
    nonlinear, observed : sequence of int
        The nonlinear coordinates (unit loads there) and further coordinates to recover.
    band : ndarray
        Frequencies where the reduced model must meet ``tol``.
    exact : bool, optional
        Use the full matrices (default: for n <= :data:`EXACT_SIZE`).
    tol : float
        Tolerance of the reduced model.  Where neither the reduced model nor a basis of
        modes and Ritz vectors reaches it, the transfers are exact sparse solves
        (:class:`ExactTransfers`) and the unconverged reduced model gives the poles.

    Returns
    -------
    LinearPart
    """
    start = time.monotonic()
    n = M.shape[0]
    exact_part, why = None, ""
    nl = list(nonlinear)
    rows = nl + [i for i in observed if i not in nl]
    exact = n <= EXACT_SIZE if exact is None else exact
    unit = np.zeros((n, len(nl)), dtype=complex)
    unit[nl, range(len(nl))] = 1.0
    B = np.hstack([unit, np.asarray(loads, dtype=complex).reshape(n, -1)])
    if exact:
        dense = [dense_matrix(a) for a in (M, C, K)]
        V = None
        Mr, Cr, Kr = dense
        Br = B
        error = 0.0
    else:
        # the rational Krylov model of the band first: a few vectors per input whatever
        # the modal density (a 100 x 100 grid: 131 vectors in 2 s, where its 400 modes
        # below 4 H W_max took 50 s); modes and Ritz vectors where it does not converge
        rom = reduced_model(M, C, K, B, band, tol=tol, deadline=deadline)
        basis = (rom.V, float(np.max(rom.estimated_error, initial=0.0))) \
            if rom.converged else None
        if basis is None and symmetric(M) and symmetric(K):
            basis = modal_ritz_basis(M, C, K, B, float(band.max()), rows, tol, deadline)
        if basis is None:
            why = _exact_instead(rom, tol)
            finite = rom.estimated_error[np.isfinite(rom.estimated_error)]
            basis = rom.V, float(np.max(finite, initial=math.inf if finite.size == 0 else 0))
            exact_part = ExactTransfers(M, C, K, B, rows, why, deadline)
        V, error = basis
        Mr, Cr, Kr = (V.T @ (a @ V) for a in (M, C if C is not None else 0 * M, K))
        Br = V.T @ B
    r = Mr.shape[0]
    mu, X, Xinv = state_modes(Mr, Cr, Kr, "the condensed harmonic balance")
    Vrows = np.eye(n)[rows] if V is None else V[rows]
    Rin = Xinv[:, r:] @ np.linalg.solve(Mr, Br)
    return LinearPart(mu, Vrows @ X[:r], Vrows @ X[r:], Rin, len(nl), error, r,
                      time.monotonic() - start, math.inf if exact else float(band.max()),
                      exact_part, why if exact_part is not None else "")


def _exact_instead(rom: ReducedModel, tol: float) -> str:
    """Why exact receptances replace the reduced model ``rom`` short of ``tol``; refused
    where it has no vector to give the poles, or where its rounding floor (that of every
    solve, exact ones included) lies above ``tol``."""
    why = f"the reduced model did not reach the tolerance {tol:.2g}: {rom.reason}"
    refusal = why.replace("reduced model", "reduced model of the linear part", 1)
    if rom.floor > tol:
        raise AnalysisError(f"{refusal} (exact solves round off as much: a tolerance above "
                            f"{rom.floor:.2g} with --tol, or tol=)")
    if rom.V.shape[1] == 0:
        raise AnalysisError(refusal)
    return why


# -- the harmonic balance -----------------------------------------------------------------

class _Basis:
    """The real Fourier basis [1, cos t, sin t, ..., cos Ht, sin Ht] at N samples."""

    def __init__(self, H: int, N: int) -> None:
        self.H, self.N, self.size = H, N, 2 * H + 1
        tau = 2 * np.pi * np.arange(N) / N
        k = np.arange(1, H + 1)
        c, s = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
        self.phi = np.ones((N, self.size))
        self.dphi = np.zeros((N, self.size))
        self.phi[:, 1::2], self.phi[:, 2::2] = c, s
        self.dphi[:, 1::2], self.dphi[:, 2::2] = -k * s, k * c
        self.P = np.empty((self.size, N))
        self.P[0] = 1.0 / N
        self.P[1::2], self.P[2::2] = 2.0 / N * c.T, 2.0 / N * s.T
        #: d/dtau in the basis: dphi = phi @ D
        self.D = np.zeros((self.size, self.size))
        self.D[2 * k, 2 * k - 1], self.D[2 * k - 1, 2 * k] = -k, k

    def galerkin(self, G: np.ndarray) -> np.ndarray:
        """``P diag(G) phi`` for samples G (..., N), from G's spectrum: the product of
        g = sum_d c_d e^{i d tau} with cos j tau, sin j tau has the coefficients
        (c_{k-j} +- c_{k+j}) / 2 (/ i) at e^{i k tau}, indices modulo N as the samples
        alias them (equal to the sampled product to rounding; O(H^2), not O(N H^2))."""
        H, N = self.H, self.N
        c = np.fft.fft(G, axis=-1) / N
        k = np.arange(H + 1)[:, None]
        j = np.arange(1, H + 1)[None, :]
        minus, plus = c[..., (k - j) % N], c[..., (k + j) % N]
        F = np.empty((*G.shape[:-1], H + 1, self.size), dtype=complex)
        F[..., 0] = c[..., np.arange(H + 1)]
        F[..., 1::2] = (minus + plus) / 2
        F[..., 2::2] = (minus - plus) / 2j
        out = np.empty((*G.shape[:-1], self.size, self.size))
        out[..., 0, :] = F[..., 0, :].real
        out[..., 1::2, :] = 2 * F[..., 1:, :].real
        out[..., 2::2, :] = -2 * F[..., 1:, :].imag
        return out

    def complex(self, X: np.ndarray) -> np.ndarray:
        """(..., 2H+1) real coefficients -> (..., H+1) complex z_k = a_k - i b_k."""
        Z = np.empty((*X.shape[:-1], self.H + 1), dtype=complex)
        Z[..., 0] = X[..., 0]
        Z[..., 1:] = X[..., 1::2] - 1j * X[..., 2::2]
        return Z

    def real(self, Z: np.ndarray) -> np.ndarray:
        X = np.empty((*Z.shape[:-1], self.size))
        X[..., 0] = Z[..., 0].real
        X[..., 1::2], X[..., 2::2] = Z[..., 1:].real, -Z[..., 1:].imag
        return X


class CondensedBalance:
    """Residual, Jacobian and stability of the condensed harmonic balance.

    Parameters
    ----------
    linear : LinearPart
    forces : callable
        p -> ElementForces at the parameter value p.
    loads : list of (int, int)
        (harmonic order k, column of the external loads in ``linear``) pairs.
    base : callable
        p -> base frequency W.
    H, N : int
        Harmonics and samples per period.
    param : str
        The continuation parameter.
    names : tuple of str
        The kept rows' coordinates (nonlinear first, then observed).
    top : float
        The highest base frequency of the range (which modes stay dynamic).
    outputs : BranchOutputs, optional
        The model's outputs, evaluated in full from the kept rows.
    """

    def __init__(self, linear: LinearPart, forces: Callable[[float], ElementForces],
                 loads: list[tuple[int, int]], base: Callable[[float], float], H: int,
                 N: int, param: str, names: tuple[str, ...],
                 top: float, outputs: BranchOutputs | None = None) -> None:
        self.outputs = outputs
        #: factor of the external loads (below 1 only while the start point is found)
        self.load_scale = 1.0
        self.linear, self.forces, self.loads, self.base = linear, forces, loads, base
        self.m = linear.m
        self.basis = _Basis(H, N)
        self.H = H
        self.size = self.m * self.basis.size
        self.param = param
        self._names = names
        self.dynamic = _dynamic_modes(linear.mu, top, H)
        self._rows = np.arange(len(names))
        self._cache: dict[float, np.ndarray] = {}
        #: (sign of det J, parity of the real unstable exponents) at the branch's start
        self.reference: tuple[float, int] | None = None

    def transfers(self, W: float, rows: np.ndarray | None = None) -> np.ndarray:
        """(H+1, rows, m + p) transfers at kW (default rows: the nonlinear coordinates)."""
        if rows is not None:
            return np.array([self.linear.transfer(k * W, rows) for k in range(self.H + 1)])
        if W not in self._cache:
            if len(self._cache) > 64:
                self._cache.clear()
            lin = self.linear
            if lin.exact is not None:
                self._cache[W] = np.array([lin.transfer(k * W, slice(0, self.m))
                                           for k in range(self.H + 1)])
                return self._cache[W]
            with np.errstate(all="ignore"):  # every harmonic at once (m rows: small)
                ws = W * np.arange(self.H + 1)
                self._cache[W] = (lin.Lq[None, :self.m] / (1j * ws[:, None, None] - lin.mu)
                                  ) @ lin.Rin
        return self._cache[W]

    def _directions(self, W: float) -> tuple[np.ndarray, np.ndarray]:
        m, b = self.m, self.basis
        dU = np.zeros((m, b.N, self.size))
        dUd = np.zeros((m, b.N, self.size))
        for i in range(m):
            dU[i, :, i * b.size:(i + 1) * b.size] = b.phi
            dUd[i, :, i * b.size:(i + 1) * b.size] = W * b.dphi
        return dU, dUd

    def samples(self, x: np.ndarray, W: float) -> tuple[np.ndarray, np.ndarray]:
        X = x.reshape(self.m, self.basis.size)
        return X @ self.basis.phi.T, W * (X @ self.basis.dphi.T)

    def linear_response(self, T: np.ndarray, rows: slice | np.ndarray) -> np.ndarray:
        """(rows, H+1) complex response to the external loads."""
        out = np.zeros((T[0][rows].shape[0], self.H + 1), dtype=complex)
        for k, column in self.loads:
            if k <= self.H:
                out[:, k] += T[k][rows, self.m + column]
        return self.load_scale * out if self.load_scale != 1.0 else out

    def evaluate(self, x: np.ndarray, p: float, jacobian: bool = True
                 ) -> tuple[np.ndarray, np.ndarray | None]:
        W = self.base(p)
        T = self.transfers(W)
        U, Ud = self.samples(x, W)
        b, m = self.basis, self.m
        forces = self.forces(p)
        if not jacobian:
            F, _ = forces.evaluate(U, Ud)
        elif forces.hysteretic:
            F, dF_coefficients = self.force_derivatives_by_directions(forces, U, Ud, W)
        else:
            F, dF_coefficients = self.force_derivatives_by_tangent(forces, U, Ud, W)
        G = b.complex(F @ b.P.T)                                  # (m, H+1)
        Uc = b.complex(x.reshape(m, b.size))
        Hnl = T[:, :m, :m]                                        # (H+1, m, m)
        r = Uc - self.linear_response(T, slice(0, m)) + np.einsum("kij,jk->ik", Hnl, G)
        R = b.real(r).ravel()
        if not jacobian:
            return R, None
        dG = b.complex(dF_coefficients)                           # (m, c, H+1)
        dr = np.einsum("kij,jck->ick", Hnl, dG)                   # (m, c, H+1)
        J = b.real(dr).transpose(0, 2, 1).reshape(self.size, self.size) + np.eye(self.size)
        return R, J

    def force_derivatives_by_directions(self, forces: ElementForces, U: np.ndarray,
                                        Ud: np.ndarray, W: float
                                        ) -> tuple[np.ndarray, np.ndarray]:
        """The forces (m, N) and the (m, c, 2H+1) real coefficients of their derivatives
        along each of the c unknowns, the motion's derivative pushed through the elements
        sample by sample (what a hysteretic element needs: its force depends on the path)."""
        dU, dUd = self._directions(W)
        F, dF = forces.evaluate(U, Ud, dU, dUd)
        assert dF is not None
        return F, np.einsum("inc,jn->icj", dF, self.basis.P)

    def force_derivatives_by_tangent(self, forces: ElementForces, U: np.ndarray,
                                     Ud: np.ndarray, W: float
                                     ) -> tuple[np.ndarray, np.ndarray]:
        """The same from the instantaneous tangent stiffness G0 and damping G1 (m, m, N)
        of elements whose force depends on the present state only: block (i, j) is
        P diag(G0_ij) phi + W P diag(G1_ij) dphi, without a sample array per unknown."""
        b, m = self.basis, self.m
        F, G0, G1 = forces.forces_and_tangent(U, Ud)
        if b.N > SPECTRAL_SAMPLES * b.size:  # many samples (a gap): from the spectra
            blocks = b.galerkin(G0)                               # (m, m, 2H+1, 2H+1)
            if G1.any():
                blocks += W * (b.galerkin(G1) @ b.D)
        else:
            blocks = (G0[:, :, None, :] * b.P) @ b.phi
            if G1.any():
                blocks += W * ((G1[:, :, None, :] * b.P) @ b.dphi)
        return F, blocks.transpose(0, 1, 3, 2).reshape(m, m * b.size, b.size)

    def jacobian(self, x: np.ndarray, p: float
                 ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, float, float]]:
        """R, dR/dx and the point (x, p, W) for :meth:`exponents`."""
        R, J = self.evaluate(x, p)
        assert J is not None
        return R, J, (x, p, self.base(p))

    def dp(self, x: np.ndarray, p: float) -> np.ndarray:
        h = 1e-6 * max(1.0, abs(p))
        result: np.ndarray = (self.evaluate(x, p + h, False)[0]
                              - self.evaluate(x, p - h, False)[0]) / (2 * h)
        return result

    def newton(self, x: np.ndarray, p: float, scale: float) -> tuple[np.ndarray, bool]:
        """Newton's method at fixed p (:func:`~resonant.analyses.hb_solver.newton_at`)."""
        return newton_at(self.jacobian, x, p, scale, NEWTON_TOL)

    def kept_coordinates(self) -> tuple[str, ...]:
        """The nonlinear coordinates, then the observed ones."""
        return self._names

    def names(self) -> tuple[str, ...]:
        """The nonlinear coordinates, then the observed ones, then the outputs."""
        return self._names + (self.outputs.series.names if self.outputs else ())

    def coefficients(self, x: np.ndarray, p: float, rows: np.ndarray | None = None
                     ) -> np.ndarray:
        """(rows, 2H+1) real coefficients of the kept rows ``rows`` (default: every one,
        nonlinear and observed)."""
        b, m = self.basis, self.m
        W = self.base(p)
        T = self.transfers(W, self._rows if rows is None else rows)
        U, Ud = self.samples(x, W)
        F, _ = self.forces(p).evaluate(U, Ud)
        G = b.complex(F @ b.P.T)
        z = self.linear_response(T, slice(None)) - np.einsum("kij,jk->ik", T[:, :, :m], G)
        return b.real(z)

    def amplitudes(self, x: np.ndarray, p: float) -> np.ndarray:
        """Peak |q| over one period of every kept row, then peak |deviation| of every
        output, located to rounding."""
        coef = self.coefficients(x, p)
        peaks = np.asarray(series_peaks(coef))
        if not self.outputs:
            return peaks
        return np.concatenate([peaks, self.outputs.peaks(coef, self.base(p), p)])

    def amplitude(self, x: np.ndarray, p: float, j: int) -> float:
        """The amplitude of quantity ``j`` of :meth:`names` alone: a kept row's costs one
        row of transfers (locating a peak of one of 200 observed coordinates needs no
        other)."""
        if j >= len(self._rows):
            return float(self.amplitudes(x, p)[j])
        return float(np.asarray(series_peaks(self.coefficients(x, p, self._rows[j:j + 1])))[0])

    def exponents(self, J: np.ndarray, blocks: tuple[np.ndarray, float, float]
                  ) -> np.ndarray:
        """Floquet exponents by Hill's method on the kept modes (see the module docstring);
        ``blocks`` is the point (x, p, W) of :meth:`jacobian`."""
        x, p, W = blocks
        lin, m, b = self.linear, self.m, self.basis
        U, Ud = self.samples(x, W)
        forces = self.forces(p)
        G0, G1 = forces.stiffness(U, Ud)                          # (m, m, N)
        sliders = forces.sliders(U) if forces.hysteretic else []
        keep = _slider_modes(lin.mu, W) if forces.hysteretic else self.dynamic
        mu_s = lin.mu[keep]
        Cq, Cv = lin.Lq[:m, keep], lin.Lv[:m, keep]
        Bs = lin.Rin[keep, :m]
        fast = ~keep
        Rres = (lin.Lq[:m, fast] / lin.mu[fast]) @ lin.Rin[fast, :m]
        s = mu_s.size
        if s == 0:
            return np.zeros(0, dtype=complex)
        # per sample: the nonlinear coordinates' perturbation T eta (fast modes quasi-static)
        # and the force it feeds back, P eta; A(t) = diag(mu) - Bs P(t)
        E = np.eye(m) - np.einsum("ij,jkn->nik", Rres, G0)
        rhs = Cq[None] + np.einsum("ij,jkn,kl->nil", Rres, G1, Cv)
        T = np.linalg.solve(E, rhs)                               # (N, m, s)
        P = np.einsum("ijn,njk->nik", G0, T) + np.einsum("ijn,jk->nik", G1, Cv)
        if sliders:  # the sliders' memory: the samples' own monodromy, whatever H
            lam = _slider_monodromy(mu_s, Bs, Rres, G0, E, T, P, sliders, W)
            return self._parity(J, lam, W)
        H = self.H
        spectrum = np.fft.fft(P, axis=0) / b.N                    # index k: e^{i k W t}
        offsets = np.arange(-2 * H, 2 * H + 1)
        coef = -np.einsum("ij,djk->dik", Bs, spectrum[offsets % b.N])
        coef[2 * H] += np.diag(mu_s)
        if b.N <= 4 * H:  # too few samples to resolve the offsets: alias-free part only
            coef[np.abs(offsets) >= b.N // 2] = 0.0
        if s * (2 * H + 1) <= MONODROMY_ROWS or _hill_is_cheaper(coef, W, H, s):
            lam = _hill(coef, W, H, s)
        else:
            pairs = _real_coordinates(mu_s)
            real = pairs is not None
            if pairs is not None:  # the same system in real coordinates: a quarter the work
                Q, Qinv = pairs
                coef = Qinv @ coef @ Q
            lam = _monodromy(coef, W, H, s, real)
        return self._parity(J, lam, W)

    def _parity(self, J: np.ndarray, lam: np.ndarray, W: float) -> np.ndarray:
        """The exponents ``lam`` with their count of real unstable ones matched to the
        sign of det J against the branch's start (:func:`_match_parity`)."""
        sign = float(np.linalg.slogdet(J)[0])
        if self.reference is None:
            self.reference = (sign, _real_unstable(lam, W) % 2)
            return lam
        odd = (sign != self.reference[0]) != bool(self.reference[1])
        return _match_parity(lam, W, odd)


def _hill(coef: np.ndarray, W: float, H: int, s: int) -> np.ndarray:
    """The s exponents of the periodic system eta' = A(t) eta in the fundamental strip, by
    Hill's method with harmonics -H ... H; ``coef[d + 2H]`` (s, s) multiplies
    e^{i d W t}, d = -2H ... 2H."""
    size = s * (2 * H + 1)
    hill = np.zeros((size, size), dtype=complex)
    for a, k in enumerate(range(-H, H + 1)):
        for c, j in enumerate(range(-H, H + 1)):
            hill[a * s:(a + 1) * s, c * s:(c + 1) * s] = coef[k - j + 2 * H]
        hill[a * s:(a + 1) * s, a * s:(a + 1) * s] -= 1j * k * W * np.eye(s)
    return fundamental_strip(eigenvalues(hill), s)


def _real_coordinates(mu: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Q and Q^-1 with eta = Q y taking first-order modal coordinates eta (poles ``mu``
    of a real system: each complex pole beside its conjugate, whose modes are conjugate)
    to real ones y (the real and imaginary parts of each pair's first); None where the
    poles do not pair.

    Examples
    --------
    >>> Q, Qinv = _real_coordinates(np.array([-0.1 + 2j, -0.3, -0.1 - 2j]))
    >>> A = np.diag([-0.1 + 2j, -0.3, -0.1 - 2j])
    >>> np.round((Qinv @ A @ Q).real, 12) + 0.0  # the pair's rotation, the real pole alone
    array([[-0.1, -2. ,  0. ],
           [ 2. , -0.1,  0. ],
           [ 0. ,  0. , -0.3]])
    """
    s = mu.size
    Q = np.zeros((s, s), dtype=complex)
    used = np.zeros(s, dtype=bool)
    column = 0
    scale = max(float(np.abs(mu).max(initial=0.0)), 1e-300)
    for i in np.argsort(-mu.imag, kind="stable"):
        if used[i]:
            continue
        used[i] = True
        if abs(mu[i].imag) <= 1e-12 * scale:  # a real pole: its mode is real
            Q[i, column] = 1.0
            column += 1
            continue
        if mu[i].imag < 0:
            return None
        rest = np.flatnonzero(~used)
        if rest.size == 0:
            return None
        j = rest[np.argmin(np.abs(mu[rest] - np.conj(mu[i])))]
        if abs(mu[j] - np.conj(mu[i])) > 1e-9 * scale:
            return None
        used[j] = True
        Q[i, column], Q[i, column + 1] = 1.0, 1j
        Q[j, column], Q[j, column + 1] = 1.0, -1j
        column += 2
    return Q, np.linalg.inv(Q)


def _monodromy(coef: np.ndarray, W: float, H: int, s: int, real: bool = False
               ) -> np.ndarray:
    """The s exponents of eta' = A(t) eta (``coef`` as :func:`_hill` takes it) from its
    monodromy matrix: the state-transition matrix over one period T = 2 pi / W as the
    product of fourth-order Magnus steps (A at the two Gauss points of each step, from its
    Fourier series), its eigenvalues the multipliers mu, the exponents log(mu) / T (the
    fundamental strip, |Im| <= W / 2).  At least :data:`MONODROMY_STEPS` steps, 16 per
    harmonic, and 4 per unit of T |A| (the modes kept dynamic are slow where it is used).
    ``real``: A(t) is real (``coef`` in real coordinates, :func:`_real_coordinates`),
    its rounding-level imaginary part dropped: real arithmetic, a quarter of the work.

    Examples
    --------
    >>> coef = np.zeros((5, 1, 1), dtype=complex)
    >>> coef[2] = -0.1 + 2.5j  # eta' = (-0.1 + 2.5i) eta: its exponent, Im shifted by W
    >>> np.round(_monodromy(coef, 2.0, 1, 1), 12)
    array([-0.1+0.5j])
    """
    T = 2 * np.pi / W
    steps = _monodromy_steps(coef, W, H)
    h = T / steps
    d = np.arange(-2 * H, 2 * H + 1)
    # the steps a chunk at a time: memory bounded whatever the step count (a stiff
    # coordinate makes T |A| large), the product of the chunks' products in order
    chunk = chunk_rows(16.0 * (16 * s * s + 2 * d.size), steps)
    phi = np.eye(s, dtype=float if real else complex)
    for first in range(0, steps, chunk):
        phi = _magnus_steps(coef, W, d, h, np.arange(first, min(first + chunk, steps)),
                            s, real) @ phi
    mult = eigenvalues(phi)
    with np.errstate(divide="ignore"):
        lam = np.log(np.where(mult == 0, 1e-300, mult)) / T
    return fundamental_strip(lam, lam.size)


def _slider_monodromy(mu: np.ndarray, Bs: np.ndarray, Rres: np.ndarray, G0: np.ndarray,
                      E: np.ndarray, T: np.ndarray, P: np.ndarray,
                      sliders: list[tuple[np.ndarray, float, np.ndarray]], W: float
                      ) -> np.ndarray:
    """The s exponents of the linearization about a periodic motion in which friction
    elements slip, from its monodromy matrix over the N samples of the period.

    A perturbation moves a slipping element's slider with the motion and leaves it
    where the element sticks again, so the force it adds while it sticks is
    kt (du - dz), dz the slider's shift (the memory of the balance's Jacobian,
    :meth:`~resonant.system.nonlinear_elements.ElementForces.sliders`), not the
    kt du of the instantaneous tangent.  The state is the s kept modal coordinates eta
    and each slipping element's dz (fixed while it sticks, reset to du at each sample
    where it slips); A(t) is piecewise linear between the samples (each step the
    exponential of the mean of its ends' A, second order where A is smooth), a slip's
    reset at the end of its step.  The resets make the monodromy matrix singular: its
    e smallest eigenvalues (zero to rounding) belong to the sliders and are dropped.
    Depends on the samples only, not on the harmonics of Hill's matrix, whose Fourier
    series of a stick-slip A(t) converges slowly (Gibbs).

    Parameters
    ----------
    mu, Bs, Rres
        The kept poles (s,), their inputs from the nonlinear coordinates (s, m) and the
        fast modes' static flexibility (m, m).
    G0, E, T, P
        Per sample: the tangent stiffness (m, m, N), I - Rres G0 (N, m, m), the
        nonlinear coordinates' displacement (N, m, s) and force (N, m, s) per eta.
    sliders : list
        As :meth:`~resonant.system.nonlinear_elements.ElementForces.sliders` gives them.
    W : float
        The base frequency.
    """
    s, N, e = mu.size, G0.shape[2], len(sliders)
    bz = np.array([b for b, _, _ in sliders]).T                   # (m, e)
    stick = np.array([st for _, _, st in sliders]).T              # (N, e)
    Bz = bz[None] * (np.array([kt for _, kt, _ in sliders]) * stick)[:, None, :]
    Tz = -np.linalg.solve(E, Rres[None] @ Bz)                     # (N, m, e)
    Pz = np.einsum("ijn,njk->nik", G0, Tz) - Bz
    pairs = _real_coordinates(mu)
    Q, Qinv = pairs if pairs is not None else (np.eye(s), np.eye(s))
    A = np.zeros((N, s + e, s + e), dtype=complex)
    A[:, :s, :s] = Qinv @ (np.diag(mu)[None] - Bs[None] @ P) @ Q
    A[:, :s, s:] = -Qinv @ (Bs[None] @ Pz)
    reset = np.einsum("me,nmk->nek", bz, np.concatenate([T @ Q, Tz], axis=2))
    dtype = float if pairs is not None else complex
    if pairs is not None:
        A, reset = A.real, reset.real
    period = 2 * np.pi / W
    h = period / N
    chunk = chunk_rows(16.0 * 8 * (s + e) ** 2, N)
    phi = np.eye(s + e, dtype=dtype)
    for first in range(0, N, chunk):
        n = np.arange(first, min(first + chunk, N))
        step = _expm_small(h / 2 * (A[n] + A[(n + 1) % N]))
        ends = (n + 1) % N
        slips = ~stick[ends]                                      # (steps, e)
        for j in range(e):  # the slider's row of the step's end, where it slips there
            rows = np.flatnonzero(slips[:, j])
            step[rows, s + j, :] = np.einsum("rk,rkl->rl", reset[ends[rows], j], step[rows])
        phi = _product(step) @ phi
    mult = eigenvalues(phi)
    mult = mult[np.argsort(np.abs(mult), kind="stable")[e:]]
    with np.errstate(divide="ignore"):
        lam = np.log(np.where(mult == 0, 1e-300, mult)) / period
    return fundamental_strip(lam, lam.size)


def _monodromy_steps(coef: np.ndarray, W: float, H: int) -> int:
    """The Magnus steps over a period: at least :data:`MONODROMY_STEPS`, 16 per harmonic
    and 4 per unit of T |A|."""
    size = float(np.abs(coef).sum(axis=(0, 2)).max(initial=0.0))
    return max(MONODROMY_STEPS, 16 * H, math.ceil(4 * 2 * np.pi / W * size))


def _hill_is_cheaper(coef: np.ndarray, W: float, H: int, s: int) -> bool:
    """Whether Hill's matrix (s (2H + 1) rows, one eigenvalue problem of about 10 rows^3
    flops) costs less than the monodromy matrix (about 15 s^3 flops a step): a stiff
    coordinate makes T |A|, and so the steps, large; neither is then needed twice."""
    rows = s * (2 * H + 1)
    return 10.0 * rows**3 <= 15.0 * _monodromy_steps(coef, W, H) * s**3 and \
        16.0 * rows * rows <= budget()


def _magnus_steps(coef: np.ndarray, W: float, d: np.ndarray, h: float, steps: np.ndarray,
                  s: int, real: bool) -> np.ndarray:
    """The product of the fourth-order Magnus steps ``steps`` (of length h) of
    eta' = A(t) eta, the last on the left."""
    gauss = 0.5 / math.sqrt(3)
    t = (steps[:, None] + 0.5 + np.array([-gauss, gauss])) * h   # (steps, 2)
    # A at every Gauss point at once: (2 steps, offsets) @ (offsets, s s), one product
    A = (np.exp(1j * W * t.reshape(-1, 1) * d) @ coef.reshape(d.size, s * s)
         ).reshape(len(steps), 2, s, s)
    if real:
        A = np.ascontiguousarray(A.real)
    A1, A2 = A[:, 0], A[:, 1]
    omega = h / 2 * (A1 + A2) + math.sqrt(3) / 12 * h * h * (A2 @ A1 - A1 @ A2)
    return _product(_expm_small(omega))


def _expm_small(omega: np.ndarray) -> np.ndarray:
    """exp of each matrix of the stack ``omega`` (k, s, s): the [7/7] Pade approximant
    with scaling and squaring to a 1-norm of at most 0.95 (Higham 2005, "The scaling and
    squaring method for the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26:
    the degree ``scipy.linalg.expm`` takes for these norms, backward error below the unit
    roundoff), batched: ``scipy.linalg.expm`` loops over a stack in Python, and the
    monodromy's steps are many small matrices of norm about 1/4.

    Examples
    --------
    >>> import scipy.linalg
    >>> a = np.array([[[0.1, 0.3], [-0.2, 0.05j]], [[2.0, -1.0], [0.5, 1.5]]])
    >>> bool(np.allclose(_expm_small(a), scipy.linalg.expm(a), rtol=1e-14, atol=1e-14))
    True
    """
    norm = float(np.abs(omega).sum(axis=-2).max(initial=0.0))
    squarings = max(0, math.ceil(math.log2(norm / PADE7_THETA))) if norm > PADE7_THETA else 0
    x = omega / 2.0 ** squarings
    b = PADE7
    eye = np.broadcast_to(np.eye(omega.shape[-1], dtype=omega.dtype), omega.shape)
    x2 = x @ x
    x4 = x2 @ x2
    x6 = x4 @ x2
    u = x @ (b[7] * x6 + b[5] * x4 + b[3] * x2 + b[1] * eye)
    v = b[6] * x6 + b[4] * x4 + b[2] * x2 + b[0] * eye
    result: np.ndarray = np.linalg.solve(v - u, v + u)
    for _ in range(squarings):
        result = result @ result
    return result


def _product(factors: np.ndarray) -> np.ndarray:
    """factors[-1] @ ... @ factors[1] @ factors[0] of a stack (k, s, s), pairwise in
    batched products (log2 k of them)."""
    while factors.shape[0] > 1:
        if factors.shape[0] % 2:
            factors = np.concatenate([factors[:-2], (factors[-1] @ factors[-2])[None]])
            continue
        factors = factors[1::2] @ factors[0::2]
    result: np.ndarray = factors[0]
    return result


def _dynamic_modes(mu: np.ndarray, top: float, H: int) -> np.ndarray:
    """Which first-order modes the stability analysis keeps dynamic (the same at every
    point of a branch): all of them where Hill's matrix stays small (at most
    :data:`SMALL_HILL` rows with H harmonics), else those up to :data:`DYNAMIC_FACTOR`
    times the highest base frequency ``top`` (at most :data:`MAX_DYNAMIC`, the slowest)."""
    if mu.size * (2 * H + 1) <= SMALL_HILL:
        return np.ones(mu.size, dtype=bool)
    return _slowest_below(mu, DYNAMIC_FACTOR * top)


def _slowest_below(mu: np.ndarray, frequency: float) -> np.ndarray:
    """The first-order modes up to ``frequency`` (|Im mu|), at most :data:`MAX_DYNAMIC` of
    them, the slowest."""
    keep: np.ndarray = np.abs(mu.imag) <= frequency
    if keep.sum() > MAX_DYNAMIC:
        keep = np.zeros(mu.size, dtype=bool)
        keep[np.argsort(np.abs(mu.imag), kind="stable")[:MAX_DYNAMIC]] = True
    return keep


def _slider_modes(mu: np.ndarray, W: float) -> np.ndarray:
    """Which first-order modes the stability analysis of a model with friction elements
    keeps dynamic at the base frequency W (:func:`_slider_monodromy`, or Hill's matrix
    where every element sticks throughout): all of them up to :data:`MAX_DYNAMIC`, else those up to
    :data:`DYNAMIC_FACTOR` W (at most :data:`MAX_DYNAMIC`, the slowest).  Its cost does
    not grow with the harmonics, so neither H nor the sweep's range choose them: the
    exponents of one periodic motion are the same whichever branch finds it."""
    if mu.size <= MAX_DYNAMIC:
        return np.ones(mu.size, dtype=bool)
    return _slowest_below(mu, DYNAMIC_FACTOR * W)


def _real_unstable(lam: np.ndarray, W: float) -> int:
    """The count of unstable exponents with no oscillating part (multipliers > 1)."""
    return classify(lam, W)[0]


def _match_parity(lam: np.ndarray, W: float, odd: bool) -> np.ndarray:
    """The exponents with the count of real unstable ones made odd or even as the sign of
    det J says (exact for the condensed balance: det J_full = det D det J with det D of
    one sign along a branch, and a real exponent crossing zero flips it): the real
    exponent nearest zero, which the modal truncation puts on the wrong side near a fold
    or a branch point, changes side."""
    if (_real_unstable(lam, W) % 2 == 1) == odd:
        return lam
    real = np.nonzero(np.abs(lam.imag) < 0.02 * W)[0]
    if real.size == 0:  # the pair that turns real at the fold is still complex here
        j = int(np.argmin(np.abs(lam.imag)))
        lam = lam.copy()
        lam[j] = lam[j].real
    else:
        j = real[np.argmin(np.abs(lam[real].real))]
    floor = 2 * math.log1p(STABILITY_TOL) * W / (2 * np.pi)
    out = lam.copy()
    out[j] = (floor if lam[j].real <= 0 else -floor) + 1j * lam[j].imag \
        if abs(lam[j].real) < floor else -lam[j].real + 1j * lam[j].imag
    return out


# -- the model ----------------------------------------------------------------------------

class BranchOutputs:
    """The outputs of a ``[matrices]`` model along a branch of the condensed balance.

    Parameters
    ----------
    series : OutputSeries
        The outputs, compiled.
    rows : ndarray of int
        For each coordinate of ``series.coordinates``, its row among the kept ones.
    values : callable
        p -> the parameter values at the continuation parameter p.
    H : int
        Harmonics.
    """

    def __init__(self, series: OutputSeries, rows: np.ndarray,
                 values: Callable[[float], dict[str, float]], H: int) -> None:
        self.series, self.rows, self.values, self.H = series, rows, values, H

    def deviations(self, coef: np.ndarray, W: float, p: float, tau: np.ndarray
                   ) -> np.ndarray:
        """(outputs, k): each output minus its value at rest, at the phases tau, from the
        kept rows' coefficients (rows, 2H+1)."""
        phi, dphi, d2phi = basis(tau, self.H)
        c = coef[self.rows]
        samples = np.stack([c @ phi.T, W * (c @ dphi.T), W * W * (c @ d2phi.T)])
        values = self.values(p)
        rest = self.series(np.zeros((3, len(self.rows), 1)), values)
        result: np.ndarray = self.series(samples, values) - rest
        return result

    def peaks(self, coef: np.ndarray, W: float, p: float) -> np.ndarray:
        """Peak |deviation| over one period of every output."""
        return periodic_peak(lambda tau: self.deviations(coef, W, p, tau),
                             len(self.series.names))

    def coefficients(self, coef: np.ndarray, W: float, p: float, N: int) -> np.ndarray:
        """(outputs, 2H+1): the first H harmonics of every output's deviation."""
        tau = 2 * np.pi * np.arange(N) / N
        F = np.fft.rfft(self.deviations(coef, W, p, tau), axis=1)
        out = np.empty((F.shape[0], 2 * self.H + 1))
        out[:, 0] = F[:, 0].real / N
        out[:, 1::2] = 2.0 / N * F[:, 1:self.H + 1].real
        out[:, 2::2] = -2.0 / N * F[:, 1:self.H + 1].imag
        return out


@dataclass(frozen=True)
class _Setup:
    M: Any
    C: Any
    K: Any
    loads: np.ndarray
    orders: list[tuple[int, int]]
    base: Callable[[float], float]
    forces: Callable[[float], ElementForces]
    values: Callable[[float], dict[str, float]]


def _setup(system: NonlinearSystem, parts: LocalElements, param: str, start: float,
           stop: float) -> _Setup:
    """The fixed matrices, the loads with their harmonic orders and the parameter maps."""
    batch = parts.linear.batch(param, np.array([start, stop], dtype=float))
    if not batch.constant:
        raise AnalysisError(f"M, C and K change with '{param}': the condensed harmonic "
                            "balance needs them fixed")
    columns = []
    for h in batch.harmonics:
        f_s, f_c = np.atleast_2d(h.F_S), np.atleast_2d(h.F_C)
        if not (np.allclose(f_s, f_s[:1]) and np.allclose(f_c, f_c[:1])):
            raise AnalysisError(f"a harmonic load changes with '{param}': the condensed "
                                "harmonic balance needs fixed load vectors")
        columns.append(f_c[0] - 1j * f_s[0])
    if not columns:
        raise AnalysisError("nothing excites the model periodically (no [[harmonic]] load)")
    points: dict[float, np.ndarray] = {}

    def point(p: float) -> np.ndarray:
        """All parameter values at ``param = p`` (cached: a branch revisits its points)."""
        if p not in points:
            if len(points) > 256:
                points.clear()
            points[p] = system.parameter_point(param, float(p))
        return points[p]

    def values(p: float) -> dict[str, float]:
        return {k: float(v) for k, v in zip(system.parameters, point(p))}

    def omegas(p: float) -> np.ndarray:
        return np.asarray(np.abs(parts.frequencies(point(p))))

    w0 = omegas(start)
    lowest = float(w0[w0 > 0].min()) if np.any(w0 > 0) else 0.0
    if not lowest > 0:
        raise AnalysisError("every excitation frequency is zero at the start value")
    ratios = w0 / lowest
    if np.any(np.abs(ratios - np.round(ratios)) > 1e-9 * np.maximum(ratios, 1)):
        raise AnalysisError("the excitation frequencies are not integer multiples of the "
                            "lowest: the condensed harmonic balance needs one base frequency")
    index = int(np.argmin(np.where(w0 > 0, w0, np.inf)))
    orders = [(int(round(r)), j) for j, r in enumerate(ratios)]

    def base(p: float) -> float:
        return float(omegas(p)[index])

    cache: dict[float, ElementForces] = {}

    def forces(p: float) -> ElementForces:
        if p not in cache:
            if len(cache) > 256:
                cache.clear()
            cache[p] = parts.forces(point(p))
        return cache[p]

    return _Setup(batch.M, batch.C, batch.K, np.array(columns).T, orders, base, forces,
                  values)


def _start_point(hb: CondensedBalance, start: float) -> np.ndarray:
    """The linear response at the start (the elements' forces left out), refined; where
    the elements change it too much for Newton, the loads are raised step by step from
    a small fraction (where the linear response is the answer) to their full size."""
    W = hb.base(start)
    T = hb.transfers(W)
    linear = hb.basis.real(hb.linear_response(T, slice(0, hb.m))).ravel()
    scale = max(float(np.abs(linear).max()), 1e-300)
    x0, ok = hb.newton(linear, start, scale)
    if ok:
        return x0
    try:
        return _load_steps(hb, start, linear, scale)
    finally:
        hb.load_scale = 1.0


def _load_steps(hb: CondensedBalance, start: float, linear: np.ndarray, scale: float
                ) -> np.ndarray:
    """Newton at the loads times s for s rising from 1/64 to 1 (steps halved where Newton
    fails, the last solution scaled up as the predictor)."""
    done, x, step = 0.0, np.zeros_like(linear), 1.0 / 64
    while done < 1.0:
        trial = min(1.0, done + step)
        hb.load_scale = trial
        guess = linear * trial if done == 0.0 else x * (trial / done)
        found, ok = hb.newton(guess, start, scale * trial)
        if ok:
            done, x, step = trial, found, step * 2
        elif step > 1e-3:
            step /= 4
        else:
            raise AnalysisError(
                f"harmonic balance did not converge at the start value {start:g}, neither "
                f"from the linear response nor with the loads raised step by step (stuck at "
                f"{done:.3g} of them); start the range where the response is small")
    return x


def _linear_sweep(system: LinearSystem, hb: CondensedBalance, param: str,
                  band: tuple[float, float], warnings: list[str], deadline: Deadline
                  ) -> FrequencyResponse | None:
    """The linear response over the band, of the kept coordinates (and every output)."""
    try:
        return sweep(system, param, np.linspace(min(band), max(band), 201),
                     names=list(hb.kept_coordinates()), deadline=deadline)
    except AnalysisError as exc:
        warnings.append(f"no linear sweep to compare with: {exc}")
        return None


def default_samples(elements: Sequence[NonlinearElement], harmonics: int) -> int:
    """Samples per period of the alternating frequency-time scheme: 8 per harmonic
    coefficient (at least 64) for smooth forces; for a gap or a friction element, whose
    force has kinks between samples and whose harmonics converge only as 1/N^2, at
    least :data:`NONSMOOTH_SAMPLES` (fewer leave steps in the residual that the
    continuation takes for folds).

    Examples
    --------
    >>> default_samples((), 7)
    120
    """
    smooth = max(64, 8 * (2 * harmonics + 1))
    if any(not e.law.smooth for e in elements):
        return max(NONSMOOTH_SAMPLES, 2 * smooth)
    return smooth


def condensed_sweep(system: NonlinearSystem, param: str, start: float, stop: float, *,
                    harmonics: int | None = None, points: int = 101,
                    observe: Sequence[str] | None = None, samples: int | None = None,
                    exact: bool | None = None, tol: float = DEFAULT_TOL,
                    linear: bool = True, deadline: Deadline = NO_DEADLINE
                    ) -> NonlinearResponse:
    """Follow the periodic response of a ``[matrices]`` model with ``[[nonlinear]]`` elements.

    Parameters
    ----------
    system : NonlinearSystem
        The system of a ``[matrices]`` model with ``[[nonlinear]]`` elements
        (:func:`resonant.system.nonlinear_system`), whose ``local_elements`` it condenses
        onto.
    param : str
        The continuation parameter (usually the excitation frequency); M, C, K and
        the load vectors must not depend on it.
    start, stop : float
        The range; the continuation starts from the linear response at ``start``.
    harmonics : int, optional
        H, kept as given; default: 7, raised by the full balance's rule
        (:func:`~resonant.analyses.hb_solver.raise_harmonics`) until the highest
        harmonics of the kept coordinates carry at most 1e-6 of the amplitude (at most
        40, and at most ``samples`` / 4 - 1 with ``samples`` given).
    points : int
        About this many steps across the range (more near folds).
    observe : sequence of str, optional
        Further coordinates whose amplitudes are recovered (the nonlinear ones always are).
    samples : int, optional
        Time samples per period of the alternating frequency-time scheme (default
        :func:`default_samples`).
    exact : bool, optional
        Use the full matrices instead of a reduced model (default: for n <= 400).
    tol : float
        Tolerance of the reduced model of the linear part.
    linear : bool
        Also compute the linear sweep of the reported coordinates over the range.
    deadline : Deadline, optional

    Returns
    -------
    NonlinearResponse
        With the nonlinear and observed coordinates; ``warnings`` carries the
        reduced model's estimated error, and the truncation where the highest harmonics
        carry more than 1e-6 (with the harmonic resonance behind it, where found).

    Raises
    ------
    AnalysisError
        For a model without nonlinear elements, matrices or loads that change with
        ``param``, incommensurate excitations, or no convergence at the start.
    """
    parts = system.local_elements
    if parts is None:
        raise AnalysisError("the condensed harmonic balance needs a [matrices] model with "
                            "[[nonlinear]] elements")
    given, harmonics = harmonics, DEFAULT_HARMONICS if harmonics is None else harmonics
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise AnalysisError("the range must be two different finite numbers")
    BalanceOptions(harmonics=harmonics, points=points, samples=samples, tol=tol)  # checks
    setup = _setup(system, parts, param, start, stop)
    coords = system.coordinates
    position = {q: i for i, q in enumerate(coords)}
    unknown = [q for q in (observe or ()) if q not in position]
    if unknown:
        raise AnalysisError(f"unknown coordinate(s) {', '.join(unknown)}")
    elements = setup.forces(start)
    nl = list(elements.dofs)
    series = parts.outputs
    wanted = [*(observe or ()), *(series.coordinates if series else ())]
    observed = list(dict.fromkeys(position[q] for q in wanted if position[q] not in nl))
    grid = np.linspace(min(start, stop), max(start, stop), 64)
    Wmax = max(setup.base(float(p)) for p in grid)
    names = tuple(coords[i] for i in nl + observed)
    balances = _Balances(setup, parts.elements, nl, observed, names, series, param, Wmax,
                         samples, exact, tol, deadline, points)
    limit = MAX_HARMONICS if samples is None else \
        max(harmonics, min(MAX_HARMONICS, samples // 4 - 1))
    hb, branch, failed = _branch(balances, harmonics, given is not None, start, stop, points,
                                 limit, deadline)
    lin, N, outputs = hb.linear, hb.basis.N, hb.outputs
    coeffs = _coefficients(hb, branch)
    lam, residual = [], 0.0
    for x, p in zip(branch.x, branch.p):
        deadline.check("during the stability analysis", analysis=True)
        R, J, blocks = hb.jacobian(x, p)
        worst = float(np.abs(R).max())
        residual = max(residual, worst if math.isfinite(worst) else math.inf)
        lam.append(hb.exponents(J, blocks))
    Ws = np.array([hb.base(p) for p in branch.p])
    width = max((v.size for v in lam), default=0)
    # a point with fewer kept modes (friction: chosen by its own W) padded with exponents
    # of multiplier 0, stable and never the one that crosses
    lam_arr = np.array([np.pad(v, (0, width - v.size), constant_values=PAD_EXPONENT * Ws[i])
                        for i, v in enumerate(lam)])
    mult = np.exp(lam_arr * (2 * np.pi / Ws)[:, None])
    stable = np.all(np.abs(mult) <= 1 + STABILITY_TOL, axis=1)
    amps = np.asarray(series_peaks(coeffs))
    out_coeffs = None
    if outputs:
        out_coeffs = np.array([outputs.coefficients(c, W, p, N)
                               for c, W, p in zip(coeffs, Ws, branch.p)])
        amps = np.hstack([amps, np.array([outputs.peaks(c, W, p)
                                          for c, W, p in zip(coeffs, Ws, branch.p)])])
    special = special_points(hb, branch, lam_arr, Ws, amps, deadline)
    warnings = list(branch.warnings)
    trunc = float(truncation(coeffs, hb.H).max()) if coeffs.size else 0.0
    if hb.H > 1 and trunc > TRUNCATION_TOL:
        warnings.append(_truncation_warning(hb, coeffs, Ws, branch.p, given is not None,
                                            failed, elements))
    if lin.exact is not None:
        warnings.append(_exact_warning(lin))
    elif lin.error > 0:
        warnings.append(f"linear part: reduced model of {lin.size} vectors, largest error "
                        f"{lin.error:.2g} of its transfer functions where checked against "
                        "exact solves (an estimate, not a bound)")
    linear_response = _linear_sweep(parts.linear, hb, param, (start, stop), warnings,
                                    deadline) if linear else None
    return NonlinearResponse(
        title=system.title, parameter=param, coordinates=names, values=np.array(branch.p),
        amplitudes=MappingProxyType({nm: amps[:, j] for j, nm in enumerate(hb.names())}),
        coefficients=coeffs, base_frequencies=Ws, stable=stable, multipliers=mult,
        special_points=tuple(special), harmonics=hb.H, residual=residual,
        truncation=trunc, start=float(start), stop=float(stop),
        linear=linear_response, warnings=tuple(warnings),
        outputs=series.names if series else (), output_coefficients=out_coeffs)


def _exact_warning(lin: LinearPart) -> str:
    """What the exact receptances that replaced the reduced model cost."""
    assert lin.exact is not None
    return (f"linear part: {lin.why}; the balance used the exact receptances instead "
            f"({lin.exact.solves} sparse LU solves at the harmonics' frequencies, "
            f"{lin.exact.seconds:.3g} s), the stability analysis that reduced model "
            f"({lin.size} vectors, estimated error {lin.error:.2g}); a larger tolerance "
            "(--tol) keeps the reduced model and is faster")


class _Balances:
    """The condensed balance of one sweep at any H: the linear part built once per band
    (a reduced model holds up to the band it was built for, H W_max; the full matrices
    for every H), the samples per period the default for H unless given."""

    def __init__(self, setup: _Setup, elements: Sequence[NonlinearElement], nl: list[int],
                 observed: list[int],
                 names: tuple[str, ...], series: OutputSeries | None, param: str,
                 Wmax: float, samples: int | None, exact: bool | None, tol: float,
                 deadline: Deadline, points: int = 0) -> None:
        self.setup, self.elements, self.nl, self.observed = setup, elements, nl, observed
        self.names, self.series, self.param, self.Wmax = names, series, param, Wmax
        self.samples, self.exact, self.tol, self.deadline = samples, exact, tol, deadline
        self.points = points
        self.parts: list[LinearPart] = []

    def at(self, H: int) -> CondensedBalance:
        top = H * self.Wmax * 1.05
        lin = next((part for part in self.parts if part.top >= top), None)
        if lin is None:
            setup = self.setup
            lin = linear_part(setup.M, setup.C, setup.K, setup.loads, self.nl, self.observed,
                              np.linspace(0.0, top, BAND_POINTS), exact=self.exact,
                              tol=self.tol, deadline=self.deadline)
            self.parts.append(lin)
        if lin.exact is not None:
            lin.exact.expected = EXACT_SOLVES * H * self.points
        N = self.samples or default_samples(self.elements, H)
        outputs = None
        if self.series is not None:
            kept = {q: j for j, q in enumerate(self.names)}
            rows = np.array([kept[q] for q in self.series.coordinates], dtype=int)
            outputs = BranchOutputs(self.series, rows, self.setup.values, H)
        return CondensedBalance(lin, self.setup.forces, self.setup.orders, self.setup.base,
                                H, N, self.param, self.names, self.Wmax, outputs)


    def trial(self, H: int) -> CondensedBalance:
        """The balance at H for the automatic choice of H, which solves one point at each
        H tried: where no linear part built so far holds up to H W_max, the first one's
        poles with exact receptances (H + 1 sparse solves at the point's W) instead of a
        reduced model of the wider band (8 s at H = 11 and 71 s at H = 15 on a
        2,500-coordinate grid, docs/performance-nonlinear.md), built for the H chosen only."""
        top = H * self.Wmax * 1.05
        if not self.parts or any(part.top >= top for part in self.parts):
            return self.at(H)
        first, setup = self.parts[0], self.setup
        n = setup.M.shape[0]
        rows = self.nl + [i for i in self.observed if i not in self.nl]
        B = np.zeros((n, len(self.nl)), dtype=complex)
        B[self.nl, range(len(self.nl))] = 1.0
        B = np.hstack([B, np.asarray(setup.loads, dtype=complex).reshape(n, -1)])
        exact = ExactTransfers(setup.M, setup.C, setup.K, B, rows,
                               f"the automatic choice of H tried {H} harmonics", self.deadline)
        lin = replace(first, exact=exact, top=math.inf)
        N = self.samples or default_samples(self.elements, H)
        return CondensedBalance(lin, setup.forces, setup.orders, setup.base, H, N, self.param,
                                self.names, self.Wmax, None)


def _coefficients(hb: CondensedBalance, branch: Branch) -> np.ndarray:
    """(points, kept rows, 2H+1) coefficients along the branch."""
    return np.array([hb.coefficients(x, p) for x, p in zip(branch.x, branch.p)])


def _branch(balances: _Balances, H: int, given: bool, start: float, stop: float,
            points: int, limit: int, deadline: Deadline
            ) -> tuple[CondensedBalance, Branch, str]:
    """The branch with H harmonics; when H is not given, H is raised by the full balance's
    rule (:func:`~resonant.analyses.hb_solver.raise_harmonics`) at the point of the branch
    whose highest harmonics carry most of the kept rows' amplitude, and the branch followed
    again, until they carry at most TRUNCATION_TOL or H reaches ``limit``.  Also: why the
    last round's raise failed ('' when it did not)."""
    hb = balances.at(H)
    branch = follow(hb, _start_point(hb, start), start, stop, points, deadline,
                    relative=True)
    failed = ""
    while not given and hb.H < limit:
        shares = truncation(_coefficients(hb, branch), hb.H)
        worst = int(np.argmax(shares))
        if shares[worst] <= TRUNCATION_TOL:
            break
        raised, failed = _raise(balances, hb, branch.x[worst], float(branch.p[worst]),
                                limit, deadline)
        if raised is hb:
            break
        hb = raised
        branch = follow(hb, _start_point(hb, start), start, stop, points, deadline,
                        relative=True)
    return hb, branch, failed


def _raise(balances: _Balances, hb: CondensedBalance, x: np.ndarray, p: float, limit: int,
           deadline: Deadline) -> tuple[CondensedBalance, str]:
    """The balance at the H the shared rule reaches at the point (x, p) (``hb`` itself when
    the first raise fails), and why a raise failed ('' when none did)."""
    trials = {hb.H: hb}
    failed = ""

    def converge(x: np.ndarray, H: int) -> tuple[np.ndarray, bool]:
        nonlocal failed
        try:
            trials[H] = balances.trial(H)
        except DeadlineExceeded:
            raise
        except AnalysisError as exc:
            failed = f"no linear part for {H} harmonics ({exc})"
            return x, False
        x_new, ok = trials[H].newton(x, p, float(np.linalg.norm(x)))
        if not ok:
            failed = f"the balance with {H} harmonics did not converge at " \
                     f"{balances.param} = {p:.6g}"
        return x_new, ok

    def share(x: np.ndarray, H: int) -> float:
        return float(truncation(trials[H].coefficients(x, p)[None], H)[0])

    H, _ = raise_harmonics(x, hb.m, hb.H, converge, share, limit, lambda: deadline.check(
        "while raising the number of harmonics", analysis=True))
    if H == hb.H:
        return hb, failed
    try:  # the linear part of the band of the H chosen (the trials' were exact solves)
        return balances.at(H), failed
    except DeadlineExceeded:
        raise
    except AnalysisError as exc:
        return hb, f"no linear part for {H} harmonics ({exc})"


def _ordinal(k: int) -> str:
    suffix = "th" if 10 <= k % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(k % 10, "th")
    return f"{k}{suffix}"


def harmonic_resonance(mu: np.ndarray, W: float, coef: np.ndarray
                       ) -> tuple[int, int, float] | None:
    """The highest harmonic of a periodic motion that resonates with a mode.

    Parameters
    ----------
    mu : ndarray
        Poles of the linear part (its modes: those with Im mu > 0, natural frequencies
        |mu|, counted from the lowest).
    W : float
        Base frequency.
    coef : ndarray
        (rows, 2H+1) coefficients of the motion.

    Returns
    -------
    (k, j, w_j) or None
        The highest harmonic k >= 2 that carries more than TRUNCATION_TOL of a row's
        amplitude and whose frequency k W lies within :data:`RESONANCE_BAND` of the
        natural frequency w_j of mode j; None when there is none.

    Examples
    --------
    >>> mu = np.array([-0.01 + 1j, -0.01 - 1j, -0.01 + 3.1j, -0.01 - 3.1j])
    >>> k, j, w = harmonic_resonance(mu, 1.0, np.array([[0.0, 1.0, 0.0, 0.0, 0.0, 0.01, 0.0]]))
    >>> k, j, round(w, 4)  # the 3rd harmonic, 3 rad/s, within 5 % of mode 2's 3.1 rad/s
    (3, 2, 3.1)
    """
    freqs = np.sort(np.abs(mu[mu.imag > 0]))
    if freqs.size == 0:
        return None
    amps = np.hypot(coef[:, 1::2], coef[:, 2::2])
    total = np.abs(coef[:, 0]) + amps.sum(axis=1)
    share = (amps / np.where(total > 0, total, 1.0)[:, None]).max(axis=0, initial=0.0)
    for k in range(amps.shape[1], 1, -1):
        if share[k - 1] <= TRUNCATION_TOL:
            continue
        j = int(np.argmin(np.abs(k * W - freqs)))
        if abs(k * W - freqs[j]) <= RESONANCE_BAND * freqs[j]:
            return k, j + 1, float(freqs[j])
    return None


def _truncation_warning(hb: CondensedBalance, coeffs: np.ndarray, Ws: np.ndarray,
                        values: Sequence[float], given: bool, failed: str,
                        elements: ElementForces) -> str:
    """Why the highest harmonics still carry more than TRUNCATION_TOL, in words."""
    shares = truncation(coeffs, hb.H)
    worst = int(np.argmax(shares))
    stopped = f"the automatic choice stopped there: {failed}" if failed else \
        f"the most the automatic choice takes with {hb.basis.N} samples per period " \
        "(4 per harmonic)" if hb.H < MAX_HARMONICS else ""
    cause = ""
    found = harmonic_resonance(hb.linear.mu, float(Ws[worst]), coeffs[worst])
    if found is not None:
        k, j, w = found
        cause = f"the {_ordinal(k)} harmonic ({k * Ws[worst]:.4g} rad/s) resonates with " \
                f"mode {j} ({w:.4g} rad/s)"
    elif any(not e.law.smooth for e in elements.elements):
        cause = "the force of a gap or friction element has kinks, so its harmonics decay " \
                "slowly"
    return truncation_warning(float(shares[worst]), hb.H, given,
                              f"{hb.param} = {values[worst]:.6g}", stopped, cause)


__all__ = ["condensed_sweep", "default_samples", "harmonic_resonance",
           "CondensedBalance", "LinearPart", "linear_part", "EXACT_SIZE",
           "ExactTransfers"]
