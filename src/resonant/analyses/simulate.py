"""Time simulation of a model: the linearized and the full nonlinear equations.

The linear simulation integrates ``M q'' + C q' + K q = Q(t)`` with the
signals written out as functions of time (:attr:`LinearEOM.Q`); the nonlinear
one integrates the full Lagrange equations ``mass(q, ...) q'' + rest(q, q',
signals) = 0`` of :class:`~resonant.system.NonlinearSystem` (compiled once by the system).  Both are
integrated with :func:`scipy.integrate.solve_ivp`
(:mod:`resonant.analyses.time_integration`).

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
import os
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt
import sympy

from ..arrays import freeze_fields
from ..charts import (
    COLORS,
    MAX_CURVES,
    Chart,
    Charts,
    Curve,
    PathArg,
    Rule,
    Span,
    check_plot_path,
    draw_figure,
    save_figure,
    unit_text,
)
from ..deadline import NO_DEADLINE, AnalysisTimeout, Deadline
from ..errors import AnalysisError, ModelError, Problem, name_list, printable
from ..expressions import parse, primed_names
from ..expressions.notation import dollar_name
from ..modal import point_state_eigenvalues
from ..model.options import START_KINDS, SimulationOptions, chosen
from ..model.types import constant_prime_message
from ..model.unbalance_loads import with_unbalance_loads
from ..model.units_display import (
    NO_UNIT,
    ResultUnits,
    Shown,
    curve_units,
    name_label,
    shown_unit,
    unit_suffix,
)
from ..system.base import LinearSystem, NumericEOM
from ..system.build import linear_system as build_linear_system
from ..system.build import nonlinear_system
from ..system.nonlinear import NonlinearSystem
from ..system.stability import (
    ASYMPTOTIC,
    UNSTABLE,
    check_mass_matrix,
    classify,
)
from ..tables import ResultTable, number_cell
from .peaks import sampled_peak
from .periodic import PeriodicSolution, periodic_solution
from .result_fields import FieldsJSON, Framed, saved
from .stationary import StationarySolution, stationary
from .time_integration import (
    STIFF_RATIO,
    LinearDynamics,
    NonlinearDynamics,
    dense_values,
    integrate,
    resolved_frequency,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: measurement window: this many periods of the lowest excitation frequency
DEFAULT_PERIODS = 5.0
#: a damped run lasts until the slowest transient has decayed by exp(-DECAY_TIMES)
DECAY_TIMES = 12.0
#: default duration of an undamped run, in periods of the lowest frequency (+ the window)
UNDAMPED_PERIODS = 15.0
#: upper bound of a default duration, in cycles of the highest frequency involved
MAX_DEFAULT_CYCLES = 4000.0
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
#: longest run, in periods of the highest frequency involved (excitation or natural)
MAX_PERIODS = 1e6
#: largest initial deviation or velocity: squares and the error norms stay finite
MAX_INITIAL = 1e100

@dataclass(frozen=True)
class Simulation(FieldsJSON, Framed):
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
        ``"rest"``, ``"stationary"`` (the stationary solution's initial state),
        ``"periodic"`` (the periodic solution of the full equations) or ``"given"``
        (``initial`` values): a key of :data:`resonant.model.options.START_KINDS`.
    title, coordinates
        The model's title and its coordinates.
    nonlinear : bool
        Whether the full equations were integrated.
    method : str
        The integrator (a :func:`scipy.integrate.solve_ivp` method).
    initial : mapping
        The initial deviation of every coordinate and its rate (``"x'"``).
    warnings : tuple of str
        What the user should know.

    Examples
    --------
    >>> import resonant
    >>> sim = simulate(resonant.load("examples/two_dof_free.toml").linearize(), duration=0.1,
    ...                initial={"x1": 0.01})
    >>> sim.start, sim.nonlinear, float(sim.t[0])
    ('given', False, 0.0)
    """

    #: the columns of to_frame() (resonant.analyses.result_fields.Framed)
    _frame = (("t", "t"), ("states", "{key}"))
    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON): the summary,
    #: then the time history (only by ``to_dict(history=True)``, which from_dict needs)
    _json_order = ("title", "coordinates", "nonlinear", "t_end", "samples", "method", "start",
                   "initial", "window", "amplitude_definition", "steady_amplitudes",
                   "linear_amplitudes", "relative_difference", "warnings", "history")

    title: str
    coordinates: tuple[str, ...]
    t: np.ndarray = saved(history=True)
    states: Mapping[str, np.ndarray] = saved(history=True, axes=("t",))
    linear_response: Mapping[str, np.ndarray] = saved(history=True, axes=("t",))
    steady_amplitudes: Mapping[str, float] = saved()
    linear_amplitudes: Mapping[str, float] = saved()
    relative_difference: Mapping[str, float] = saved()
    window: tuple[float, float] = saved()
    nonlinear: bool = saved()
    start: str = saved()
    method: str = saved()
    initial: Mapping[str, float] = saved(default_factory=dict)
    warnings: tuple[str, ...] = saved(())

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def t_end(self) -> float:
        return float(self.t[-1])

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.states)

    def _derived_json(self) -> dict[str, Any]:
        return {"t_end": self.t_end, "samples": int(self.t.size),
                "amplitude_definition": "peak absolute deviation from the reference state "
                                        "over the window"}

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

    def chart(self, units: Mapping[str, str] | None = None) -> Charts:
        """The figure's description: each history against time, the linear prediction
        dashed, the window of the steady amplitudes shaded (:func:`simulation_chart`).

        Parameters
        ----------
        units : mapping, optional
            name -> unit text for the axis labels.

        Returns
        -------
        resonant.charts.Charts
        """
        return simulation_chart(self, units)

    def plot(self, path: str | os.PathLike[str] | None = None,
             axes: Sequence[Axes] | None = None,
             units: Mapping[str, str] | None = None) -> Figure:
        """The time histories (:func:`resonant.analyses.simulate.plot_simulation`).

        Parameters
        ----------
        path : str or Path, optional
            Save the figure there (format from the suffix).
        axes : sequence of matplotlib.axes.Axes, optional
            Draw into the caller's axes (one per coordinate).
        units : mapping, optional
            coordinate -> unit text for the axis labels.

        Returns
        -------
        matplotlib.figure.Figure
        """
        return plot_simulation(self, path=path, axes=axes, units=units)

    def summary(self) -> str:
        """The text ``resonant simulate`` prints
        (:func:`resonant.analyses.simulate.simulation_text`).

        Returns
        -------
        str

        Examples
        --------
        >>> import resonant
        >>> sim = resonant.load("examples/two_dof_free.toml").simulate(0.05, initial={"x1": 0.01})
        >>> sim.start, "x1" in sim.summary()
        ('given', True)
        """
        return simulation_text(self)


