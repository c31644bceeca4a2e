"""The periodic steady state a slow upward sweep of a parameter reaches.

Where the nonlinear frequency response has several periodic solutions (the
overhang of a hardening or softening resonance), the state observed at a
parameter value depends on the way there.  :func:`swept_state` answers for the
one a laboratory sees when the parameter (usually the excitation frequency)
is raised slowly from ``start`` to ``value``:

1. at ``start`` the periodic solution is the linear stationary solution refined
   by harmonic balance (Newton's method, exact Jacobian; see
   :mod:`resonant.analyses.hb_solver`);
2. the branch is followed by pseudo-arclength continuation
   (:mod:`resonant.analyses.continuation`) towards ``value``, each point's
   stability decided by Hill's method;
3. while the parameter increases and the points are stable, the slowly swept
   system stays on the branch; where the branch turns back (a fold) or loses
   stability, the system leaves it: the jump is computed by integrating the full
   equations in time at a parameter just beyond that point (1e-3 of the
   parameter beyond a fold, located to rounding; the first unstable branch point
   after a loss of stability), from the last state on the branch, in blocks of
   :data:`BLOCK_PERIODS` excitation periods, until two blocks' last periods agree
   to :data:`SETTLED_TOL`; that motion, refined by harmonic balance and stable,
   is where the sweep lands, and it is followed on from there (at most
   :data:`MAX_JUMPS` jumps);
4. at ``value`` the amplitudes are the peak |deviation from the reference state|
   over one period of every coordinate and output, as ``sweep --nonlinear``
   reports them.

A motion that does not settle to a periodic one of the excitation's period
within :data:`MAX_PERIODS` periods after a jump (a subharmonic, quasi-periodic or
chaotic motion, or a transient longer than that) raises :class:`NotPeriodic`;
harmonic balance that does not converge raises :class:`NotConverged`.

Examples
--------
>>> import resonant
>>> from resonant.system import nonlinear_system
>>> system = nonlinear_system(resonant.load("examples/duffing.toml"))
>>> state = swept_state(system, "omega", 0.5, 1.3, harmonics=3)
>>> round(state.amplitudes["x"], 4), state.jumps
(1.4258, ())
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError
from ..model.options import check_harmonics
from ..system.base import numeric_point
from ..system.nonlinear import NonlinearSystem, nonlinear_only
from ..system.nonlinear_at import nonlinear_at
from .continuation import Branch, follow, refine
from .hb_solver import (
    DEFAULT_HARMONICS,
    HarmonicBalance,
    basis,
    raise_harmonics,
    start_coefficients,
    truncation,
)
from .result_fields import FieldsJSON
from .results_json import Saved
from .special_points import STABILITY_TOL
from .stationary import stationary
from .time_integration import NonlinearDynamics, integrate

#: continuation steps across the way from one start to ``value``
SWEEP_POINTS = 41
#: the most jumps between branches on the way
MAX_JUMPS = 8
#: excitation periods integrated per block after a jump, and at most in all
BLOCK_PERIODS = 5
MAX_PERIODS = 3000
#: two blocks' last periods (their Fourier coefficients) agree to this: settled
SETTLED_TOL = 1e-2
#: ... and to this they are periodic (harmonic balance must then find the motion)
PERIODIC_TOL = 1e-8
#: beyond a fold the jump is computed this far (relative) past the fold
FOLD_MARGIN = 1e-3
#: the relative tolerance of the time integration of a jump (Newton refines its end)
JUMP_RTOL = 1e-6


class NotConverged(AnalysisError):
    """Harmonic balance did not converge on the way (at the start, along the branch, or
    on the motion a jump settled to)."""


class NotPeriodic(AnalysisError):
    """After a jump the motion did not settle to a periodic one of the excitation's
    period (a subharmonic, quasi-periodic or chaotic motion, or a long transient)."""


@dataclass(frozen=True)
class SweptState(FieldsJSON):
    """The periodic steady state reached by a slow sweep from ``start`` up to ``value``.

    Attributes
    ----------
    parameter : str
    start, value : float
        Where the sweep starts and the point reached.
    amplitudes : mapping
        coordinate or output -> peak |deviation from the reference state| over a period.
    coefficients : numpy.ndarray
        (n, 2H+1) per coordinate ``[a_0, a_1, b_1, ..., a_H, b_H]`` in tau = W t.
    harmonics : int
        H.
    jumps : tuple of (float, float)
        Where the sweep left a branch and the parameter at which it landed on another.
    residual : float
        max |R| of the harmonic balance at ``value``.
    truncation : float
        The relative amplitude of the highest harmonic pair at ``value``.

    Examples
    --------
    See :func:`swept_state`.
    """

    parameter: str
    start: float
    value: float
    amplitudes: Mapping[str, float]
    coefficients: np.ndarray
    harmonics: int
    jumps: tuple[tuple[float, float], ...]
    residual: float
    truncation: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "amplitudes", MappingProxyType(dict(self.amplitudes)))
        freeze_fields(self)

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], reader: Saved) -> None:
        if values["harmonics"] < 1:
            raise reader.error(f"is {values['harmonics']}, less than 1", "harmonics")
        rows = values["coefficients"]
        width = 2 * values["harmonics"] + 1
        if rows.ndim != 2 and rows.size:
            raise reader.error(f"has {rows.ndim} dimension(s), not 2", "coefficients")
        if rows.size and rows.shape[1] != width:
            raise reader.error(f"has rows of {rows.shape[-1]} numbers, not 2H + 1 = {width}",
                              "coefficients")


def stable_point(hb: HarmonicBalance, x: np.ndarray, p: float) -> bool:
    """Whether the periodic solution x at p is stable (Hill's method, every Floquet
    multiplier within 1 + STABILITY_TOL of the unit circle)."""
    _, J, blocks = hb.jacobian(x, p)
    exponents = hb.exponents(J, blocks)
    period = 2 * np.pi / float(blocks[3])
    with np.errstate(over="ignore"):
        return bool(np.all(np.abs(np.exp(exponents * period)) <= 1 + STABILITY_TOL))


def _start(system: NonlinearSystem, hb: HarmonicBalance, start: float,
           deadline: Deadline) -> np.ndarray:
    """The linear stationary solution at ``start`` (every parameter at the system's
    values), refined by Newton."""
    values = dict(zip(system.parameters, map(float, hb.pvals(start))))
    linear = system.linear
    solution = stationary(numeric_point(linear.evaluate(values, 1, deadline), 0, linear,
                                        values), deadline)
    X = start_coefficients(solution, hb.n, hb.H, system.base_frequency(hb.pvals(start)))
    x, ok = hb.newton(X.ravel(), start, max(float(np.abs(X).max()), 1e-300))
    if not ok:
        raise NotConverged(f"harmonic balance did not converge at {hb.param} = {start:.6g} "
                           "from the linear stationary solution")
    return x


def _leaves(hb: HarmonicBalance, branch: Branch, deadline: Deadline) -> int | None:
    """The first branch point where the parameter turns back or the point is unstable
    (None: the sweep stays on the branch to its end)."""
    for i, (x, p) in enumerate(zip(branch.x, branch.p)):
        deadline.check("while checking the stability of the branch", analysis=True)
        if branch.tp[i] < 0 or not stable_point(hb, x, p):
            return i
    return None


def _departure(hb: HarmonicBalance, branch: Branch, i: int, value: float, start: float
               ) -> tuple[np.ndarray, float, float]:
    """The state the sweep leaves the branch with, the parameter where it leaves (a fold
    located on the branch, or the last stable point) and the parameter of the jump."""
    if i == 0:
        return branch.x[0], branch.p[0], branch.p[0]
    j = i - 1
    if branch.tp[i] >= 0:  # lost stability: the first unstable point's parameter
        return branch.x[j], branch.p[j], min(branch.p[i], value)
    fold = refine(hb, branch, j, lambda x, p, t: float(t[-1]), branch.tp[j], branch.tp[i])
    x, p = fold if fold is not None else (branch.x[j], max(branch.p[j], branch.p[i]))
    margin = FOLD_MARGIN * (abs(p) if p != 0 else value - start)
    return x, p, min(p + margin, value)


def _last_period(hb: HarmonicBalance, result: Any, duration: float, W: float) -> np.ndarray:
    """The harmonic-balance coefficients of the last excitation period integrated."""
    t = duration - 2 * np.pi / W + hb.tau / W
    q = result.sol(t)[:hb.n]
    return hb.project(q - hb.reference[:, None])


def _jump(system: NonlinearSystem, hb: HarmonicBalance, x: np.ndarray, p: float,
          deadline: Deadline) -> np.ndarray:
    """Integrate the full equations at p from the state x (at tau = 0) until the motion
    settles to a periodic one; that motion by harmonic balance (stable)."""
    pvals = hb.pvals(p)
    at_p = nonlinear_at(system, dict(zip(system.parameters, map(float, pvals))))
    W = system.base_frequency(pvals)
    duration = BLOCK_PERIODS * 2 * np.pi / W
    phi, dphi, _ = basis(np.zeros(1), hb.H)
    X = x.reshape(hb.n, hb.m)
    y = np.concatenate([hb.reference + X @ phi[0], W * (X @ dphi[0])])
    scale = max(float(np.abs(X).max()), 1e-12)
    atol = np.concatenate([np.full(hb.n, 1e-10 * scale), np.full(hb.n, 1e-10 * scale * W)])
    dynamics, previous = NonlinearDynamics(at_p), None
    for _ in range(MAX_PERIODS // BLOCK_PERIODS):
        result, _ = integrate(dynamics, y, duration, "DOP853", JUMP_RTOL, atol, 1.0,
                              system.coordinates, True, [], deadline, False)
        y = result.y[:, -1]
        c = _last_period(hb, result, duration, W)
        size = max(float(np.linalg.norm(c)), 1e-300)
        change = np.inf if previous is None else float(np.linalg.norm(c - previous)) / size
        if change <= SETTLED_TOL:
            landed, ok = hb.newton(c, p, size)
            if ok and np.linalg.norm(landed - c) <= 0.1 * size and stable_point(hb, landed, p):
                return landed
            if change <= PERIODIC_TOL:
                raise NotConverged(
                    f"after the jump at {hb.param} = {p:.6g} the full equations settle to a "
                    f"periodic motion that harmonic balance with H = {hb.H} does not "
                    "resolve (a stable solution near it): raise the harmonics")
        previous = c
    raise NotPeriodic(f"after the jump at {hb.param} = {p:.6g} the motion did not settle to "
                      f"a periodic one of the excitation's period within {MAX_PERIODS} periods")


def _more_harmonics(hb: HarmonicBalance, x: np.ndarray, p: float
                    ) -> tuple[HarmonicBalance, np.ndarray]:
    """H raised until the highest harmonics of x carry less than TRUNCATION_TOL of its
    amplitude, the point converged again at each H (the shared rule,
    :func:`~resonant.analyses.hb_solver.raise_harmonics`)."""
    trials = {hb.H: hb}

    def converge(x_new: np.ndarray, H: int) -> tuple[np.ndarray, bool]:
        trials[H] = HarmonicBalance(hb.system, hb.param, H, reference=hb.reference)
        return trials[H].newton(x_new, p, float(np.linalg.norm(x)))

    H, x = raise_harmonics(x, hb.n, hb.H, converge)
    return trials[H], x


def _check(system: NonlinearSystem, param: str, start: float, value: float,
           harmonics: int | None) -> None:
    if param not in system.parameters:
        raise AnalysisError(f"'{param}' is not a parameter of the model")
    if not (math.isfinite(start) and math.isfinite(value)) or value < start:
        raise AnalysisError(f"a slow upward sweep needs start <= value, got {start:g} and "
                            f"{value:g}")
    check_harmonics(harmonics)


def _sweep(system: NonlinearSystem, hb: HarmonicBalance, start: float, value: float,
           deadline: Deadline) -> tuple[np.ndarray, list[tuple[float, float]]]:
    """The state at ``value`` and the jumps on the way (steps 1 to 3 of the module)."""
    x, p = _start(system, hb, start, deadline), start
    jumps: list[tuple[float, float]] = []
    while True:
        if p >= value:
            branch = Branch([x], [p], [1.0], [], [np.zeros(x.size + 1)], 1.0, 1.0)
        else:
            branch = follow(hb, x, p, value, SWEEP_POINTS, deadline)
        i = _leaves(hb, branch, deadline)
        if i is None:
            if branch.p[-1] != value:
                raise NotConverged(f"the continuation did not reach {hb.param} = {value:.6g}"
                                   + (f": {branch.warnings[0]}" if branch.warnings else ""))
            return branch.x[-1], jumps
        if len(jumps) >= MAX_JUMPS:
            raise NotPeriodic(f"more than {MAX_JUMPS} jumps between branches on the way to "
                              f"{hb.param} = {value:.6g}")
        x_leave, p_leave, p_jump = _departure(hb, branch, i, value, start)
        x, p = _jump(system, hb, x_leave, p_jump, deadline), p_jump
        jumps.append((float(p_leave), float(p_jump)))


def swept_state(system: NonlinearSystem, param: str, start: float, value: float, *,
                harmonics: int | None = None, deadline: Deadline = NO_DEADLINE
                ) -> SweptState:
    """The periodic steady state at ``param = value`` reached by a slow sweep up from
    ``start`` (see the module docstring).

    Parameters
    ----------
    system : NonlinearSystem
        The full equations, compiled (:func:`resonant.system.nonlinear_system`); for other
        parameter values than the model's, :func:`resonant.system.nonlinear_at`.
    param : str
        The swept parameter (usually the excitation frequency).
    start, value : float
        From where and up to where it is swept (``start <= value``).
    harmonics : int, optional
        H; default 7 along the way, raised at ``value`` until the highest harmonics
        carry less than 1e-6 of the amplitude (at most 40).
    deadline : Deadline, optional

    Returns
    -------
    SweptState

    Raises
    ------
    NotConverged
        Harmonic balance did not converge on the way.
    NotPeriodic
        A jump did not settle to a periodic motion of the excitation's period.
    AnalysisError
        For a non-periodic excitation, an unknown parameter, ``value < start``, a
        time integration that breaks down.

    Examples
    --------
    Beyond the jump-down frequency of the hardening Duffing oscillator the sweep has
    jumped to the lower branch:

    >>> import resonant
    >>> from resonant.system import nonlinear_system
    >>> system = nonlinear_system(resonant.load("examples/duffing.toml"))
    >>> state = swept_state(system, "omega", 0.5, 2.0, harmonics=3)
    >>> round(state.amplitudes["x"], 4), len(state.jumps)
    (0.0666, 1)
    """
    system = nonlinear_only(system, "the slow sweep")
    _check(system, param, start, value, harmonics)
    reference = system.reference(system.parameter_point(param, start))
    hb = HarmonicBalance(system, param, harmonics or DEFAULT_HARMONICS, reference=reference)
    x, jumps = _sweep(system, hb, float(start), float(value), deadline)
    if harmonics is None:
        hb, x = _more_harmonics(hb, x, value)
    R = hb.residual(x, value)
    amplitudes = hb.amplitudes(x, value)
    return SweptState(param, float(start), float(value),
                      dict(zip(hb.names(), map(float, amplitudes))),
                      x.reshape(hb.n, hb.m), hb.H, tuple(jumps), float(np.abs(R).max()),
                      float(truncation(x.reshape(1, hb.n, hb.m), hb.H)[0]))


__all__ = ["SweptState", "swept_state", "stable_point", "NotConverged", "NotPeriodic",
           "SWEEP_POINTS", "MAX_JUMPS", "BLOCK_PERIODS", "MAX_PERIODS", "SETTLED_TOL",
           "FOLD_MARGIN"]
