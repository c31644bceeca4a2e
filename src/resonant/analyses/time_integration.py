"""Time integration of the equations of motion (the engine of :mod:`.simulate`).

Two right-hand sides in the state ``y = [q, q']``: :class:`LinearDynamics`
(``M q'' + C q' + K q = Q(t)``, q deviations from the reference state) and
:class:`NonlinearDynamics` (the full equations of a
:class:`~resonant.system.NonlinearSystem`, ``E(q, q', q'', s(t)) = 0``, solved for
q'' from its mass matrix dE/dq'' and its value at q'' = 0; q absolute).
:func:`integrate` runs :func:`scipy.integrate.solve_ivp` on either within a
budget of evaluations, checks the deadline, retries an explicit method that
stalls on a stiff system with an implicit one, and turns a breakdown into an
:class:`~resonant.errors.AnalysisError` that says when and where.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any, Protocol, TypeAlias

import numpy as np
import sympy

from ..deadline import Deadline
from ..errors import AnalysisError
from ..expressions import compilable
from ..modal import state_matrix
from ..model import TIME, symbol
from ..system.base import LinearSystem, NumericEOM
from ..system.nonlinear import NonlinearSystem
from ..system.output_map import output_map

#: most right-hand-side evaluations of one run (all attempts together): beyond it the run
#: stops with exit 3 and the time reached (about 100 s and 200 MB for a small system)
MAX_RHS_CALLS = 2_000_000
#: an explicit method on a stiff system (natural frequencies spread over more than
#: STIFF_RATIO) gets this many evaluations before the run is retried with STIFF_METHOD
STIFF_TRIAL_CALLS = 50_000
STIFF_RATIO = 1e3
#: the method a stiff run falls back to (LSODA switches to an implicit BDF method)
STIFF_METHOD = "LSODA"
EXPLICIT_METHODS = ("DOP853", "RK45")


class Budget(Exception):
    """The integration used up its evaluations of the right-hand side."""

    def __init__(self, t: float) -> None:
        super().__init__(t)
        self.t = t


class Breakdown(Exception):
    """The integration cannot continue (not finite, singular mass matrix)."""

    def __init__(self, t: float, reason: str, small: bool = True) -> None:
        super().__init__(reason)
        self.t = t
        self.small = small  # may be because the motion is no longer small
        self.reason = reason
        self.state: np.ndarray | None = None


def _lambdify(exprs: Sequence[sympy.Expr], args: Sequence[sympy.Symbol]
              ) -> Callable[..., list[Any]]:
    function: Callable[..., list[Any]] = sympy.lambdify(
        list(args), [compilable(e) for e in exprs], modules="numpy", cse=True)
    return function


def _stack(values: Sequence[Any], shape: tuple[int, ...]) -> np.ndarray:
    """Values of a lambdified list (scalars where an entry is constant) as one float array."""
    if not shape:  # one instant: every value is a scalar (the integrator's hot path)
        return np.array(values, dtype=float)
    return np.array([np.broadcast_to(np.asarray(v, dtype=float), shape) for v in values],
                    dtype=float)


def _parameter_args(values: Mapping[str, float]) -> tuple[list[sympy.Symbol], list[float]]:
    return [symbol(n) for n in values], [float(v) for v in values.values()]


class LinearDynamics:
    """y = [q, q'] of M q'' + C q' + K q = Q(t); q are deviations."""

    def __init__(self, eom: LinearSystem, num: NumericEOM) -> None:
        # the loads and signals in sympy (a bare NumericEOM has no model to simulate)
        equations = eom.symbolic()
        if equations is None:
            raise AnalysisError("a simulation needs the system's loads as functions of time; "
                                "this system is given by numbers only")
        self.n = num.n
        self.M, self.C, self.K = num.M, num.C, num.K
        self.Minv = np.linalg.inv(num.M)
        self.A = state_matrix(self.Minv @ num.K, self.Minv @ num.C)
        params, self.pvals = _parameter_args(num.parameters)
        self._q = _lambdify(list(equations.Q), [TIME, *params]) if equations.excitation \
            else None
        signals = equations.signal_functions
        every = output_map(num.outputs, num.coordinates)
        # the integration gives q, q' and q'': an output of a higher derivative is left out
        self.unsupported = [n for n, k in zip(every.names, every.orders) if k > 2]
        self.outputs = output_map(num.outputs, num.coordinates,
                                  [n for n in every.names if n not in self.unsupported])
        self.signal_vars = list(self.outputs.signals)
        self._signals = _lambdify([signals[v] for v in self.signal_vars], [TIME, *params]) \
            if self.signal_vars else None

    def forcing(self, t: float | np.ndarray) -> np.ndarray:
        shape = np.shape(t)
        if self._q is None:
            return np.zeros((self.n, *shape))
        return _stack(self._q(t, *self.pvals), shape)

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        dy: np.ndarray = self.A @ y
        if self._q is not None:
            dy[self.n:] += self.Minv @ self.forcing(t)
        return dy

    def to_state(self, deviation: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        return np.concatenate([deviation, velocity])

    def jacobian(self) -> np.ndarray | None:
        """The constant Jacobian of the right-hand side (for the implicit methods)."""
        return self.A

    def evaluate(self, t: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Deviations (n, N) of the coordinates and the outputs at the samples."""
        q, v = Y[:self.n], Y[self.n:]
        a = self.Minv @ (self.forcing(t) - self.C @ v - self.K @ q)
        sig = _stack(self._signals(t, *self.pvals), t.shape) if self._signals else None
        y = self.outputs.history((q, v, a), sig)
        return q, {name: y[j] for j, name in enumerate(self.outputs.names)}


class NonlinearDynamics:
    """y = [q, q'] (absolute coordinates) of the full equations E(q, q', q'', s(t)) = 0."""

    def __init__(self, system: NonlinearSystem) -> None:
        # imported here: a module-level import put scipy.linalg (0.1-0.2 s) into every
        # command that imports this module, the linear studies' among them
        from scipy.linalg.lapack import dgesv

        self._gesv = dgesv
        self.system = system
        self.n = system.n
        self.pvals = system.parameter_values
        self.equilibrium = system.reference(self.pvals)
        self.unsupported = list(system.unsupported_outputs)

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:self.n], y[self.n:]
        # called by Counter, under np.errstate(all="ignore")
        mass, rest = self.system.dynamics(t, q, v, self.pvals)
        if not math.isfinite(mass.sum() + rest.sum()):  # one test: NaN and infinity
            self._breakdown(t)
        # LAPACK's LU with partial pivoting, as numpy.linalg.solve, without its wrapping
        # (a quarter of the time of a small system's right-hand side)
        _, _, a, info = self._gesv(mass, -rest)
        if info > 0:
            raise Breakdown(t, "the mass matrix became singular")
        return np.concatenate([v, a])

    def _breakdown(self, t: float) -> None:
        """Why the equations are not finite at t: a signal, or the coordinates."""
        if not np.all(np.isfinite(self.system.forcing(np.array([t]), self.pvals))):
            raise Breakdown(t, "the equations cannot be evaluated there (a signal is not "
                               "finite at that time: a signal such as 1/t undefined there?)",
                            small=False)
        raise Breakdown(t, "the equations of motion are not finite there (a coordinate "
                           "left the range where the model is defined)")

    def to_state(self, deviation: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        return np.concatenate([self.equilibrium + deviation, velocity])

    def jacobian(self) -> np.ndarray | None:
        return None  # estimated by finite differences

    def evaluate(self, t: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        n = self.n
        q, v = Y[:n], Y[n:]
        outputs = {}
        if self.system.outputs:
            with np.errstate(all="ignore"):
                mass, rest = self.system.dynamics(t, q, v, self.pvals)
                s = self.system.forcing(t, self.pvals)
                a = np.linalg.solve(np.moveaxis(mass, -1, 0),
                                    -np.moveaxis(rest, -1, 0)[..., None])[..., 0].T
                outputs = self.system.output_values(q, v, a, s, self.pvals)
        return q - self.equilibrium[:, None], outputs


#: the right-hand side of an integration: the linearized or the full equations
Dynamics: TypeAlias = LinearDynamics | NonlinearDynamics


class Progress:
    """A one-line progress indication on stderr for runs longer than a second."""

    def __init__(self, duration: float, enabled: bool) -> None:
        self.duration, self.enabled = duration, enabled
        self.started = time.monotonic()
        self.shown = -1

    def __call__(self, t: float) -> None:
        percent = int(100 * t / self.duration)
        if self.enabled and percent > self.shown and time.monotonic() - self.started > 1.0:
            self.shown = percent
            print(f"\rsimulating: {percent:3d}% (t = {t:.4g} of {self.duration:.4g} s)",
                  end="", file=sys.stderr, flush=True)

    def done(self) -> None:
        if self.shown >= 0:
            print("\r" + " " * 60 + "\r", end="", file=sys.stderr, flush=True)


class Counter:
    """The right-hand side of one run: counts evaluations, checks the deadline and the
    budget, shows progress, and turns non-finite values into :class:`Breakdown`."""

    def __init__(self, dynamics: Dynamics, duration: float, deadline: Deadline,
                 report: Progress) -> None:
        self.dynamics, self.duration, self.deadline, self.report = \
            dynamics, duration, deadline, report
        self.calls, self.limit, self.reached = 0, MAX_RHS_CALLS, 0.0

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        self.calls += 1
        self.reached = max(self.reached, t)
        if self.calls % 2000 == 0:
            self.report(t)
        if self.calls % 200 == 0:
            self.deadline.check(f"while integrating (t = {t:.4g} of {self.duration:.4g} s)",
                                analysis=True)
        if self.calls > self.limit:
            raise Budget(t)
        try:
            with np.errstate(all="ignore"):
                dy: np.ndarray = self.dynamics.rhs(t, y)
            if not math.isfinite(dy.sum()):  # one cheap test catches NaN and infinity
                raise Breakdown(t, "the response is not finite")
        except ArithmeticError as exc:  # Python floats: 1/t at t = 0, overflow
            error = Breakdown(t, f"the equations cannot be evaluated there ({exc}; a signal "
                                 "such as 1/t undefined at that time?)", small=False)
            error.state = np.array(y, dtype=float)
            raise error from None
        except Breakdown as exc:
            exc.state = np.array(y, dtype=float)
            raise
        return dy


def _solve(rhs: Counter, y0: np.ndarray, method: str, rtol: float, atol: np.ndarray) -> Any:
    import scipy.integrate

    options: dict[str, Any] = {}
    jacobian = rhs.dynamics.jacobian()
    if jacobian is not None and method in ("Radau", "BDF", "LSODA"):
        options["jac"] = lambda t, y: jacobian
    with np.errstate(over="ignore", invalid="ignore"):  # the rhs checks finiteness
        return scipy.integrate.solve_ivp(rhs, (0.0, rhs.duration), y0, method=method,
                                         rtol=rtol, atol=atol, dense_output=True, **options)


def _with_fallback(rhs: Counter, y0: np.ndarray, method: str, rtol: float, atol: np.ndarray,
                   spread: float, warnings: list[str]) -> tuple[Any, str]:
    """An explicit method first; on a stiff system that stalls, STIFF_METHOD instead."""
    stiff_trial = method in EXPLICIT_METHODS and spread > STIFF_RATIO
    if method in EXPLICIT_METHODS:
        rhs.limit = STIFF_TRIAL_CALLS if stiff_trial else MAX_RHS_CALLS
        result = None
        try:
            result = _solve(rhs, y0, method, rtol, atol)
        except Budget:
            if not stiff_trial:
                raise
        if result is not None and result.status == 0:
            return result, method
        why = (f"needed more than {STIFF_TRIAL_CALLS:.0e} evaluations" if result is None
               else f"failed ({result.message})")
        decades = f"{math.log10(max(spread, 1.0)):.1f} decades"
        warnings.append(
            f"{method} {why} at t = {rhs.reached:.4g} s: the system "
            f"{'is' if stiff_trial else 'may be'} stiff (its frequencies spread over "
            f"{decades}); integrated with {STIFF_METHOD} (implicit, for stiff systems) "
            "instead")
        method = STIFF_METHOD
        rhs.reached = 0.0
    rhs.limit = MAX_RHS_CALLS
    return _solve(rhs, y0, method, rtol, atol), method


#: points per call of one step's interpolant: its temporaries stay small (in cache, and in
#: memory however many samples are asked for)
DENSE_CHUNK = 4096
#: a step of the integrator spans at most this many periods of anything its interpolant
#: shows (a polynomial of degree d has at most d - 1 extrema: 7 for DOP853, 12 for LSODA)
STEP_PERIODS = 8.0


class DenseSolution(Protocol):
    """What :func:`dense_values` and :func:`resolved_frequency` read of solve_ivp's dense
    output (scipy's ``OdeSolution``): the step ends and each step's interpolant."""

    ts: np.ndarray
    interpolants: Sequence[Callable[[np.ndarray], np.ndarray]]


def dense_values(solution: DenseSolution, t: np.ndarray) -> np.ndarray:
    """solve_ivp's dense output at the ascending times t, shape (states, len(t)).

    The same values as ``solution(t)`` (a forward run's; each time goes to the step
    scipy's ``OdeSolution`` picks: ``ts[j] < t <= ts[j + 1]``, the ends clipped), without
    its per-point grouping in Python and its copies: each step's interpolant is called
    once per :data:`DENSE_CHUNK` of the times inside it and writes into one array.
    """
    ts = np.asarray(solution.ts)
    steps = len(solution.interpolants)
    segment = np.searchsorted(ts, t, side=getattr(solution, "side", "left")) - 1
    np.clip(segment, 0, steps - 1, out=segment)
    edges = np.concatenate([[0], np.flatnonzero(np.diff(segment)) + 1, [t.size]]) \
        if t.size else np.zeros(1, dtype=int)
    states = np.asarray(solution.interpolants[0](ts[:1])).shape[0]
    out = np.empty((states, t.size))
    for a, b in zip(edges[:-1], edges[1:]):
        interpolant = solution.interpolants[int(segment[a])]
        for lo in range(int(a), int(b), DENSE_CHUNK):
            hi = min(lo + DENSE_CHUNK, int(b))
            out[:, lo:hi] = interpolant(t[lo:hi])
    return out


def resolved_frequency(solution: DenseSolution, highest: float, start: float = 0.0
                       ) -> float:
    """The highest circular frequency the solution can show after ``start``.

    ``highest``, unless the integrator's steps there are too long for it: a mode that
    does not move (a stiff mode of a model at rest, below the tolerances) is not
    followed, and sampling it would only multiply the samples of a smooth curve.
    """
    ts = np.asarray(solution.ts)
    h = np.diff(ts)[ts[1:] > start]
    if h.size == 0 or not float(h.min()) > 0:
        return highest
    return min(highest, 2 * math.pi * STEP_PERIODS / float(h.min()))


def integrate(dynamics: Dynamics, y0: np.ndarray, duration: float, method: str, rtol: float,
              atol: np.ndarray, spread: float, coordinates: Sequence[str], nonlinear: bool,
              warnings: list[str], deadline: Deadline, progress: bool) -> tuple[Any, str]:
    """solve_ivp's result (with dense output) and the method that produced it.

    Raises
    ------
    AnalysisError
        When the budget of evaluations is used up, the equations break down (not finite,
        singular mass matrix) or the integrator fails; the message gives the time.
    """
    kind = "nonlinear" if nonlinear else "linear"
    report = Progress(duration, progress)
    rhs = Counter(dynamics, duration, deadline, report)
    try:
        result, method = _with_fallback(rhs, y0, method, rtol, atol, spread, warnings)
    except Budget as exc:
        raise AnalysisError(
            f"the {kind} integration stopped at t = {exc.t:.6g} s of {duration:.6g} s: it "
            f"needed more than {MAX_RHS_CALLS:.0e} evaluations of the equations (the limit "
            "of one run); ask for a shorter --duration") from None
    except Breakdown as exc:
        where = ""
        if exc.state is not None:
            where = " (" + ", ".join(f"{c} = {v:.6g}" for c, v in
                                     zip(coordinates, exc.state[:len(coordinates)])) + ")"
        hint = (": the motion is no longer small (a pendulum flipping over, a rod angle "
                "leaving the range of asin, ...)" if nonlinear and exc.small else "")
        raise AnalysisError(f"the {kind} integration broke down at t = {exc.t:.6g} s"
                            f"{where}: {exc.reason}{hint}") from None
    finally:
        report.done()
    if result.status != 0:
        stopped = float(result.t[-1]) if result.t.size else 0.0
        raise AnalysisError(f"the {kind} integration failed at t = {stopped:.6g} s of "
                            f"{duration:.6g} s: {result.message}")
    return result, method


__all__ = ["LinearDynamics", "NonlinearDynamics", "integrate", "dense_values",
           "resolved_frequency", "STIFF_RATIO"]