def _fmt(value: float | None, percent: bool = False) -> str:
    if value is None:
        return ""
    return f"{100 * value:+.4g}%" if percent else f"{value:.6g}"



@dataclass(frozen=True)
class _Scales:
    """The time scales of a linear system: its eigenvalues and the excitation frequencies."""

    eigenvalues: np.ndarray
    stability: str
    natural: np.ndarray
    excitation: list[float]
    highest: float
    window: float | None
    sigma: float

    @staticmethod
    def of(num: NumericEOM, periods: float) -> _Scales:
        eigenvalues = point_state_eigenvalues(num.M, num.C, num.K)
        stability = classify(eigenvalues)
        natural = np.abs(eigenvalues.imag)
        natural = natural[natural > 1e-9 * max(1.0, float(natural.max(initial=0.0)))]
        excitation = [h.omega for h in num.harmonics if h.omega > 0] if num.harmonic else []
        highest = max([*excitation, *natural, 1e-300])
        window = (periods * 2 * math.pi / min(excitation) if excitation else
                  periods * 2 * math.pi / float(natural.min()) if natural.size else None)
        if highest <= 1e-300:
            highest = 2 * math.pi  # no frequency at all (rigid bodies, no signals)
        # the slowest decay rate: a transient falls to exp(-sigma t) of its size
        sigma = float(np.min(-eigenvalues.real)) if stability == ASYMPTOTIC else 0.0
        return _Scales(eigenvalues, stability, natural, excitation, highest, window, sigma)

    @property
    def settle_time(self) -> float:
        return SETTLED_DECAY / self.sigma if self.sigma > 0 else math.inf

    @property
    def slowest(self) -> float:
        return (min(self.excitation) if self.excitation else
                float(self.natural.min()) if self.natural.size else 2 * math.pi / 10)

    @property
    def spread(self) -> float:
        return float(self.highest / max(min([*self.excitation, *self.natural, self.highest]),
                                        1e-300))


