"""Time simulation of a model: the linearized and the full nonlinear equations.

The linear simulation integrates ``M q'' + C q' + K q = Q(t)`` with the
signals written out as functions of time (:attr:`LinearEOM.Q`); the nonlinear
one integrates the full Lagrange equations ``mass(q, ...) q'' + rest(q, q',
signals) = 0`` of :func:`resonant.nonlinear.nonlinear_equations`, with each
signal symbol ``s^(k)`` replaced by the k-th time derivative of the signal's
expression.  Both are compiled once (:func:`sympy.lambdify` with common
subexpressions, numpy) and integrated with :func:`scipy.integrate.solve_ivp`.

Both report **deviations from the reference state** (``[equilibrium]``), so
they compare with each other and with the linear stationary solution.  The
steady-state amplitude is the **peak absolute deviation** over the last
periods of the lowest excitation frequency, the same definition as the
stationary ``amplitudes``; their relative difference shows how far "small
oscillations" hold.

Examples
--------
>>> from resonant.api import loads
>>> model = loads('''
... [parameters]
... m = 1
... k = 100
... c = 4
... [coordinates]
... x = "displacement"
... [signals]
... F = "sin(5*t)"
... [energy]
... T = "m*x'^2/2"
... U = "k*x^2/2"
... D = "c*x'^2/2"
... [[force]]
... name = "F"
... generalized = { x = "F" }
... ''')
>>> sim = simulate(model.linearize(), duration=8.0)
>>> round(sim.linear_amplitudes["x"], 6), abs(sim.relative_difference["x"]) < 1e-4
(0.012883, True)
"""

from __future__ import annotations

import csv
import html
import math
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy

from .. import hooks
from ..deadline import NO_DEADLINE, AnalysisTimeout, Deadline
from ..derivation import nonlinear_equations
from ..errors import AnalysisError, ModelError, Problem, name_list
from ..expressions import compilable, parse
from ..model import TIME, Model, symbol
from ..model.types import constant_prime_message, primed_names
from ..system import LinearSystem, NumericEOM
from ..system.stability import (
    ASYMPTOTIC,
    UNSTABLE,
    check_mass_matrix,
    classify,
    state_eigenvalues,
)
from .stationary import StationarySolution, freeze_fields, stationary

if TYPE_CHECKING:  # pragma: no cover
    pass

#: measurement window: this many periods of the lowest excitation frequency
DEFAULT_PERIODS = 5.0
#: a damped run lasts until the slowest transient has decayed by exp(-DECAY_TIMES)
DECAY_TIMES = 12.0
#: default duration of an undamped run, in periods of the lowest frequency (+ the window)
UNDAMPED_PERIODS = 15.0
#: upper bound of a default duration, in cycles of the highest frequency involved
MAX_DEFAULT_CYCLES = 4000.0
#: spread of the natural frequencies above which an implicit (stiff) method is used
STIFF_RATIO = 1e3
#: stored samples per period of the highest frequency (the amplitude is measured finer)
SAMPLES_PER_PERIOD = 40
MAX_SAMPLES = 200_001
#: samples per period of the highest frequency in the measurement window
WINDOW_SAMPLES_PER_PERIOD = 2000
MAX_WINDOW_SAMPLES = 400_001
#: a transient counts as decayed at exp(-SETTLED_DECAY) (about 1e-3) of its size
SETTLED_DECAY = 7.0
#: |relative difference| above which a warning says small oscillations do not hold
LARGE_DIFFERENCE = 0.05
#: most right-hand-side evaluations of one run (all attempts together): beyond it the run
#: stops with exit 3 and the time reached (about 100 s and 200 MB for a small system)
MAX_RHS_CALLS = 2_000_000
#: an explicit method on a stiff system (natural frequencies spread over more than
#: STIFF_RATIO) gets this many evaluations before the run is retried with STIFF_METHOD
STIFF_TRIAL_CALLS = 50_000
#: the method a stiff run falls back to (LSODA switches to an implicit BDF method)
STIFF_METHOD = "LSODA"
EXPLICIT_METHODS = ("DOP853", "RK45")
#: longest run, in periods of the highest frequency involved (excitation or natural)
MAX_PERIODS = 1e6
START_MODES = ("auto", "rest", "stationary", "periodic")
METHODS = ("DOP853", "RK45", "LSODA", "Radau", "BDF")
#: largest initial deviation or velocity: squares and the error norms stay finite
MAX_INITIAL = 1e100


