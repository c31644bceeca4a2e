"""The nonlinear periodic steady state: harmonic balance, arc-length continuation, stability.

The full Lagrange equations ``E = mass(q) q'' + rest(q, q', t) = 0`` of
:func:`resonant.derivation.nonlinear_equations` (the equations ``simulate
--nonlinear`` integrates) are solved for periodic motions of the excitation's
base frequency W (the largest common divisor of the signals' frequencies), in
the time tau = W t::

    q(tau) = q_ref + a_0 + sum_{k=1..H} a_k cos(k tau) + b_k sin(k tau)

**Residual** by the alternating frequency-time method: q, q' = W dq/dtau and
q'' = W^2 d^2q/dtau^2 are sampled at N >= 4H + 1 (at least 32) points of one
period, E is evaluated there (compiled once with :func:`sympy.lambdify`), and
its first H harmonics are taken with :func:`numpy.fft.rfft`.

**Jacobian** exact: the partial derivatives dE/dq, dE/dq', dE/dq'' are derived
symbolically and compiled once; the chain rule through the Fourier basis gives
``dR/dx = P [G0 Phi + W G1 Phi' + W^2 G2 Phi'']`` (P the projection, Phi the
sampled basis).  Only the derivative with respect to the continuation
parameter is a central finite difference.

**Continuation** by pseudo-arclength in (x / s_x, p / s_p) with a predictor
along the tangent, Newton correctors with the analytical Jacobian and step
control from the Newton iteration count, the relative change of the
amplitude and of the parameter per step.  Folds are passed; they are located
where the parameter component of the tangent changes sign.

**Stability** by Hill's method: with q = q_p + e^{lambda t} p(tau) the
linearized equations give the quadratic eigenvalue problem
``(D0 + lambda D1 + lambda^2 D2) v = 0``, ``D0`` the harmonic-balance
Jacobian, ``D1 = Gal(G1 + 2 W G2 d/dtau)``, ``D2 = Gal(G2)``.  Of its
2n(2H+1) eigenvalues the 2n with the smallest |Im lambda| (the fundamental
strip) are the Floquet exponents; the multipliers are ``exp(lambda T)``.  A
point is stable when every |mu| <= 1 + 1e-6.  Where the count of multipliers
outside the unit circle changes, the kind is read from the crossing
multiplier: real positive -> ``fold`` (or ``branch`` when the tangent does not
turn), real negative -> ``period-doubling``, complex pair -> ``neimark-sacker``.

Examples
--------
>>> from resonant.api import loads
>>> model = loads('''
... [parameters]
... k3 = 0.5
... omega = 1
... [coordinates]
... x = ""
... [signals]
... F = "0.01*cos(omega*t)"
... [energy]
... T = "x'^2/2"
... U = "x^2/2 + k3*x^4/4"
... D = "0.1*x'^2/2"
... [[force]]
... generalized = { x = "F" }
... ''')
>>> r = nonlinear_sweep(model.linearize(), "omega", 0.5, 1.5, harmonics=3, points=40)
>>> r.special_points, bool(r.stable.all())
((), True)
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from fractions import Fraction
from functools import reduce
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy

from ..deadline import NO_DEADLINE, Deadline
from ..derivation import nonlinear_equations
from ..derivation.harmonics import NotHarmonic, decompose
from ..errors import AnalysisError
from ..expressions import compilable
from ..model import TIME, Model, symbol
from ..system import LinearSystem, linear_system
from ..system.base import parameter_values
from .simulate import _equilibrium_values, _peak, _signal_function
from .stationary import freeze_fields, stationary
from .sweep import FrequencyResponse, sweep

if TYPE_CHECKING:  # pragma: no cover
    pass

#: default number of harmonics (the start of the automatic choice)
DEFAULT_HARMONICS = 7
#: the automatic choice adds harmonics until the highest carry less than this
TRUNCATION_TOL = 1e-6
MAX_HARMONICS = 40
#: Newton: relative step size that ends the iteration, and its iteration limit
NEWTON_TOL = 1e-11
NEWTON_MAX = 12
#: a multiplier with |mu| > 1 + this is unstable
STABILITY_TOL = 1e-6
#: largest relative change of the coefficient vector per continuation step
MAX_RELATIVE_CHANGE = 0.08
SPECIAL_KINDS = ("fold", "period-doubling", "neimark-sacker", "branch")


@dataclass(frozen=True)
class SpecialPoint:
    """A point where the stability or the direction of the branch changes."""

    kind: str
    value: float
    amplitudes: Mapping[str, float]
    index: int

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "value": self.value, "amplitudes": dict(self.amplitudes)}


@dataclass(frozen=True)
class NonlinearResponse:
    """The periodic steady state of the full equations, followed along a parameter.

    Attributes
    ----------
    parameter : str
        The continuation parameter.
    values : numpy.ndarray
        Its value at every branch point, in the order of the continuation.
    amplitudes : mapping
        ``coordinate -> peak |deviation from the reference state|`` over one period.
    coefficients : numpy.ndarray
        (points, n, 2H+1): per coordinate ``[a_0, a_1, b_1, ..., a_H, b_H]``.
    base_frequencies : numpy.ndarray
        The base frequency W (rad/s) at every point.
    stable : numpy.ndarray
        bool per point.
    multipliers : numpy.ndarray
        (points, 2n) Floquet multipliers (Hill's method).
    special_points : tuple of SpecialPoint
    harmonics : int
        H.
    residual : float
        The largest harmonic-balance residual (max |R|) of the branch.
    truncation : float
        The largest relative amplitude of the highest harmonic pair (H, H-1).
    linear : FrequencyResponse or None
        The linear sweep over the same range, for comparison.
    """

    title: str
    parameter: str
    coordinates: tuple[str, ...]
    values: np.ndarray
    amplitudes: Mapping[str, np.ndarray]
    coefficients: np.ndarray
    base_frequencies: np.ndarray
    stable: np.ndarray
    multipliers: np.ndarray
    special_points: tuple[SpecialPoint, ...]
    harmonics: int
    residual: float
    truncation: float
    start: float
    stop: float
    linear: FrequencyResponse | None = None
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        freeze_fields(self)

    def harmonic_lists(self, i: int) -> dict[str, list[list[float]]]:
        """``name -> [[a_0], [a_1, b_1], ...]`` of branch point i."""
        out = {}
        for j, name in enumerate(self.coordinates):
            c = self.coefficients[i, j]
            out[name] = [[float(c[0])]] + [[float(c[2 * k - 1]), float(c[2 * k])]
                                           for k in range(1, self.harmonics + 1)]
        return out

    def peak(self) -> tuple[float, dict[str, float]] | None:
        """(value, amplitudes) of the stable point with the largest amplitude of the first
        coordinate (None when no point is stable)."""
        if not self.stable.any():
            return None
        first = self.amplitudes[self.coordinates[0]]
        i = int(np.argmax(np.where(self.stable, first, -np.inf)))
        return float(self.values[i]), {k: float(v[i]) for k, v in self.amplitudes.items()}

    def to_dict(self) -> dict[str, Any]:
        """The linear sweep's keys (when there is one) and ``branch``, ``special_points``,
        ``harmonics``, ``residual``, ``truncation``."""
        data: dict[str, Any] = self.linear.to_dict() if self.linear is not None else {
            "title": self.title, "parameter": self.parameter}
        data["warnings"] = list(data.get("warnings", [])) + list(self.warnings)
        data["branch"] = [
            {"value": float(self.values[i]),
             "amplitudes": {k: float(v[i]) for k, v in self.amplitudes.items()},
             "stable": bool(self.stable[i]),
             "harmonics": self.harmonic_lists(i)}
            for i in range(self.values.size)]
        data["special_points"] = [p.to_dict() for p in self.special_points]
        data["harmonics"] = self.harmonics
        data["residual"] = self.residual
        data["truncation"] = self.truncation
        return data

    def to_csv(self, path: str | Path) -> None:
        """One row per branch point: value, stable, the amplitudes."""
        names = list(self.amplitudes)
        with open(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow([self.parameter, "stable", *names])
            for i in range(self.values.size):
                writer.writerow([repr(float(self.values[i])), int(self.stable[i]),
                                 *(repr(float(self.amplitudes[n][i])) for n in names)])

# -- the equations -------------------------------------------------------------------------

def _base_frequency(model: Model) -> Callable[[np.ndarray], float]:
    """W(parameter values) = the largest common divisor of the signals' frequencies."""
    frequencies: list[sympy.Expr] = []
    for name, expression in model.signals.items():
        expr = expression.to_sympy(lambda n, p: TIME if n == "t" else symbol(n))
        try:
            parts = decompose(sympy.expand(expr))
        except NotHarmonic:
            raise AnalysisError(f"signal '{name}' is not a sum of harmonics: the excitation "
                                "must be periodic for a nonlinear steady state") from None
        frequencies.extend(w for w in parts if w != 0)
    if not frequencies:
        raise AnalysisError("nothing excites the model periodically (no harmonic signal): "
                            "there is no forced periodic steady state to follow")
    params = [symbol(n) for n in model.parameters]
    compiled = sympy.lambdify(params, [compilable(w) for w in frequencies], modules="numpy")
    values = np.abs(np.array(compiled(*[model.parameter_values[n] for n in model.parameters]),
                             dtype=float))
    lowest = float(values.min())
    if not lowest > 0:
        raise AnalysisError("an excitation frequency is zero at the start value")
    fractions = [Fraction(v / lowest).limit_denominator(1000) for v in values]
    if any(abs(float(f) - v / lowest) > 1e-9 * v / lowest for f, v in zip(fractions, values)):
        raise AnalysisError("the excitation frequencies are not commensurate: the excitation "
                            "is not periodic")
    denominator = reduce(math.lcm, (f.denominator for f in fractions), 1)
    index = int(np.argmin(values))

    def base(pvals: np.ndarray) -> float:
        return abs(float(compiled(*pvals)[index])) / denominator
    return base


class _Equations:
    """E, dE/dq, dE/dq', dE/dq'' of the full equations, compiled once (all parameters free)."""

    def __init__(self, model: Model, autonomous: bool = False) -> None:
        self.model = model
        eq = nonlinear_equations(model)
        self.n = n = len(model.coordinates)
        self.names = list(model.parameters)
        self.pvals = np.array([float(model.parameter_values[k]) for k in self.names])
        params = [symbol(k) for k in self.names]
        signal_subs = {s: _signal_function(model, name, order)
                       for s, (name, order) in eq.ops.registry.items()
                       if name in model.signals}
        E = (eq.mass * sympy.Matrix(eq.qdd) + eq.rest).xreplace(signal_subs)
        exprs = [*E, *E.jacobian(eq.q), *E.jacobian(eq.qd), *E.jacobian(eq.qdd)]
        self._fn = sympy.lambdify([TIME, *eq.q, *eq.qd, *eq.qdd, *params],
                                  [compilable(e) for e in exprs], modules="numpy", cse=True)
        self.equilibrium = _equilibrium_values(model)
        # autonomous (backbone curves): the frequency is an unknown, not the excitation's
        self.base = (lambda pvals: math.nan) if autonomous else _base_frequency(model)
        self.n_values = 1 + 3 * n

    def __call__(self, t: np.ndarray, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                 pvals: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        n, N = self.n, t.size
        with np.errstate(all="ignore"):
            raw = self._fn(t, *q, *qd, *qdd, *pvals)
        values = np.empty((len(raw), N))
        for i, v in enumerate(raw):  # scalars (constant entries) broadcast on assignment
            values[i] = v
        E = values[:n]
        G = values[n:].reshape(3, n, n, N)
        return E, G[0], G[1], G[2]


class _HarmonicBalance:
    """Residual, Jacobian and Hill matrices for H harmonics and one continuation parameter."""

    def __init__(self, eqs: _Equations, param: str, H: int) -> None:
        self.eqs, self.H, self.n = eqs, H, eqs.n
        self.index = eqs.names.index(param)
        self.param = param
        # parameters defined by expressions of ``param`` follow it
        probe = parameter_values(eqs.model, param, np.array([1.0, 2.0]))
        self.dependent = any(np.ndim(v) and np.ptp(np.asarray(v, dtype=float)) != 0
                             for k, v in probe.items() if k != param)
        self.m = 2 * H + 1
        self.N = N = max(32, 4 * H + 4)
        tau = 2 * np.pi * np.arange(N) / N
        k = np.arange(1, H + 1)
        self.tau = tau
        phi = np.ones((N, self.m))
        dphi = np.zeros((N, self.m))
        d2phi = np.zeros((N, self.m))
        c, s = np.cos(np.outer(tau, k)), np.sin(np.outer(tau, k))
        phi[:, 1::2], phi[:, 2::2] = c, s
        dphi[:, 1::2], dphi[:, 2::2] = -k * s, k * c
        d2phi[:, 1::2], d2phi[:, 2::2] = -k ** 2 * c, -k ** 2 * s
        self.phi, self.dphi, self.d2phi = phi, dphi, d2phi
        P = np.empty((self.m, N))
        P[0] = 1.0 / N
        P[1::2], P[2::2] = 2.0 / N * c.T, 2.0 / N * s.T
        self.P = P

    def pvals(self, p: float) -> np.ndarray:
        if self.dependent:
            values = parameter_values(self.eqs.model, self.param, np.array([p]))
            return np.array([float(np.asarray(values[k], dtype=float).ravel()[0])
                             for k in self.eqs.names])
        v = self.eqs.pvals.copy()
        v[self.index] = p
        return v

    def samples(self, x: np.ndarray, p: float) -> tuple[Any, ...]:
        X = x.reshape(self.n, self.m)
        pv = self.pvals(p)
        W = self.eqs.base(pv)
        q = self.eqs.equilibrium[:, None] + X @ self.phi.T
        qd = W * (X @ self.dphi.T)
        qdd = W * W * (X @ self.d2phi.T)
        return (*self.eqs(self.tau / W, q, qd, qdd, pv), W)

    def project(self, E: np.ndarray) -> np.ndarray:
        F = np.fft.rfft(E, axis=1)
        R = np.empty((self.n, self.m))
        N, H = self.N, self.H
        R[:, 0] = F[:, 0].real / N
        R[:, 1::2] = 2.0 / N * F[:, 1:H + 1].real
        R[:, 2::2] = -2.0 / N * F[:, 1:H + 1].imag
        return R.ravel()

    def residual(self, x: np.ndarray, p: float) -> np.ndarray:
        return self.project(self.samples(x, p)[0])

    def galerkin(self, *terms: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
        """Matrix of x -> P sum(G(tau) (basis x)) for (n, n, N) coefficients G."""
        T = sum(G[:, :, :, None] * basis for G, basis in terms)
        B = np.matmul(self.P, T)  # (n, n, m, m): row equation i, harmonic row; column j, k
        size = self.n * self.m
        return np.ascontiguousarray(B.transpose(0, 2, 1, 3)).reshape(size, size)

    def jacobian(self, x: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray, Any]:
        E, G0, G1, G2, W = self.samples(x, p)
        J = self.galerkin((G0, self.phi), (G1, W * self.dphi), (G2, W * W * self.d2phi))
        return self.project(E), J, (G0, G1, G2, W)

    def dp(self, x: np.ndarray, p: float) -> np.ndarray:
        h = 1e-6 * max(1.0, abs(p))
        return (self.residual(x, p + h) - self.residual(x, p - h)) / (2 * h)

    def exponents(self, J: np.ndarray, blocks: Any) -> np.ndarray:
        """The 2n Floquet exponents of Hill's method (smallest |Im| of the QEP's)."""
        import scipy.linalg

        G0, G1, G2, W = blocks
        D1 = self.galerkin((G1, self.phi), (G2, 2 * W * self.dphi))
        D2 = self.galerkin((G2, self.phi))
        size = J.shape[0]
        eye, zero = np.eye(size), np.zeros((size, size))
        A = np.block([[zero, eye], [-J, -D1]])
        B = np.block([[eye, zero], [zero, D2]])
        lam = scipy.linalg.eig(A, B, right=False)
        lam = lam[np.isfinite(lam)]
        order = np.argsort(np.abs(lam.imag), kind="stable")
        return lam[order[:2 * self.n]]

    def newton(self, x: np.ndarray, p: float, scale: float) -> tuple[np.ndarray, bool]:
        for _ in range(NEWTON_MAX):
            R, J, _ = self.jacobian(x, p)
            try:
                dx = np.linalg.solve(J, -R)
            except np.linalg.LinAlgError:
                return x, False
            x = x + dx
            if not np.all(np.isfinite(x)):
                return x, False
            if np.linalg.norm(dx) <= NEWTON_TOL * max(float(np.linalg.norm(x)), scale):
                return x, True
        return x, False


# -- continuation --------------------------------------------------------------------------

@dataclass
class _Branch:
    x: list[np.ndarray]
    p: list[float]
    tp: list[float]
    warnings: list[str]
    tangents: list[np.ndarray]
    sx: float
    sp: float

    def append(self, x: np.ndarray, p: float, t: np.ndarray) -> None:
        self.x.append(x)
        self.p.append(p)
        self.tp.append(float(t[-1]))
        self.tangents.append(t)


def _tangent(J: np.ndarray, Rp: np.ndarray, sx: float, sp: float,
             previous: np.ndarray) -> np.ndarray:
    A = np.vstack([np.hstack([J * sx, (Rp * sp)[:, None]]), previous[None, :]])
    b = np.zeros(A.shape[0])
    b[-1] = 1.0
    t = np.linalg.solve(A, b)
    t /= np.linalg.norm(t)
    return t if t @ previous >= 0 else -t


def _correct(hb: _HarmonicBalance, pred: np.ndarray, t: np.ndarray, sx: float, sp: float
             ) -> tuple[np.ndarray, bool, int]:
    """Newton on R(x, p) = 0 and t . (v - pred) = 0 from the predictor (scaled variables)."""
    v = pred.copy()
    # dR/dp (a central difference, two residuals) once at the predictor: a chord column
    # beside the exact dR/dx; the corrected point solves R = 0 all the same
    Rp = hb.dp(pred[:-1] * sx, pred[-1] * sp)
    for iterations in range(1, NEWTON_MAX + 1):
        xv, pv = v[:-1] * sx, v[-1] * sp
        R, J, _ = hb.jacobian(xv, pv)
        A = np.vstack([np.hstack([J * sx, (Rp * sp)[:, None]]), t[None, :]])
        rhs = -np.concatenate([R, [t @ (v - pred)]])
        try:
            dv = np.linalg.solve(A, rhs)
        except np.linalg.LinAlgError:
            return v, False, iterations
        v = v + dv
        if not np.all(np.isfinite(v)):
            return v, False, iterations
        if np.linalg.norm(dv) <= NEWTON_TOL * max(float(np.linalg.norm(v)), 1.0):
            return v, True, iterations
    return v, False, NEWTON_MAX


def _continue(hb: _HarmonicBalance, x0: np.ndarray, start: float, stop: float, points: int,
              deadline: Deadline) -> _Branch:
    sp = abs(stop - start)
    direction = 1.0 if stop > start else -1.0
    sx = max(float(np.linalg.norm(x0)), 1e-12)
    size = x0.size
    previous = np.zeros(size + 1)
    previous[-1] = direction
    x, p = x0, start
    R, J, _ = hb.jacobian(x, p)
    t = _tangent(J, hb.dp(x, p), sx, sp, previous)
    ds_max = 1.0 / max(points - 1, 2)
    ds_min = 1e-7
    ds = ds_max
    branch = _Branch([x], [p], [float(t[-1])], [], [t], sx, sp)
    steps = 0
    max_steps = 50 * points
    while steps < max_steps:
        steps += 1
        deadline.check(f"while following the branch ({hb.eqs.names[hb.index]} = {p:.6g})",
                       analysis=True)
        u = np.concatenate([x / sx, [p / sp]])
        v, ok, iterations = _correct(hb, u + ds * t, t, sx, sp)
        x_new, p_new = v[:-1] * sx, v[-1] * sp
        change = float(np.linalg.norm(x_new - x)) / max(float(np.linalg.norm(x)), 1e-3 * sx)
        dp_rel = abs(p_new - p) / sp
        if not ok or change > 2 * MAX_RELATIVE_CHANGE or dp_rel > 2 * ds_max:
            ds /= 2
            if ds < ds_min:
                branch.warnings.append(f"the continuation stopped at {hb.eqs.names[hb.index]} "
                                       f"= {p:.6g}: no converged step (step size below "
                                       f"{ds_min:g})")
                break
            continue
        R, J, _ = hb.jacobian(x_new, p_new)
        t_new = _tangent(J, hb.dp(x_new, p_new), sx, sp, t)
        if t_new @ t < 0.8 and ds > 1e-4:  # turned too sharply: maybe a jump between branches
            ds /= 2
            continue
        x, p, t = x_new, p_new, t_new
        if (p - stop) * direction > 0:  # passed the end: finish exactly at stop
            xs, pp = branch.x[-1], branch.p[-1]
            guess = xs + (x - xs) * (stop - pp) / (p - pp) if p != pp else x
            xe, converged = hb.newton(guess, stop, sx)
            if converged:
                branch.append(xe, stop, t)
            break
        if (p - start) * direction < -0.05 * sp:
            branch.warnings.append(f"the branch turned back out of the range at "
                                   f"{hb.eqs.names[hb.index]} = {p:.6g} (an isola or a "
                                   "closed curve); stopped there")
            branch.append(x, p, t)
            break
        branch.append(x, p, t)
        factor = 1.5 if iterations <= 3 else (1.0 if iterations <= 5 else 0.6)
        factor = min(factor, MAX_RELATIVE_CHANGE / max(change, 1e-12),
                     ds_max / max(dp_rel, 1e-12))
        ds = float(np.clip(ds * max(factor, 0.3), ds_min, ds_max * 20))
    else:
        branch.warnings.append(f"the continuation stopped after {max_steps} steps before "
                               f"reaching {stop:g}")
    return branch


def _refine(hb: _HarmonicBalance, branch: _Branch, i: int,
            g: Callable[[np.ndarray, float, np.ndarray], float], g0: float, g1: float
            ) -> tuple[np.ndarray, float] | None:
    """The point between branch points i and i+1 where g(x, p, tangent) = 0 (regula falsi
    with the Illinois modification on the arc-length coordinate)."""
    sx, sp = branch.sx, branch.sp
    t = branch.tangents[i]
    ui = np.concatenate([branch.x[i] / sx, [branch.p[i] / sp]])
    uj = np.concatenate([branch.x[i + 1] / sx, [branch.p[i + 1] / sp]])
    a, b = 0.0, float(t @ (uj - ui))
    fa, fb = g0, g1
    if not (fa * fb < 0 and b > 0):
        return None
    best: tuple[np.ndarray, float] | None = None
    for _ in range(40):
        sigma = (a * fb - b * fa) / (fb - fa)
        v, ok, _ = _correct(hb, ui + sigma * t, t, sx, sp)
        if not ok:
            return best
        x, p = v[:-1] * sx, float(v[-1] * sp)
        R, J, _ = hb.jacobian(x, p)
        f = g(x, p, _tangent(J, hb.dp(x, p), sx, sp, t))
        best = (x, p)
        if f * fb < 0:
            a, fa = b, fb
        else:
            fa /= 2
        b, fb = sigma, f
        if abs(b - a) < 1e-13 * max(1.0, abs(b)) or f == 0:
            break
    return best


def _amplitudes(coeffs: np.ndarray, H: int) -> np.ndarray:
    """(points, n) peak |deviation| over one period of the series."""
    m = 2 * H + 1
    fine = max(512, 16 * m)
    tau = 2 * np.pi * np.arange(fine) / fine
    k = np.arange(1, H + 1)
    basis = np.ones((m, fine))
    basis[1::2], basis[2::2] = np.cos(np.outer(k, tau)), np.sin(np.outer(k, tau))
    series = coeffs @ basis
    return np.array([[_peak(series[i, j]) for j in range(coeffs.shape[1])]
                     for i in range(coeffs.shape[0])]).reshape(coeffs.shape[:2])


def _truncation(coefficients: np.ndarray, H: int) -> np.ndarray:
    """Relative amplitude of the highest harmonic pair, per point (max over coordinates)."""
    c = coefficients
    amps = np.concatenate([np.abs(c[..., :1]), np.hypot(c[..., 1::2], c[..., 2::2])], axis=-1)
    total = amps.sum(axis=-1)
    top = amps[..., -2:].sum(axis=-1) if H >= 2 else amps[..., -1]
    largest = total.max(axis=-1, keepdims=True)
    significant = total > 1e-6 * np.maximum(largest, 1e-300)
    ratio = np.where(significant, top / np.where(total > 0, total, 1.0), 0.0)
    return np.asarray(ratio.max(axis=-1))


def _resize(x: np.ndarray, n: int, H_old: int, H_new: int) -> np.ndarray:
    X = x.reshape(n, 2 * H_old + 1)
    out = np.zeros((n, 2 * H_new + 1))
    k = min(H_old, H_new)
    out[:, :2 * k + 1] = X[:, :2 * k + 1]
    return out.ravel()


def _classify(lam: np.ndarray, W: float) -> tuple[int, int, int]:
    """Counts of unstable exponents: (real positive mu, real negative mu, complex)."""
    T = 2 * np.pi / W
    unstable = lam[lam.real * T > math.log1p(STABILITY_TOL)]
    phase = np.abs(unstable.imag) / W
    pos = int(np.sum(phase < 0.02))
    neg = int(np.sum(phase > 0.48))
    return pos, neg, unstable.size - pos - neg


def nonlinear_sweep(system: LinearSystem, param: str, start: float, stop: float, *,
                    harmonics: int | None = None, points: int = 101, linear: bool = True,
                    deadline: Deadline = NO_DEADLINE) -> NonlinearResponse:
    """Follow the periodic steady state of the full equations from ``start`` to ``stop``.

    Parameters
    ----------
    system : LinearSystem
        The system of a model given by its energies (``model.linearize()``).
    param : str
        Any parameter; when it sets an excitation frequency the base frequency follows.
    start, stop : float
        The range; the continuation starts from the linear stationary solution at
        ``start`` (refined by Newton) and ends at ``stop``.
    harmonics : int, optional
        H; default: 7, raised until the highest harmonics carry less than 1e-6 of the
        amplitude (at most 40).
    points : int
        About this many steps across the range in the parameter direction (more near
        folds and where the amplitude changes fast).
    linear : bool
        Also compute the linear sweep over the range (for the plot and the JSON).

    Raises
    ------
    AnalysisError
        For a ``[matrices]`` model, a non-periodic excitation, an unknown parameter,
        or when Newton does not converge at the start.
    """
    model = system._model()
    if model.matrices is not None:
        raise AnalysisError("a [matrices] model has no nonlinear equations: --nonlinear needs "
                            "a model given by its energies")
    if param not in model.parameters:
        raise AnalysisError(f"'{param}' is not a parameter of the model (parameters: "
                            f"{', '.join(model.parameters)})")
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise AnalysisError("the range must be two different finite numbers")
    if harmonics is not None and not 1 <= harmonics <= 200:
        raise AnalysisError(f"harmonics must be between 1 and 200, not {harmonics}")
    if points < 3:
        raise AnalysisError("points must be at least 3")
    at_start = model.with_parameters(**{param: repr(float(start))})
    eqs = _Equations(at_start)
    n = eqs.n
    H = harmonics or DEFAULT_HARMONICS
    hb = _HarmonicBalance(eqs, param, H)

    # the start: the linear stationary solution, refined
    solution = stationary(linear_system(at_start, deadline), deadline)
    W0 = eqs.base(hb.pvals(start))
    X = np.zeros((n, hb.m))
    for h in solution.harmonics:
        k = int(round(h.omega / W0))
        if k == 0:
            X[:, 0] += h.L
        elif k <= H:
            X[:, 2 * k - 1] += h.L
            X[:, 2 * k] += h.N
    x0, ok = hb.newton(X.ravel(), start, max(float(np.abs(X).max()), 1e-300))
    if not ok:
        raise AnalysisError(f"harmonic balance did not converge at {param} = {start:g} from "
                            "the linear stationary solution; start the range where the "
                            "response is small")
    branch = _continue(hb, x0, start, stop, points, deadline)
    if harmonics is None:
        coeffs = np.array(branch.x).reshape(len(branch.x), n, hb.m)
        ratios = _truncation(coeffs, H)
        worst = int(np.argmax(ratios))
        H_new, x = H, branch.x[worst]
        while ratios[worst] > TRUNCATION_TOL and H_new < MAX_HARMONICS:
            H_next = min(MAX_HARMONICS, H_new + 4)
            x = _resize(x, n, H_new, H_next)
            trial = _HarmonicBalance(eqs, param, H_next)
            x, ok = trial.newton(x, branch.p[worst], float(np.linalg.norm(x)))
            H_new = H_next
            if not ok:
                break
            if _truncation(x.reshape(1, n, trial.m), H_new)[0] <= TRUNCATION_TOL:
                break
        if H_new != H:
            H = H_new
            hb = _HarmonicBalance(eqs, param, H)
            x0, ok = hb.newton(_resize(x0, n, DEFAULT_HARMONICS, H), start,
                               float(np.linalg.norm(x0)))
            branch = _continue(hb, x0, start, stop, points, deadline)

    # stability, residual, amplitudes
    values = np.array(branch.p)
    coeffs = np.array(branch.x).reshape(values.size, n, hb.m)
    residual = 0.0
    exps = []
    Ws = []
    for x, p in zip(branch.x, branch.p):
        deadline.check("during the stability analysis", analysis=True)
        R, J, blocks = hb.jacobian(x, p)
        residual = max(residual, float(np.abs(R).max()))
        exps.append(hb.exponents(J, blocks))
        Ws.append(blocks[3])
    Ws_arr = np.array(Ws)
    lam = np.array(exps)
    mult = np.exp(lam * (2 * np.pi / Ws_arr)[:, None])
    stable = np.all(np.abs(mult) <= 1 + STABILITY_TOL, axis=1)
    amps = _amplitudes(coeffs, H)
    amplitudes = {name: amps[:, j] for j, name in enumerate(model.coordinates)}

    # special points, each located between two branch points and refined
    special: list[SpecialPoint] = []
    counts = [_classify(lam[i], Ws_arr[i]) for i in range(values.size)]
    tp = np.array(branch.tp)
    folds: set[int] = set()

    def point(i: int, kind: str, found: tuple[np.ndarray, float] | None) -> SpecialPoint:
        if found is None:  # not refined: halfway
            x = 0.5 * (branch.x[i] + branch.x[i + 1])
            found = (x, 0.5 * (branch.p[i] + branch.p[i + 1]))
        x, p = found
        a = _amplitudes(x.reshape(1, n, hb.m), H)[0]
        return SpecialPoint(kind, float(p), MappingProxyType(
            {nm: float(a[j]) for j, nm in enumerate(model.coordinates)}), i)

    def growth(k: int) -> Callable[[np.ndarray, float, np.ndarray], float]:
        """The k-th largest log|mu| (zero where the k-th multiplier crosses the circle)."""
        def g(x: np.ndarray, p: float, tangent: np.ndarray) -> float:
            _, J, blocks = hb.jacobian(x, p)
            rates = np.sort(hb.exponents(J, blocks).real)[::-1] * 2 * np.pi / blocks[3]
            return float(rates[k])
        return g

    def rate(i: int, k: int) -> float:
        return float(np.sort(lam[i].real)[::-1][k] * 2 * np.pi / Ws_arr[i])

    for i in range(values.size - 1):
        if tp[i] * tp[i + 1] < 0:
            found = _refine(hb, branch, i, lambda x, p, tangent: float(tangent[-1]),
                            float(tp[i]), float(tp[i + 1]))
            special.append(point(i, "fold", found))
            folds.update({i - 1, i, i + 1})
    for i in range(values.size - 1):
        a, b = counts[i], counts[i + 1]
        changes = [kind for j, kind in
                   ((1, "period-doubling"), (2, "neimark-sacker"), (0, "branch"))
                   if a[j] != b[j] and not (j == 0 and i in folds)]
        for kind in changes:
            k = sum(a) if sum(b) > sum(a) else sum(b)  # the multiplier that crosses
            found = None
            if k < lam.shape[1]:
                found = _refine(hb, branch, i, growth(k), rate(i, k), rate(i + 1, k))
            special.append(point(i, kind, found))
    special.sort(key=lambda sp: sp.index)

    warnings = list(branch.warnings)
    trunc = float(_truncation(coeffs, H).max()) if values.size else 0.0
    if H > 1 and trunc > TRUNCATION_TOL:
        warnings.append(f"the highest harmonics carry up to {trunc:.3g} of the amplitude: "
                        "raise --harmonics for a more accurate curve")
    linear_response = None
    if linear:
        try:
            grid = np.linspace(min(start, stop), max(start, stop), max(points, 201))
            linear_response = sweep(system, param, grid, deadline=deadline)
        except AnalysisError as exc:
            warnings.append(f"no linear sweep to compare with: {exc}")
    return NonlinearResponse(
        title=model.title, parameter=param, coordinates=tuple(model.coordinates),
        values=values, amplitudes=MappingProxyType(amplitudes), coefficients=coeffs,
        base_frequencies=Ws_arr, stable=stable, multipliers=mult,
        special_points=tuple(special), harmonics=H, residual=residual, truncation=trunc,
        start=float(start), stop=float(stop), linear=linear_response,
        warnings=tuple(warnings))


__all__ = ["NonlinearResponse", "SpecialPoint", "nonlinear_sweep", "SPECIAL_KINDS"]