def _periodic_start(system: NonlinearSystem | None, start: str, given: bool,
                    stability: str, solution: StationarySolution | None, warnings: list[str],
                    deadline: Deadline, slow: bool = False) -> PeriodicSolution | None:
    """The periodic solution of the full equations to start on (start "periodic", or "auto"
    for a nonlinear run of a model that is not asymptotically stable), or None."""
    # auto: also for a damped model whose transient would not decay within the default run
    nonlinear = system is not None
    wanted = start == "periodic" or (start == "auto" and nonlinear and not given
                                     and (stability != ASYMPTOTIC or slow)
                                     and solution is not None)
    if not wanted:
        return None
    if system is None:
        if start == "periodic":
            raise AnalysisError("start 'periodic' is the periodic solution of the full "
                                "equations: it needs nonlinear=True (--nonlinear); the linear "
                                "periodic solution is start 'stationary'")
        return None
    try:
        periodic = periodic_solution(system, deadline=deadline)
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


def parse_initial(coordinates: Sequence[str], values: Mapping[str, float],
                  initial: Mapping[str, float | str] | None
                  ) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Deviations and velocities from ``{"x1": 0.01, "x2'": "0.1*l"}`` (None where not given).

    Values may be expressions of the parameters ``values`` (parsed, never evaluated as
    code).

    Examples
    --------
    >>> parse_initial(("x",), {"l": 2.0}, {"x": "l/4", "x'": 1})
    (array([0.5]), array([1.]))
    """
    if not initial:
        return None, None

    n = len(coordinates)
    index = {c: i for i, c in enumerate(coordinates)}
    q0, v0 = np.full(n, np.nan), np.full(n, np.nan)
    problems = []
    for key, value in initial.items():
        name = key.strip()
        order = len(name) - len(name.rstrip("'"))
        base = name.rstrip("'")
        if base not in index or order > 1:
            problems.append(Problem(
                f"'{key}' is not a coordinate or a coordinate's velocity (coordinates: "
                f"{name_list(coordinates)}; a velocity is written x')", "--initial"))
            continue
        try:
            expression = parse(value, allowed=set(values), file="--initial", key=name)
            primed = primed_names(expression)
            if primed:
                problems.append(Problem(constant_prime_message(primed), "--initial", "", name))
                continue
            number = float(expression.to_sympy(
                lambda nm, p: sympy.Float(values[nm])).evalf())
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



def _with_unbalance(system: LinearSystem | NonlinearSystem, deadline: Deadline,
                    warnings: list[str]) -> LinearSystem | NonlinearSystem:
    """A rotor's system with its ``[[unbalance]]`` as the rotating load m e Omega^2
    (cos, sin)(Omega t + phi) at the model's speed: a ``[[harmonic]]`` of the model
    (:func:`resonant.model.unbalance_loads.with_unbalance_loads`), so that it takes the one
    load path every harmonic load takes (docs/rotors.md)."""
    linear = system.linear if isinstance(system, NonlinearSystem) else system
    model, speed = linear.model, linear.speed
    if model is None or not model.unbalances or linear.given_matrices is None or \
            speed is None:
        return system
    loaded = with_unbalance_loads(model)
    if loaded is model:
        return system
    if model.parameter_values.get(speed) == 0:
        warnings.append(f"the rotor is at rest ({speed} = 0): its [[unbalance]] loads "
                        f"nothing; give the speed (--set {speed}=...)")
    return nonlinear_system(loaded, deadline) if isinstance(system, NonlinearSystem) \
        else build_linear_system(loaded, deadline)


def _systems(system: LinearSystem | NonlinearSystem, nonlinear: bool | None,
             deadline: Deadline) -> tuple[LinearSystem, NonlinearSystem | None]:
    """The linear system and, for a nonlinear run, the nonlinear one."""
    if isinstance(system, NonlinearSystem):
        return system.linear, system if nonlinear is None or nonlinear else None
    if not nonlinear:
        return system, None
    return system, nonlinear_system(system, deadline)


def _linear_solution(num: NumericEOM, scales: _Scales, warnings: list[str],
                     deadline: Deadline) -> StationarySolution | None:
    """The linear stationary prediction (None, with a warning, where there is none)."""
    solution: StationarySolution | None = None
    if not num.harmonic:
        warnings.append("the signals are not sums of harmonics: there is no linear stationary "
                        "prediction to compare with (relative_difference is empty)")
    elif num.harmonics:
        try:
            solution = stationary(num, deadline)
        except AnalysisError as exc:
            warnings.append(f"no linear stationary prediction: {exc}")
    if scales.stability == UNSTABLE:
        warnings.append("the equilibrium is unstable: the response grows with time")
    return solution


def _start_kind(start: str, given: bool, scales: _Scales,
                solution: StationarySolution | None, periodic: PeriodicSolution | None) -> str:
    if periodic is not None:
        return "periodic"
    if start == "auto":
        use_stationary = not given and scales.stability != ASYMPTOTIC and solution is not None
        return "stationary" if use_stationary else "rest"
    if start == "stationary" and solution is None:
        raise AnalysisError("there is no linear stationary solution to start from; use "
                            "start 'rest' or give the initial state")
    return start


def _initial_state(num: NumericEOM, initial: Mapping[str, float | str] | None,
                   start: str, scales: _Scales, solution: StationarySolution | None,
                   full: NonlinearSystem | None, slow: bool, excited: bool,
                   warnings: list[str], deadline: Deadline
                   ) -> tuple[np.ndarray, np.ndarray, str]:
    """Initial deviations, velocities and the kind of start."""
    q_given, v_given = parse_initial(num.coordinates, num.parameters, initial)
    periodic = _periodic_start(full, start, bool(initial), scales.stability, solution,
                               warnings, deadline, slow)
    start_kind = _start_kind(start, bool(initial), scales, solution, periodic)
    q0, v0 = np.zeros(num.n), np.zeros(num.n)
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
    if not excited and not np.any(q0) and not np.any(v0):
        warnings.append("nothing excites the system (no signals, initial state at rest): the "
                        "response is zero; give an initial state")
    if start_kind == "stationary":
        warnings.append("started from the linear stationary solution's initial state "
                        "q_p(0), q_p'(0)" + (" (undamped: a free vibration would never "
                                             "decay)" if scales.stability != ASYMPTOTIC else ""))
    return q0, v0, start_kind


def _duration(duration: float | None, scales: _Scales, start_kind: str, moving: bool,
              harmonic: bool, warnings: list[str]) -> tuple[float, tuple[float, float]]:
    """The run's length and its measurement window."""
    highest, window_length = scales.highest, scales.window
    if duration is None:
        if scales.stability == ASYMPTOTIC and start_kind not in ("stationary", "periodic") \
                and (scales.excitation or moving or not harmonic):
            duration = DECAY_TIMES / scales.sigma + (window_length or 0.0)
        else:
            duration = UNDAMPED_PERIODS * 2 * math.pi / scales.slowest + (window_length or 0.0)
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
    return duration, (duration - window_length, duration)