@dataclass(frozen=True)
class Simulation:
    """A simulated time history and its steady-state amplitudes.

    Attributes
    ----------
    t : numpy.ndarray
        Sample times in s (uniform, from 0 to ``t_end``).
    states : mapping
        ``name -> deviation from the reference state`` at ``t`` for every
        coordinate and output.
    linear_response : mapping
        The linear stationary prediction at ``t`` (empty when there is none).
    steady_amplitudes : mapping
        Peak absolute deviation over the measurement ``window``.
    linear_amplitudes : mapping
        The stationary prediction (``StationarySolution.amplitudes``).
    relative_difference : mapping
        ``steady / linear - 1`` (signed) where the prediction is nonzero.
    window : tuple of float
        The interval the steady amplitudes are measured over.
    start : str
        ``"rest"``, ``"stationary"`` (the stationary solution's initial state)
        or ``"given"`` (``initial`` values).
    """

    title: str
    coordinates: tuple[str, ...]
    t: np.ndarray
    states: Mapping[str, np.ndarray]
    linear_response: Mapping[str, np.ndarray]
    steady_amplitudes: Mapping[str, float]
    linear_amplitudes: Mapping[str, float]
    relative_difference: Mapping[str, float]
    window: tuple[float, float]
    nonlinear: bool
    start: str
    method: str
    initial: Mapping[str, float] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def t_end(self) -> float:
        return float(self.t[-1])

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.states)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (without the time history; see :meth:`to_csv`)."""
        return {
            "title": self.title,
            "coordinates": list(self.coordinates),
            "nonlinear": self.nonlinear,
            "t_end": self.t_end,
            "samples": int(self.t.size),
            "method": self.method,
            "start": self.start,
            "initial": dict(self.initial),
            "window": list(self.window),
            "amplitude_definition": "peak absolute deviation from the reference state "
                                    "over the window",
            "steady_amplitudes": dict(self.steady_amplitudes),
            "linear_amplitudes": dict(self.linear_amplitudes),
            "relative_difference": dict(self.relative_difference),
            "warnings": list(self.warnings),
        }

    def to_csv(self, path: str | Path) -> None:
        """Write ``t`` and every deviation (and the linear prediction) as CSV."""
        columns = [("t", self.t)] + list(self.states.items()) + [
            (f"{name} (linear stationary)", y) for name, y in self.linear_response.items()]
        with open(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow([c[0] for c in columns])
            data = np.column_stack([c[1] for c in columns])
            writer.writerows([[f"{v:.10g}" for v in row] for row in data])

    def _repr_html_(self) -> str:
        rows = "".join(
            f"<tr><td>{html.escape(n)}</td><td>{a:.6g}</td>"
            f"<td>{_fmt(self.linear_amplitudes.get(n))}</td>"
            f"<td>{_fmt(self.relative_difference.get(n), percent=True)}</td></tr>"
            for n, a in self.steady_amplitudes.items())
        warn = "".join(f"<p><b>warning:</b> {html.escape(w)}</p>" for w in self.warnings)
        kind = "nonlinear" if self.nonlinear else "linear"
        return (f"<p>{kind} simulation to t = {self.t_end:.6g} s ({html.escape(self.method)}), "
                f"amplitudes over t = {self.window[0]:.6g} … {self.window[1]:.6g} s</p>"
                "<table><tr><th>quantity</th><th>steady amplitude</th><th>linear "
                f"stationary</th><th>difference</th></tr>{rows}</table>{warn}")


def _peak(y: np.ndarray) -> float:
    """max |y| of finely sampled smooth data, refined by a parabola through the top 3 samples.

    Examples
    --------
    >>> t = np.linspace(0, 1, 50)
    >>> round(_peak(np.sin(2 * np.pi * t + 0.1)), 6)
    1.0
    """
    a = np.abs(y)
    i = int(np.argmax(a))
    top = float(a[i])
    if 0 < i < a.size - 1:
        left, right = float(a[i - 1]), float(a[i + 1])
        curvature = 2 * top - left - right
        if curvature > 0:
            try:
                refined = top + (right - left) ** 2 / (8 * curvature)
            except (OverflowError, ZeroDivisionError):  # Python floats raise
                return top
            return refined if math.isfinite(refined) else top
    return top


def _fmt(value: float | None, percent: bool = False) -> str:
    if value is None:
        return ""
    return f"{100 * value:+.4g}%" if percent else f"{value:.6g}"


# -- the two right-hand sides ----------------------------------------------------------------

class _Budget(Exception):
    """The integration used up its evaluations of the right-hand side."""

    def __init__(self, t: float) -> None:
        super().__init__(t)
        self.t = t


class _Breakdown(Exception):
    """The integration cannot continue (not finite, singular mass matrix)."""

    def __init__(self, t: float, reason: str, small: bool = True) -> None:
        super().__init__(reason)
        self.t = t
        self.small = small  # may be because the motion is no longer small
        self.reason = reason
        self.state: np.ndarray | None = None


def _lambdify(exprs: Sequence[sympy.Expr], args: Sequence[sympy.Symbol]
              ) -> Callable[..., list[Any]]:
    return sympy.lambdify(list(args), [compilable(e) for e in exprs], modules="numpy", cse=True)


def _stack(values: Sequence[Any], shape: tuple[int, ...]) -> np.ndarray:
    """Values of a lambdified list (scalars where an entry is constant) as one float array."""
    if not shape:  # one instant: every value is a scalar (the integrator's hot path)
        return np.array(values, dtype=float)
    return np.array([np.broadcast_to(np.asarray(v, dtype=float), shape) for v in values],
                    dtype=float)


def _parameter_args(model: Model) -> tuple[list[sympy.Symbol], list[float]]:
    names = list(model.parameters)
    return [symbol(n) for n in names], [float(model.parameter_values[n]) for n in names]


def _signal_function(model: Model, name: str, order: int) -> sympy.Expr:
    """d^order s/dt^order of a declared signal as a function of t and the parameters."""
    base = model.signals[name].to_sympy(lambda n, p: TIME if n == "t" else symbol(n))
    return sympy.diff(base, TIME, order) if order else base


class _LinearSystem:
    """y = [q, q'] of M q'' + C q' + K q = Q(t); q are deviations."""

    def __init__(self, eom: Any, num: NumericEOM, model: Model) -> None:
        self.n = num.n
        self.M, self.C, self.K = num.M, num.C, num.K
        self.Minv = np.linalg.inv(num.M)
        n = self.n
        self.A = np.block([[np.zeros((n, n)), np.eye(n)],
                           [-self.Minv @ num.K, -self.Minv @ num.C]])
        params, self.pvals = _parameter_args(model)
        self._q = _lambdify(list(eom.Q), [TIME, *params]) if eom.excitation else None
        signals = eom.signal_functions
        self.outputs: dict[str, list[tuple[tuple[str, int], float]]] = {}
        self.unsupported: list[str] = []
        needed_signals = []
        index = {c: i for i, c in enumerate(num.coordinates)}
        for name, out in num.outputs.items():
            terms = list(out.terms.items())
            for (var, order), _ in terms:
                if var in index and order > 2:
                    self.unsupported.append(name)
                elif var not in index:
                    needed_signals.append((var, order))
            self.outputs[name] = terms
        self.outputs = {k: v for k, v in self.outputs.items() if k not in self.unsupported}
        self.index = index
        self.signal_vars = sorted(set(needed_signals))
        self._signals = _lambdify([signals[v] for v in self.signal_vars], [TIME, *params]) \
            if self.signal_vars else None

    def forcing(self, t: Any) -> np.ndarray:
        shape = np.shape(t)
        if self._q is None:
            return np.zeros((self.n, *shape))
        return _stack(self._q(t, *self.pvals), shape)

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        dy = self.A @ y
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
        derivs = (q, v, a)
        sig = _stack(self._signals(t, *self.pvals), t.shape) if self._signals else None
        outputs = {}
        for name, terms in self.outputs.items():
            y = np.zeros_like(t)
            for (var, order), coef in terms:
                if var in self.index:
                    y = y + coef * derivs[order][self.index[var]]
                else:
                    assert sig is not None  # a term not on a coordinate is on a signal
                    y = y + coef * sig[self.signal_vars.index((var, order))]
            outputs[name] = y
        return q, outputs


class _NonlinearSystem:
    """y = [q, q'] (absolute coordinates) of mass(q, ...) q'' + rest(q, q', t) = 0."""

    def __init__(self, model: Model, equilibrium: np.ndarray) -> None:
        eq = nonlinear_equations(model)
        self.n = len(model.coordinates)
        self.equilibrium = equilibrium
        params, self.pvals = _parameter_args(model)
        q, qd, qdd = eq.q, eq.qd, eq.qdd
        # outputs in full, and their value at the reference state with all signals zero
        self.outputs: dict[str, Callable[..., Any]] = {}
        self.output_reference: dict[str, float] = {}
        self.unsupported: list[str] = []
        coordinates = set(model.coordinates)
        folded: dict[str, sympy.Expr] = {}
        for name, expression in model.outputs.items():
            if any(v in coordinates and p > 2 for v, p in expression.names()):
                self.unsupported.append(name)
                continue
            full = sympy.sympify(eq.ops.expr(expression))
            too_high = [s for s in full.free_symbols if s in eq.ops.registry and
                        eq.ops.registry[s][0] in coordinates and eq.ops.registry[s][1] > 2]
            if too_high:
                self.unsupported.append(name)
                continue
            at_rest = full.xreplace({s: sympy.S.Zero for s, (nm, order) in eq.ops.registry.items()
                                     if nm in model.signals or order > 0})
            at_rest = at_rest.xreplace({**{s: sympy.Float(v) for s, v in zip(q, equilibrium)},
                                        **{s: sympy.Float(v) for s, v in zip(params, self.pvals)}})
            try:
                self.output_reference[name] = float(at_rest)
            except TypeError:
                self.unsupported.append(name)
                continue
            folded[name] = full
        # folding the outputs may register more signal derivatives: substitute them last
        signal_subs = {s: _signal_function(model, name, order)
                       for s, (name, order) in eq.ops.registry.items()
                       if name in model.signals}
        exprs = [sympy.sympify(e).xreplace(signal_subs) for e in [*eq.mass, *eq.rest]]
        self._equations = _lambdify(exprs, [TIME, *q, *qd, *params])
        for name, full in folded.items():
            self.outputs[name] = _lambdify([full.xreplace(signal_subs)],
                                           [TIME, *q, *qd, *qdd, *params])

    def matrices(self, t: Any, q: Any, v: Any) -> tuple[np.ndarray, np.ndarray]:
        shape = np.shape(t)
        values = _stack(self._equations(t, *q, *v, *self.pvals), shape)
        n = self.n
        return values[:n * n].reshape(n, n, *shape), values[n * n:]

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:self.n], y[self.n:]
        with np.errstate(all="ignore"):
            mass, rest = self.matrices(t, q, v)
        if not (np.all(np.isfinite(mass)) and np.all(np.isfinite(rest))):
            raise _Breakdown(t, "the equations of motion are not finite there (a coordinate "
                                "left the range where the model is defined)")
        try:
            a = np.linalg.solve(mass, -rest)
        except np.linalg.LinAlgError:
            raise _Breakdown(t, "the mass matrix became singular") from None
        return np.concatenate([v, a])

    def to_state(self, deviation: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        return np.concatenate([self.equilibrium + deviation, velocity])

    def jacobian(self) -> np.ndarray | None:
        return None  # estimated by finite differences

    def evaluate(self, t: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        n = self.n
        q, v = Y[:n], Y[n:]
        outputs = {}
        if self.outputs:
            with np.errstate(all="ignore"):
                mass, rest = self.matrices(t, q, v)
                a = np.linalg.solve(np.moveaxis(mass, -1, 0),
                                    -np.moveaxis(rest, -1, 0)[..., None])[..., 0].T
            for name, fn in self.outputs.items():
                with np.errstate(all="ignore"):
                    y = _stack(fn(t, *q, *v, *a, *self.pvals), t.shape)[0]
                outputs[name] = y - self.output_reference[name]
        return q - self.equilibrium[:, None], outputs


# -- the simulation ---------------------------------------------------------------------------

def _periodic_start(system: LinearSystem, start: str, nonlinear: bool, given: bool,
                    stability: str, solution: StationarySolution | None, warnings: list[str],
                    deadline: Deadline, slow: bool = False) -> Any:
    """The periodic solution of the full equations to start on (start "periodic", or "auto"
    for a nonlinear run of a model that is not asymptotically stable), or None.

    It comes from :mod:`resonant.analyses.periodic` (harmonic balance, which builds on this
    module) through :func:`hooks.call`, so that this module does not import it."""
    # auto: also for a damped model whose transient would not decay within the default run
    wanted = start == "periodic" or (start == "auto" and nonlinear and not given
                                     and (stability != ASYMPTOTIC or slow)
                                     and solution is not None)
    if not wanted:
        return None
    if not nonlinear:
        if start == "periodic":
            raise AnalysisError("start 'periodic' is the periodic solution of the full "
                                "equations: it needs nonlinear=True (--nonlinear); the linear "
                                "periodic solution is start 'stationary'")
        return None
    try:
        periodic = hooks.call("periodic_solution", system, deadline=deadline)
    except (AnalysisError, np.linalg.LinAlgError, ValueError) as exc:
        if start == "periodic" or isinstance(exc, AnalysisTimeout):
            raise
        warnings.append(f"no periodic solution of the full equations was found ({exc}); the "
                        "model is not asymptotically stable, so a run from the linear "
                        "stationary state beats and never settles: there is no steady state "
                        "to measure (the amplitudes are the peaks of the beating)")
        return None
    if not periodic.stable and start == "auto":
        largest = float(np.abs(periodic.multipliers).max())
        warnings.append(f"the periodic solution of the full equations near the linear one is "
                        f"unstable (largest Floquet multiplier {largest:.3g}): there is no "
                        "steady state to measure; started from the linear stationary state "
                        "(start 'periodic' starts on it anyway)")
        return None
    warnings.append(f"started on the periodic solution of the full equations (harmonic "
                    f"balance, H = {periodic.harmonics}, residual {periodic.residual:.2g}"
                    f"{'' if periodic.stable else ', unstable'}): "
                    + ("an undamped model never settles, a run from rest beats forever"
                       if stability != ASYMPTOTIC else "no transient"))
    return periodic


def _equilibrium_values(model: Model) -> np.ndarray:
    values = []
    for c in model.coordinates:
        if c in model.equilibrium:
            expr = model.equilibrium[c].to_sympy(
                lambda n, p: sympy.Float(model.parameter_values[n]) if p == 0 else 0)
            values.append(float(expr))
        else:
            values.append(0.0)
    return np.array(values, dtype=float)


def parse_initial(model: Model, initial: Mapping[str, float | str] | None
                  ) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Deviations and velocities from ``{"x1": 0.01, "x2'": "0.1*l"}`` (None where not given).

    Values may be expressions of the parameters (parsed, never evaluated as code).

    Examples
    --------
    >>> from resonant.api import loads
    >>> m = loads('[parameters]\\nl = 2\\n[coordinates]\\nx = ""\\n[energy]\\nT = "x\\'^2/2"')
    >>> parse_initial(m, {"x": "l/4", "x'": 1})
    (array([0.5]), array([1.]))
    """
    if not initial:
        return None, None

    n = len(model.coordinates)
    index = {c: i for i, c in enumerate(model.coordinates)}
    q0, v0 = np.full(n, np.nan), np.full(n, np.nan)
    problems = []
    for key, value in initial.items():
        name = key.strip()
        order = len(name) - len(name.rstrip("'"))
        base = name.rstrip("'")
        if base not in index or order > 1:
            problems.append(Problem(
                f"'{key}' is not a coordinate or a coordinate's velocity (coordinates: "
                f"{name_list(model.coordinates)}; a velocity is written x')", "--initial"))
            continue
        try:
            expression = parse(value, allowed=set(model.parameters), file="--initial", key=name)
            primed = primed_names(expression)
            if primed:
                problems.append(Problem(constant_prime_message(primed), "--initial", "", name))
                continue
            number = float(expression.to_sympy(
                lambda nm, p: sympy.Float(model.parameter_values[nm])).evalf())
        except ModelError as exc:
            problems.extend(exc.problems)
            continue
        except (TypeError, ValueError):
            problems.append(Problem(f"'{value}' is not a real number", "--initial", "", name))
            continue
        except (ArithmeticError, RecursionError):
            number = math.inf
        if not math.isfinite(number) or abs(number) > MAX_INITIAL:
            problems.append(Problem(f"'{value}' is not a finite number of at most "
                                    f"{MAX_INITIAL:g} in magnitude", "--initial", "", name))
            continue
        (v0 if order else q0)[index[base]] = number
    if problems:
        raise ModelError(problems)
    return q0, v0


class _Progress:
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


def simulate(system: LinearSystem, duration: float | None = None, nonlinear: bool = False,
             initial: Mapping[str, float | str] | None = None, *, start: str = "auto",
             periods: float = DEFAULT_PERIODS, method: str | None = None, rtol: float = 1e-9,
             progress: bool | None = None, deadline: Deadline = NO_DEADLINE) -> Simulation:
    """Integrate the model's equations of motion in time.

    Parameters
    ----------
    system : LinearSystem
        The system of a model (``nonlinear=True`` needs a model given by its
        energies, not ``[matrices]``).
    duration : float, optional
        End time in s.  Default: for an asymptotically stable system, long
        enough for the slowest transient to decay by ``exp(-12)``; otherwise
        (undamped) 15 periods of the lowest excitation frequency (or natural
        frequency, for free vibration) plus the measurement window; capped at
        4000 cycles of the highest frequency (a warning says so).
    nonlinear : bool
        Integrate the full Lagrange equations instead of the linearized ones.
    initial : mapping, optional
        Initial deviations from the reference state and velocities, e.g.
        ``{"x1": 0.01, "x2'": 0}``; values may be expressions of parameters.
        Coordinates not given start at their ``start`` value.
    start : {"auto", "rest", "stationary", "periodic"}
        ``"rest"``: zero deviations and velocities.  ``"stationary"``: the
        linear stationary solution's q_p(0), q_p'(0), so that a linear run
        is stationary from the start.  ``"periodic"`` (nonlinear runs): the
        periodic solution of the full equations by harmonic balance
        (:func:`resonant.analyses.periodic.periodic_solution`).  ``"auto"``
        (default): for a model that is not asymptotically stable (undamped: a
        free vibration never decays) and no ``initial``, ``"periodic"`` for a
        nonlinear run when harmonic balance converges (else a warning says
        there is no steady state to measure) and ``"stationary"`` otherwise;
        ``"rest"`` for an asymptotically stable model.
    periods : float
        Length of the measurement window, in periods of the lowest excitation
        frequency (of the lowest natural frequency without excitation).
    method : str, optional
        A :func:`scipy.integrate.solve_ivp` method; default ``"DOP853"``, or
        ``"LSODA"`` when the natural frequencies spread over more than 3
        decades (stiff).
    rtol : float
        Relative tolerance; the absolute tolerance is ``rtol`` times 1e-2 of
        the expected amplitude (times the frequency for velocities).
    progress : bool, optional
        Show progress on stderr; default: only when stderr is a terminal.
    deadline : Deadline, optional
        Checked during the integration.

    Returns
    -------
    Simulation
        The amplitude of each coordinate and output is the **peak absolute
        deviation** from the reference state over the window (the stationary
        ``amplitudes`` use the same definition), measured on a fine sampling
        of the integrator's dense output.

    Raises
    ------
    AnalysisError
        If the integration breaks down (the response blows up, the pendulum
        leaves the range where the model is defined): the message gives the
        time.  For ``nonlinear=True`` on a ``[matrices]`` model.
    """
    import scipy.integrate

    model = system._model()
    if start not in START_MODES:
        raise AnalysisError(f"start must be one of {', '.join(START_MODES)}, not '{start}'")
    if method is not None and method not in METHODS:
        raise AnalysisError(f"method must be one of {', '.join(METHODS)}, not '{method}'")
    if duration is not None and not (math.isfinite(duration) and duration > 0):
        raise AnalysisError(f"the duration must be a positive number of seconds, not {duration}")
    if not (math.isfinite(periods) and periods > 0):
        raise AnalysisError(f"periods must be positive, not {periods}")
    if nonlinear and model.matrices is not None:
        raise AnalysisError("a [matrices] model has no nonlinear equations: --nonlinear needs "
                            "a model given by its energies")
    warnings: list[str] = []
    eom: Any = system
    num = system.numeric(deadline).dense()
    check_mass_matrix(num.M, num.coordinates)
    n = num.n
    eigenvalues = state_eigenvalues(num.M, num.C, num.K)
    stability = classify(eigenvalues)
    omegas_n = np.abs(eigenvalues.imag)
    omegas_n = omegas_n[omegas_n > 1e-9 * max(1.0, float(omegas_n.max(initial=0.0)))]
    excitation = [h.omega for h in num.harmonics if h.omega > 0] if num.harmonic else []

    solution: StationarySolution | None = None
    if not num.harmonic:
        warnings.append("the signals are not sums of harmonics: there is no linear stationary "
                        "prediction to compare with (relative_difference is empty)")
    elif num.harmonics:
        try:
            solution = stationary(num, deadline)
        except AnalysisError as exc:
            warnings.append(f"no linear stationary prediction: {exc}")
    if stability == UNSTABLE:
        warnings.append("the equilibrium is unstable: the response grows with time")

    # time scales
    highest = max([*excitation, *omegas_n, 1e-300])
    if excitation:
        window_length = periods * 2 * math.pi / min(excitation)
    elif omegas_n.size:
        window_length = periods * 2 * math.pi / float(omegas_n.min())
    else:
        window_length = None
    if highest <= 1e-300:
        highest = 2 * math.pi  # no frequency at all (rigid bodies, no signals)

    # initial state
    q_given, v_given = parse_initial(model, initial)
    # the slowest decay rate: a transient falls to exp(-sigma t) of its size
    sigma = float(np.min(-eigenvalues.real)) if stability == ASYMPTOTIC else 0.0
    settle_time = SETTLED_DECAY / sigma if sigma > 0 else math.inf
    slow = stability == ASYMPTOTIC and duration is None and \
        settle_time > MAX_DEFAULT_CYCLES * 2 * math.pi / highest
    periodic = _periodic_start(system, start, nonlinear, bool(initial), stability, solution,
                               warnings, deadline, slow)
    if periodic is not None:
        start_kind = "periodic"
    elif start == "auto":
        use_stationary = (initial is None or not initial) and stability != ASYMPTOTIC \
            and solution is not None
        start_kind = "stationary" if use_stationary else "rest"
    else:
        start_kind = start
    if start_kind == "stationary" and solution is None:
        raise AnalysisError("there is no linear stationary solution to start from; use "
                            "start 'rest' or give the initial state")
    q0, v0 = np.zeros(n), np.zeros(n)
    if start_kind == "stationary":
        assert solution is not None
        for h in solution.harmonics:
            q0 += h.L
            v0 += h.omega * h.N
    if periodic is not None:
        q0 = np.array([periodic.initial[c] for c in num.coordinates])
        v0 = np.array([periodic.initial[c + "'"] for c in num.coordinates])
    if q_given is not None and v_given is not None:
        q0 = np.where(np.isnan(q_given), q0, q_given)
        v0 = np.where(np.isnan(v_given), v0, v_given)
        if start_kind == "rest":
            start_kind = "given"
    if not eom.excitation and not np.any(q0) and not np.any(v0):
        warnings.append("nothing excites the system (no signals, initial state at rest): the "
                        "response is zero; give an initial state")
    if start_kind == "stationary":
        warnings.append("started from the linear stationary solution's initial state "
                        "q_p(0), q_p'(0)" + (" (undamped: a free vibration would never "
                                             "decay)" if stability != ASYMPTOTIC else ""))

    # duration
    if duration is None:
        if stability == ASYMPTOTIC and start_kind not in ("stationary", "periodic") and (
                excitation or np.any(q0) or np.any(v0) or not num.harmonic):
            sigma = float(np.min(-eigenvalues.real))
            duration = DECAY_TIMES / sigma + (window_length or 0.0)
        else:
            slowest = (min(excitation) if excitation else
                       float(omegas_n.min()) if omegas_n.size else 2 * math.pi / 10)
            duration = UNDAMPED_PERIODS * 2 * math.pi / slowest + (window_length or 0.0)
        cap = MAX_DEFAULT_CYCLES * 2 * math.pi / highest
        if duration > cap:
            warnings.append(f"the default duration ({duration:.4g} s) is capped at {cap:.4g} s "
                            f"({MAX_DEFAULT_CYCLES:.0f} cycles of the highest frequency): the "
                            "transient may not have decayed; give --duration")
            duration = cap
    periods_run = duration * highest / (2 * math.pi)
    if periods_run > MAX_PERIODS:
        longest = MAX_PERIODS * 2 * math.pi / highest
        raise AnalysisError(
            f"a duration of {duration:.6g} s is {periods_run:.3g} periods of the highest "
            f"frequency ({highest:.6g} rad/s); a run is limited to {MAX_PERIODS:.0e} periods: "
            f"ask for --duration {longest:.6g} or less")
    if window_length is None or window_length > duration / 2:
        if window_length is not None:
            warnings.append(f"the run is shorter than two measurement windows: amplitudes are "
                            f"measured over the second half (t > {duration / 2:.4g} s)")
        window_length = duration / 2
    window = (duration - window_length, duration)

    # the system
    if nonlinear:
        dynamics: Any = _NonlinearSystem(model, _equilibrium_values(model))
    else:
        dynamics = _LinearSystem(eom, num, model)
    for name in dynamics.unsupported:
        warnings.append(f"output '{name}' depends on a coordinate's derivative of order > 2 "
                        "and is not simulated")
    y0 = dynamics.to_state(q0, v0)

    scale = max([*(solution.amplitudes[c] for c in num.coordinates)] if solution else [0.0])
    scale = max(scale, float(np.abs(q0).max(initial=0.0)),
                float(np.abs(v0).max(initial=0.0)) / highest)
    if scale == 0.0:
        scale = 1.0
    atol = np.concatenate([np.full(n, 1e-2 * rtol * scale),
                           np.full(n, 1e-2 * rtol * scale * highest)])
    spread = highest / max(min([*excitation, *omegas_n, highest]), 1e-300)
    if method is None:
        method = "LSODA" if spread > STIFF_RATIO else "DOP853"

    show = sys.stderr.isatty() if progress is None else progress
    report = _Progress(duration, show)
    calls = [0, MAX_RHS_CALLS]  # evaluations so far, and where this attempt must stop
    reached = [0.0]

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        calls[0] += 1
        reached[0] = max(reached[0], t)
        if calls[0] % 2000 == 0:
            report(t)
        if calls[0] % 200 == 0:
            deadline.check(f"while integrating (t = {t:.4g} of {duration:.4g} s)",
                           analysis=True)
        if calls[0] > calls[1]:
            raise _Budget(t)
        try:
            with np.errstate(all="ignore"):
                dy = dynamics.rhs(t, y)
            if not math.isfinite(dy.sum()):  # one cheap test catches NaN and infinity
                raise _Breakdown(t, "the response is not finite")
        except ArithmeticError as exc:  # Python floats: 1/t at t = 0, overflow
            error = _Breakdown(t, f"the equations cannot be evaluated there ({exc}; a signal "
                                  "such as 1/t undefined at that time?)", small=False)
            error.state = np.array(y, dtype=float)
            raise error from None
        except _Breakdown as exc:
            exc.state = np.array(y, dtype=float)
            raise
        return dy

    kind = "nonlinear" if nonlinear else "linear"
    jacobian = dynamics.jacobian()

    def integrate(how: str) -> Any:
        options: dict[str, Any] = {}
        if jacobian is not None and how in ("Radau", "BDF", "LSODA"):
            options["jac"] = lambda t, y: jacobian
        with np.errstate(over="ignore", invalid="ignore"):  # the rhs checks finiteness
            return scipy.integrate.solve_ivp(rhs, (0.0, duration), y0, method=how, rtol=rtol,
                                             atol=atol, dense_output=True, **options)

    stiff_trial = method in EXPLICIT_METHODS and spread > STIFF_RATIO
    try:
        result = None
        if method in EXPLICIT_METHODS:
            calls[1] = STIFF_TRIAL_CALLS if stiff_trial else MAX_RHS_CALLS
            try:
                result = integrate(method)
            except _Budget:
                if not stiff_trial:
                    raise
            if result is None or result.status != 0:
                why = (f"needed more than {STIFF_TRIAL_CALLS:.0e} evaluations" if result is None
                       else f"failed ({result.message})")
                decades = f"{math.log10(max(spread, 1.0)):.1f} decades"
                warnings.append(
                    f"{method} {why} at t = {reached[0]:.4g} s: the system "
                    f"{'is' if stiff_trial else 'may be'} stiff (its frequencies spread over "
                    f"{decades}); integrated with {STIFF_METHOD} (implicit, for stiff systems) "
                    "instead")
                method = STIFF_METHOD
                reached[0] = 0.0
                result = None
        if result is None:
            calls[1] = MAX_RHS_CALLS
            result = integrate(method)
    except _Budget as exc:
        raise AnalysisError(
            f"the {kind} integration stopped at t = {exc.t:.6g} s of {duration:.6g} s: it "
            f"needed more than {MAX_RHS_CALLS:.0e} evaluations of the equations (the limit "
            "of one run); ask for a shorter --duration") from None
    except _Breakdown as exc:
        where = ""
        if exc.state is not None:
            where = " (" + ", ".join(f"{c} = {v:.6g}" for c, v in
                                     zip(num.coordinates, exc.state[:n])) + ")"
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

    # samples: a uniform grid for the history and a finer one for the amplitudes
    count = int(min(MAX_SAMPLES, max(2001, duration * highest / (2 * math.pi)
                                     * SAMPLES_PER_PERIOD + 1)))
    t = np.linspace(0.0, duration, count)
    with np.errstate(all="ignore"):  # not finite: reported below
        q, outputs = dynamics.evaluate(t, result.sol(t))
    states = {c: q[i] for i, c in enumerate(num.coordinates)}
    states.update(outputs)
    fine = int(min(MAX_WINDOW_SAMPLES, max(5001, window_length * highest / (2 * math.pi)
                                           * WINDOW_SAMPLES_PER_PERIOD + 1)))
    tw = np.linspace(window[0], window[1], fine)
    with np.errstate(all="ignore"):
        qw, outw = dynamics.evaluate(tw, result.sol(tw))
    steady = {c: _peak(qw[i]) for i, c in enumerate(num.coordinates)}
    steady.update({name: _peak(y) for name, y in outw.items()})
    bad = [name for name, a in steady.items() if not math.isfinite(a)]
    if bad:
        raise AnalysisError(f"the {kind} response of {name_list(bad)} is not finite")

    linear: dict[str, float] = {}
    response: dict[str, np.ndarray] = {}
    relative: dict[str, float] = {}
    if solution is not None:
        linear = {name: float(solution.amplitudes[name]) for name in states
                  if name in solution.amplitudes}
        predicted = solution.response(t)
        response = {name: predicted[name] for name in states if name in predicted}
        largest = max(linear.values(), default=0.0)
        for name, a in linear.items():
            if a > 1e-9 * largest and a > 0:
                relative[name] = steady[name] / a - 1.0
        skipped = [name for name in linear if name not in relative]
        if skipped:
            warnings.append(f"no relative difference for {name_list(skipped)}: the linear "
                            "stationary amplitude is zero")
        large = {name: d for name, d in relative.items() if abs(d) > LARGE_DIFFERENCE}
        # like with like: a run from rest (or a given state) whose slowest transient has not
        # decayed by the window compares a transient with a steady state
        settled = start_kind in ("stationary", "periodic") or sigma * window[0] >= SETTLED_DECAY
        if large and not settled:
            worst = max(large, key=lambda k: abs(large[k]))
            left = math.exp(-sigma * window[0]) if sigma > 0 else 1.0
            warnings.append(
                f"the response has not settled: the slowest mode decays as "
                f"exp(-{sigma:.3g} t), so {100 * left:.3g}% of the transient is left when the "
                f"amplitude window starts; settling takes about {settle_time:.4g} s. The "
                f"difference of up to {100 * large[worst]:+.3g}% ({worst}) includes the "
                "transient" + (", not only the nonlinearity (start 'periodic' measures the "
                               "steady state of the full equations directly)"
                               if nonlinear else ""))
            large = {}
        if large:
            worst = max(large, key=lambda k: abs(large[k]))
            what = ("small oscillations do not hold: the nonlinear response differs from the "
                    "linear prediction" if nonlinear else
                    "the simulated response has not settled to the stationary solution")
            warnings.append(f"{what} by up to {100 * large[worst]:+.3g}% ({worst}: "
                            f"{steady[worst]:.4g} vs {linear[worst]:.4g})")
    return Simulation(
        title=model.title, coordinates=num.coordinates, t=t,
        states=MappingProxyType(states), linear_response=MappingProxyType(response),
        steady_amplitudes=MappingProxyType(steady), linear_amplitudes=MappingProxyType(linear),
        relative_difference=MappingProxyType(relative), window=window, nonlinear=nonlinear,
        start=start_kind, method=method,
        initial=MappingProxyType({**{c: float(q0[i]) for i, c in enumerate(num.coordinates)},
                                  **{c + "'": float(v0[i])
                                     for i, c in enumerate(num.coordinates)}}),
        warnings=tuple(warnings))


__all__ = ["Simulation", "simulate", "parse_initial"]