def _tolerance(q0: np.ndarray, v0: np.ndarray, solution: StationarySolution | None,
               coordinates: tuple[str, ...], rtol: float, highest: float) -> np.ndarray:
    """The absolute tolerances of deviations and velocities: 1e-2 rtol of the scale."""
    scale = max([*(solution.amplitudes[c] for c in coordinates)] if solution else [0.0])
    scale = max(scale, float(np.abs(q0).max(initial=0.0)),
                float(np.abs(v0).max(initial=0.0)) / highest)
    if scale == 0.0:
        scale = 1.0
    n = len(coordinates)
    return np.concatenate([np.full(n, 1e-2 * rtol * scale),
                           np.full(n, 1e-2 * rtol * scale * highest)])


def _sample(dynamics: Any, result: Any, duration: float, window: tuple[float, float],
            highest: float, coordinates: tuple[str, ...], nonlinear: bool
            ) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, float]]:
    """A uniform grid of the history, and the steady amplitudes on a finer one.

    Both follow the highest frequency the integrator resolved (each in its span), not a
    stiff mode that does not move: the steps of a model at rest span hundreds of periods
    of its stiffest mode (``time_integration.resolved_frequency``).
    """
    shown = resolved_frequency(result.sol, highest)
    count = int(min(MAX_SAMPLES, max(2001, duration * shown / (2 * math.pi)
                                     * SAMPLES_PER_PERIOD + 1)))
    t = np.linspace(0.0, duration, count)
    with np.errstate(all="ignore"):  # not finite: reported below
        q, outputs = dynamics.evaluate(t, dense_values(result.sol, t))
    states = {c: q[i] for i, c in enumerate(coordinates)}
    states.update(outputs)
    length = window[1] - window[0]
    shown = resolved_frequency(result.sol, highest, window[0])
    fine = int(min(MAX_WINDOW_SAMPLES, max(5001, length * shown / (2 * math.pi)
                                           * WINDOW_SAMPLES_PER_PERIOD + 1)))
    tw = np.linspace(window[0], window[1], fine)
    with np.errstate(all="ignore"):
        qw, outw = dynamics.evaluate(tw, dense_values(result.sol, tw))
    steady = {c: sampled_peak(qw[i]) for i, c in enumerate(coordinates)}
    steady.update({name: sampled_peak(y) for name, y in outw.items()})
    bad = [name for name, a in steady.items() if not math.isfinite(a)]
    if bad:
        kind = "nonlinear" if nonlinear else "linear"
        raise AnalysisError(f"the {kind} response of {name_list(bad)} is not finite")
    return t, states, steady


def _not_settled(large: dict[str, float], scales: _Scales, window: tuple[float, float],
                 nonlinear: bool) -> str:
    worst = max(large, key=lambda k: abs(large[k]))
    sigma = scales.sigma
    left = math.exp(-sigma * window[0]) if sigma > 0 else 1.0
    return (f"the response has not settled: the slowest mode decays as "
            f"exp(-{sigma:.3g} t), so {100 * left:.3g}% of the transient is left when the "
            f"amplitude window starts; settling takes about {scales.settle_time:.4g} s. The "
            f"difference of up to {100 * large[worst]:+.3g}% ({worst}) includes the "
            "transient" + (", not only the nonlinearity (start 'periodic' measures the "
                           "steady state of the full equations directly)" if nonlinear else ""))


def _compare(solution: StationarySolution | None, t: np.ndarray, states: Mapping[str, Any],
             steady: Mapping[str, float], start_kind: str, scales: _Scales,
             window: tuple[float, float], nonlinear: bool, warnings: list[str]
             ) -> tuple[dict[str, float], dict[str, np.ndarray], dict[str, float]]:
    """Linear amplitudes, the linear response and the relative differences (with warnings)."""
    if solution is None:
        return {}, {}, {}
    linear = {name: float(solution.amplitudes[name]) for name in states
              if name in solution.amplitudes}
    predicted = solution.response(t)
    response = {name: predicted[name] for name in states if name in predicted}
    largest = max(linear.values(), default=0.0)
    relative = {name: steady[name] / a - 1.0 for name, a in linear.items()
                if a > 1e-9 * largest and a > 0}
    skipped = [name for name in linear if name not in relative]
    if skipped:
        warnings.append(f"no relative difference for {name_list(skipped)}: the linear "
                        "stationary amplitude is zero")
    large = {name: d for name, d in relative.items() if abs(d) > LARGE_DIFFERENCE}
    # like with like: a run from rest (or a given state) whose slowest transient has not
    # decayed by the window compares a transient with a steady state
    settled = start_kind in ("stationary", "periodic") or \
        scales.sigma * window[0] >= SETTLED_DECAY
    if large and not settled:
        warnings.append(_not_settled(large, scales, window, nonlinear))
    elif large:
        worst = max(large, key=lambda k: abs(large[k]))
        what = ("small oscillations do not hold: the nonlinear response differs from the "
                "linear prediction" if nonlinear else
                "the simulated response has not settled to the stationary solution")
        warnings.append(f"{what} by up to {100 * large[worst]:+.3g}% ({worst}: "
                        f"{steady[worst]:.4g} vs {linear[worst]:.4g})")
    return linear, response, relative


def simulate(system: LinearSystem | NonlinearSystem, duration: float | None = None,
             nonlinear: bool | None = None, initial: Mapping[str, float | str] | None = None,
             *, start: str = "auto", periods: float | None = None,
             method: str | None = None, rtol: float = 1e-9, progress: bool | None = None,
             deadline: Deadline = NO_DEADLINE, options: SimulationOptions | None = None
             ) -> Simulation:
    """Integrate the model's equations of motion in time.

    Parameters
    ----------
    system : LinearSystem or NonlinearSystem
        The linear system of a model, or the full equations
        (:func:`resonant.system.nonlinear_system`: a model given by its
        energies, or ``[matrices]`` with ``[[nonlinear]]`` elements).  A rotor's
        ``[[unbalance]]`` is integrated as the rotating load m e Omega^2 it is at the
        speed parameter's value (docs/rotors.md, The unbalance in time).
    duration : float, optional
        End time in s.  Default: for an asymptotically stable system, long
        enough for the slowest transient to decay by ``exp(-12)``; otherwise
        (undamped) 15 periods of the lowest excitation frequency (or natural
        frequency, for free vibration) plus the measurement window; capped at
        4000 cycles of the highest frequency (a warning says so).
    nonlinear : bool, optional
        Integrate the full equations instead of the linearized ones.  Default:
        for a NonlinearSystem yes, for a LinearSystem no (``True`` derives and
        compiles its full equations).
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
    periods : float, optional
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
    options : SimulationOptions, optional
        Every option above but ``deadline`` as one record (then not as keywords):
        :class:`resonant.model.options.SimulationOptions`.

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
        time.  For ``nonlinear=True`` on a ``[matrices]`` model without ``[[nonlinear]]``
        elements.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/two_dof_free.toml").linearize()
    >>> simulate(eom, 0.05, initial={"x2": 0.01}).initial["x2"]
    0.01
    """
    given = chosen(options, SimulationOptions(duration, nonlinear, initial, start, periods,
                                              method, rtol, progress))
    duration, nonlinear, initial, start = given.duration, given.nonlinear, given.initial, \
        given.start
    method, rtol, progress = given.method, given.rtol, given.progress
    periods = DEFAULT_PERIODS if given.periods is None else given.periods
    warnings: list[str] = []
    linear_system, full = _systems(_with_unbalance(system, deadline, warnings), nonlinear,
                                   deadline)
    num = linear_system.numeric(deadline).dense()
    check_mass_matrix(num.M, num.coordinates)
    scales = _Scales.of(num, periods)
    solution = _linear_solution(num, scales, warnings, deadline)
    slow = scales.stability == ASYMPTOTIC and duration is None and \
        scales.settle_time > MAX_DEFAULT_CYCLES * 2 * math.pi / scales.highest
    equations = linear_system.symbolic()
    excited = equations is not None and bool(equations.excitation)  # signals or loads
    q0, v0, start_kind = _initial_state(num, initial, start, scales, solution, full,
                                        slow, excited, warnings, deadline)
    duration, window = _duration(duration, scales, start_kind,
                                 bool(np.any(q0) or np.any(v0)), num.harmonic, warnings)
    dynamics: Any = NonlinearDynamics(full) if full is not None else \
        LinearDynamics(linear_system, num)
    for name in dynamics.unsupported:
        warnings.append(f"output '{name}' depends on a coordinate's derivative of order > 2 "
                        "and is not simulated")
    if method is None:
        method = "LSODA" if scales.spread > STIFF_RATIO else "DOP853"
    show = sys.stderr.isatty() if progress is None else progress
    result, method = integrate(
        dynamics, dynamics.to_state(q0, v0), duration, method, rtol,
        _tolerance(q0, v0, solution, num.coordinates, rtol, scales.highest), scales.spread,
        num.coordinates, full is not None, warnings, deadline, show)
    t, states, steady = _sample(dynamics, result, duration, window, scales.highest,
                                num.coordinates, full is not None)
    linear, response, relative = _compare(solution, t, states, steady, start_kind, scales,
                                          window, full is not None, warnings)
    return Simulation(
        title=linear_system.title, coordinates=num.coordinates, t=t,
        states=MappingProxyType(states), linear_response=MappingProxyType(response),
        steady_amplitudes=MappingProxyType(steady), linear_amplitudes=MappingProxyType(linear),
        relative_difference=MappingProxyType(relative), window=window,
        nonlinear=full is not None, start=start_kind, method=method,
        initial=MappingProxyType({**{c: float(q0[i]) for i, c in enumerate(num.coordinates)},
                                  **{c + "'": float(v0[i])
                                     for i, c in enumerate(num.coordinates)}}),
        warnings=tuple(warnings))


def simulation_chart(sim: Simulation, units: Mapping[str, str] | ResultUnits | None = None
                     ) -> Charts:
    """What the figure of a simulation shows: each coordinate's and output's deviation
    against time in a panel of its own, the linear stationary prediction dashed, the
    window the steady amplitude is read in shaded.

    Parameters
    ----------
    sim : Simulation
    units : ResultUnits or mapping, optional
        The display units (values and times converted), or name -> SI unit
        (``ResultUnits.si``), shown in each panel's label.

    Returns
    -------
    Charts
    """
    kind = "nonlinear" if sim.nonlinear else "linear"
    time = shown_unit(units, "s") if isinstance(units, ResultUnits) else Shown("s")
    shown = curve_units(units, sim.names)
    t = time(np.asarray(sim.t, dtype=float))
    xlim = (float(t[0]), float(t[-1])) if t.size > 1 and t[-1] > t[0] else (0.0, 1.0)
    panels = []
    drawn = _largest_motions(sim, units)
    for name in drawn:
        value = shown[name]
        curves = [Curve(t, value(np.asarray(sim.states[name], dtype=float)),
                        f"{kind} simulation", COLORS[0], 1.0)]
        if name in sim.linear_response:
            curves.append(Curve(t, value(np.asarray(sim.linear_response[name], dtype=float)),
                                "linear stationary prediction", COLORS[3], 1.0, "3.7 1.6"))
        steady = sim.steady_amplitudes.get(name)
        text = f"steady amplitude {value(steady):.4g}" if steady is not None else ""
        if name in sim.linear_amplitudes:
            text += f", linear {value(sim.linear_amplitudes[name]):.4g}"
        text += f" {unit_text(value.text)}" if text and value.text not in ("", "1") else ""
        if name in sim.relative_difference:
            text += f" ({100 * sim.relative_difference[name]:+.3g}%)"
        kindof = "coordinate" if name in sim.coordinates else "output"
        unit = f" [{unit_text(value.text)}]" if value.text not in ("", "1") else ""
        panels.append(Chart(tuple(curves), f"time $t$ [{time.text}]",
                            f"{dollar_name(name)}{unit}", xlim,
                            spans=(Span(time(float(sim.window[0])), time(float(sim.window[1])),
                                        "#e6e6e6", "amplitude window"),),
                            title=f"{dollar_name(name)}: {kindof} deviation"
                                  + (f"; {text}" if text else "")))
    start = START_KINDS[sim.start]
    title = printable(sim.title or "simulation", limit=80)
    if len(drawn) < len(sim.names):  # said, never dropped without a word
        start += f"\n{len(drawn)} of {len(sim.names)} drawn: {MOST_MOTION}"
    return Charts(tuple(panels), f"{title} — {kind}, {start}",
                  size=(9.0, 1.2 + 2.1 * len(panels)), legend="below")


def _largest_motions(sim: Simulation, units: Mapping[str, str] | ResultUnits | None = None
                     ) -> list[str]:
    """The names a simulation's figure draws: all of them, or the :data:`MAX_CURVES` that
    move most (a rotor has dozens of coordinates), in their order.

    A metre is not compared with a radian: each name's largest |deviation| is taken
    relative to the largest of the names of its own SI unit (``units``; one kind where no
    units are known), so the largest displacement and the largest tilt both rank 1; ties
    keep the names' order.
    """
    if len(sim.names) <= MAX_CURVES:
        return list(sim.names)
    si = units.si if isinstance(units, ResultUnits) else (units or {})
    size = {n: float(np.nanmax(np.abs(np.asarray(sim.states[n], dtype=float)), initial=0.0))
            for n in sim.names}
    largest: dict[str, float] = {}
    for name, value in size.items():
        kind = si.get(name, "")
        largest[kind] = max(largest.get(kind, 0.0), value)
    share = [size[n] / largest[si.get(n, "")] if largest[si.get(n, "")] > 0 else 0.0
             for n in sim.names]
    keep = set(np.argsort(-np.asarray(share), kind="stable")[:MAX_CURVES].tolist())
    return [n for i, n in enumerate(sim.names) if i in keep]


#: the figure's note where it draws some of the names (the rule of :func:`_largest_motions`)
MOST_MOTION = "those that move most relative to the largest of their unit (m, rad, ...)"


def history_chart(t: npt.ArrayLike, values: Mapping[str, Any],
                  units: Mapping[str, str] | None = None,
                  ylabel: str = "stationary response $q_p(t)$") -> Chart:
    """What the figure of responses against time shows: every curve in one chart, the
    unit on the axis (or each curve's where they differ), a line at zero.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> c = history_chart(t, {"x1": t, "x2": -t}, {"x1": "m", "x2": "rad"})
    >>> c.ylabel, [k.label for k in c.curves]
    ('stationary response $q_p(t)$ [m, rad]', ['$x_{1}$ [m]', '$x_{2}$ [rad]'])
    """
    t = np.asarray(t, dtype=float)
    suffix, per_curve = unit_suffix(list(values), units or {})
    curves = tuple(Curve(t, np.asarray(y, dtype=float), name_label(name, per_curve))
                   for name, y in values.items())
    return Chart(curves, "time $t$ [s]", ylabel + suffix, (float(t[0]), float(t[-1])),
                 rules=(Rule(0.0, vertical=False, color="#999999", width=0.8),))


def plot_simulation(sim: Simulation, path: PathArg = None, axes: Sequence[Axes] | None = None,
                    units: Mapping[str, str] | ResultUnits | None = None) -> Figure:
    """Deviations vs time, one panel per coordinate/output, the linear prediction dashed:
    the chart of :func:`simulation_chart`, drawn with matplotlib.

    Parameters
    ----------
    sim : Simulation
        The simulation to draw.
    path : str or Path, optional
        Also write the figure there; the format follows the suffix (``.png``,
        ``.svg`` or ``.pdf``, anything else raises :class:`AnalysisError`).
    axes : matplotlib.axes.Axes or sequence of Axes, optional
        Draw into the caller's figure: one Axes per coordinate/output in the
        order of ``sim.names`` (fewer Axes draw the first names only; a single
        Axes shows the first).  By default a new figure with one panel per
        name is made.
    units : mapping, optional
        name -> SI unit (``ResultUnits.si``), shown in each panel's label.

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the one ``axes`` belong to.

    Raises
    ------
    AnalysisError
        For an unsupported file suffix.
    """
    check_plot_path(path)
    if axes is not None and not list(np.ravel(np.asarray(axes, dtype=object))):
        raise AnalysisError("axes= takes an Axes or a non-empty sequence of Axes")
    fig = draw_figure(simulation_chart(sim, units), axes)
    save_figure(fig, path)
    return fig


def simulation_text(sim: Simulation, units: ResultUnits | None = None) -> str:
    """A short plain-text report of a :class:`~resonant.analyses.simulate.Simulation`;
    amplitudes and times in the display units of ``units`` where given (``--units``)."""
    kind = "nonlinear" if sim.nonlinear else "linear"
    time = shown_unit(units, "s")
    lines = [printable(sim.title),
             f"{kind} simulation, t = 0 ... {time(sim.t_end):.6g} {time.text} ({sim.method}, "
             f"start: {sim.start})",
             f"steady amplitudes (peak |deviation| over t = {time(sim.window[0]):.6g} ... "
             f"{time(sim.window[1]):.6g} {time.text}):"]
    rows = []
    for name, value in sim.steady_amplitudes.items():
        linear = sim.linear_amplitudes.get(name)
        diff = sim.relative_difference.get(name)
        unit = units.unit(name) if units is not None else NO_UNIT
        rows.append((printable(name, limit=40), number_cell(unit(value), 6),
                     number_cell(None if linear is None else unit(linear), 6), unit.text,
                     "-" if diff is None else format(100 * diff, "+.3g") + "%"))
    lines.append(ResultTable(("name", "simulated", "linear", "unit", "difference"),
                             tuple(rows), align="lrrlr").text())
    return "\n".join(line for line in lines if line) + "\n"


__all__ = ["plot_simulation", "simulation_chart", "history_chart", "Simulation", "simulate",
           "parse_initial"]
