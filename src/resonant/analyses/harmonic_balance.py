"""The nonlinear periodic steady state: harmonic balance, arc-length continuation, stability.

The full equations of motion ``E(q, q', q'', t) = 0`` of a
:class:`~resonant.system.NonlinearSystem` (the equations ``simulate
--nonlinear`` integrates, compiled once by the system) are solved for periodic
motions of the excitation's
base frequency W (the largest common divisor of the signals' frequencies), in
the time tau = W t::

    q(tau) = q_ref + a_0 + sum_{k=1..H} a_k cos(k tau) + b_k sin(k tau)

**Residual** by the alternating frequency-time method and **Jacobian** exact
(:mod:`resonant.analyses.hb_solver`).

**Continuation** (:mod:`resonant.analyses.continuation`) by pseudo-arclength in
(x / s_x, p / s_p) with a predictor along the tangent, Newton correctors with the
analytical Jacobian and step control from the Newton iteration count, the relative
change of the amplitude and of the parameter per step.  Folds are passed; they are
located where the parameter component of the tangent changes sign.

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

**Amplitudes** are the peak |deviation from the reference state| over one period
of every coordinate and every output (``[outputs]``, evaluated in full on the
periodic solution), located to rounding (:func:`resonant.analyses.peaks.periodic_peak`).
**Peaks**: where the amplitude of a coordinate or output is largest along the
branch, d(amplitude)/d(arc) = 0 is located like the folds and reported as a
special point of kind ``peak`` (:mod:`resonant.analyses.special_points`).

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
>>> from resonant.system import nonlinear_system
>>> r = nonlinear_sweep(nonlinear_system(model), "omega", 0.5, 1.5, harmonics=3, points=40)
>>> [(p.kind, p.quantity, round(p.value, 4)) for p in r.special_points], bool(r.stable.all())
([('peak', 'x', 0.9994)], True)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from types import MappingProxyType

import numpy as np

from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError
from ..model.options import MAX_GIVEN_HARMONICS, BalanceOptions, chosen, names_tuple
from ..system.nonlinear import NonlinearSystem, nonlinear_only
from .condensed import condensed_sweep
from .continuation import Branch
from .continuation import follow as _continue
from .hb_solver import (
    DEFAULT_HARMONICS,
    MAX_HARMONICS,
    TRUNCATION_TOL,
    HarmonicBalance,
    raise_harmonics,
    resize,
    start_coefficients,
    truncation,
    truncation_warning,
)
from .nonlinear_response import NonlinearResponse
from .reduced import DEFAULT_TOL
from .special_points import SPECIAL_KINDS, STABILITY_TOL, SpecialPoint, special_points
from .stationary import stationary
from .sweep import FrequencyResponse, sweep

#: a branch point whose residual exceeds this many times the branch's median is polished
POLISH_FACTOR = 100.0


def _check(system: NonlinearSystem, param: str, start: float, stop: float,
           harmonics: int | None, points: int) -> None:
    if param not in system.parameters:
        raise AnalysisError(f"'{param}' is not a parameter of the model (parameters: "
                            f"{', '.join(system.parameters)})")
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise AnalysisError("the range must be two different finite numbers")
    BalanceOptions(harmonics=harmonics, points=points)  # checks both


def _start(system: NonlinearSystem, hb: HarmonicBalance, start: float,
           deadline: Deadline) -> np.ndarray:
    """The branch's first point: the linear stationary solution at ``start``, refined."""
    num = system.linear.numeric(deadline, **{hb.param: repr(float(start))})
    solution = stationary(num, deadline)
    X = start_coefficients(solution, hb.n, hb.H, system.base_frequency(hb.pvals(start)))
    x0, ok = hb.newton(X.ravel(), start, max(float(np.abs(X).max()), 1e-300))
    if not ok:
        raise AnalysisError(f"harmonic balance did not converge at {hb.param} = {start:g} "
                            "from the linear stationary solution; start the range where the "
                            "response is small")
    return x0


def _more_harmonics(hb: HarmonicBalance, branch: Branch) -> int:
    """H at which the branch point with the largest truncation error carries less than
    TRUNCATION_TOL in its highest harmonics (at most MAX_HARMONICS; the shared rule,
    :func:`~resonant.analyses.hb_solver.raise_harmonics`)."""
    ratios = truncation(np.array(branch.x).reshape(len(branch.x), hb.n, hb.m), hb.H)
    worst = int(np.argmax(ratios))

    def converge(x: np.ndarray, H: int) -> tuple[np.ndarray, bool]:
        trial = HarmonicBalance(hb.system, hb.param, H, reference=hb.reference)
        return trial.newton(x, branch.p[worst], float(np.linalg.norm(x)))

    return raise_harmonics(branch.x[worst], hb.n, hb.H, converge)[0]


def _branch(system: NonlinearSystem, param: str, start: float, stop: float,
            harmonics: int | None, points: int, deadline: Deadline
            ) -> tuple[HarmonicBalance, Branch]:
    """The continued branch, with H raised until the truncation is small (H not given)."""
    reference = system.reference(system.parameter_point(param, start))
    hb = HarmonicBalance(system, param, harmonics or DEFAULT_HARMONICS, reference=reference)
    x0 = _start(system, hb, start, deadline)
    branch = _continue(hb, x0, start, stop, points, deadline, relative=True)
    if harmonics is None:
        H = _more_harmonics(hb, branch)
        if H != hb.H:
            hb_new = HarmonicBalance(system, param, H, reference=reference)
            x0, _ = hb_new.newton(resize(x0, hb.n, hb.H, H), start, float(np.linalg.norm(x0)))
            hb, branch = hb_new, _continue(hb_new, x0, start, stop, points, deadline,
                                           relative=True)
    return hb, branch


def _polish(hb: HarmonicBalance, branch: Branch, residuals: np.ndarray) -> list[int]:
    """Newton at fixed parameter for every point whose residual stands out (in place);
    the indices of the points changed."""
    typical = float(np.median(residuals)) if residuals.size else 0.0
    changed = []
    for i in np.flatnonzero(residuals > POLISH_FACTOR * max(typical, 1e-300)):
        x, ok = hb.newton(branch.x[i], branch.p[i], float(np.linalg.norm(branch.x[i])))
        if ok:
            branch.x[i] = x
            changed.append(int(i))
    return changed


def _points(hb: HarmonicBalance, branch: Branch, deadline: Deadline
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Floquet exponents (points, 2n), base frequencies, amplitudes (points, quantities) and
    the largest residual of the branch points (a point whose residual stands out is
    polished first)."""
    exps, Ws, residuals = [], [], []

    def evaluate(x: np.ndarray, p: float) -> tuple[float, np.ndarray, float]:
        deadline.check("during the stability analysis", analysis=True)
        R, J, blocks = hb.jacobian(x, p)
        return float(np.abs(R).max()), hb.exponents(J, blocks), float(blocks[3])

    for x, p in zip(branch.x, branch.p):
        r, lam, W = evaluate(x, p)
        residuals.append(r)
        exps.append(lam)
        Ws.append(W)
    for i in _polish(hb, branch, np.array(residuals)):
        residuals[i], exps[i], Ws[i] = evaluate(branch.x[i], branch.p[i])
    return (np.array(exps), np.array(Ws), hb.amplitudes_of(branch.x, branch.p),
            max(residuals, default=0.0))


def _linear_sweep(system: NonlinearSystem, param: str, start: float, stop: float,
                  points: int, warnings: list[str], deadline: Deadline
                  ) -> FrequencyResponse | None:
    try:
        grid = np.linspace(min(start, stop), max(start, stop), max(points, 201))
        return sweep(system.linear, param, grid, deadline=deadline)
    except AnalysisError as exc:
        warnings.append(f"no linear sweep to compare with: {exc}")
        return None


def balance_for(system: NonlinearSystem) -> str:
    """The balance that takes ``system``: ``"condensed"`` for a ``[matrices]`` model with
    ``[[nonlinear]]`` elements, ``"full"`` for a model given by its energies (the one
    place that chooses; docs/nonlinear.md, "Which balance").

    The condensed balance is chosen whatever the size: measured against the full
    balance of the same matrix models (1 to 200 coordinates, one cubic element, H = 3
    to 30), it costs as much or less per branch point (its Newton has m (2H+1)
    unknowns, not n (2H+1); its Hill matrix has at most the full one's 2n (2H+1) rows,
    a monodromy matrix beyond 200); the full balance is at best even (1 coordinate,
    H = 30: 1.2 s each).

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import nonlinear_system
    >>> balance_for(nonlinear_system(resonant.load("examples/duffing.toml")))
    'full'
    """
    return "full" if system.local_elements is None else "condensed"


def nonlinear_sweep(system: NonlinearSystem, param: str, start: float,
                    stop: float, *, harmonics: int | None = None, points: int = 101,
                    linear: bool = True, observe: Sequence[str] | None = None,
                    samples: int | None = None, exact: bool | None = None,
                    tol: float | None = None, deadline: Deadline = NO_DEADLINE,
                    options: BalanceOptions | None = None) -> NonlinearResponse:
    """The periodic steady state from ``start`` to ``stop``: harmonic balance, continuation,
    stability, balanced the way the system calls for.

    A model given by its energies is balanced in full (:func:`full_sweep`); a
    ``[matrices]`` model with ``[[nonlinear]]`` elements condensed onto the elements'
    coordinates (:func:`resonant.analyses.condensed.condensed_sweep`), as
    :func:`balance_for` chooses.  Callers make no choice.

    Parameters
    ----------
    system : NonlinearSystem
        The full equations, compiled (:func:`resonant.system.nonlinear_system`;
        ``model.nonlinear_sweep(...)`` compiles them for you).
    param : str
        Any parameter; when it sets an excitation frequency the base frequency follows.
    start, stop : float
        The range.
    harmonics : int, optional
        H; default: chosen from the truncation of the highest harmonics.
    points : int
        About this many steps across the range.
    linear : bool
        Also compute the linear sweep over the range.
    observe, samples, exact, tol : optional
        The condensed balance's options (:func:`resonant.analyses.condensed.condensed_sweep`);
        an error for a model given by its energies.
    deadline : Deadline, optional
    options : BalanceOptions, optional
        ``harmonics`` ... ``tol`` as one record (then not as keywords):
        :class:`resonant.model.options.BalanceOptions`.

    Returns
    -------
    NonlinearResponse

    Raises
    ------
    AnalysisError
        As the balance chosen raises; for a condensed option given to a model given by
        its energies.

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import nonlinear_system
    >>> duffing = nonlinear_system(resonant.load("examples/duffing.toml"))
    >>> r = nonlinear_sweep(duffing, "omega", 0.8, 1.2, harmonics=1, points=20)
    >>> r.harmonics, bool(r.values.size > 10)
    (1, True)
    """
    o = chosen(options, BalanceOptions(harmonics, points, linear, names_tuple(observe),
                                       samples, exact, tol))
    full = nonlinear_only(system, "the nonlinear sweep")
    if balance_for(full) == "condensed":
        return condensed_sweep(full, param, start, stop, harmonics=o.harmonics,
                               points=o.points, observe=o.observe, samples=o.samples,
                               exact=o.exact, tol=DEFAULT_TOL if o.tol is None else o.tol,
                               linear=o.linear, deadline=deadline)
    given = [name for name, value in (("observe", o.observe), ("samples", o.samples),
                                      ("exact", o.exact), ("tol", o.tol)) if value is not None]
    if given:
        raise AnalysisError(f"{', '.join(given)} apply to the balance condensed onto the "
                            "[[nonlinear]] elements of a [matrices] model, not to a model "
                            "given by its energies")
    return full_sweep(full, param, start, stop, harmonics=o.harmonics, points=o.points,
                      linear=o.linear, deadline=deadline)


def full_sweep(system: NonlinearSystem, param: str, start: float,
               stop: float, *, harmonics: int | None = None, points: int = 101,
               linear: bool = True, deadline: Deadline = NO_DEADLINE) -> NonlinearResponse:
    """Follow the periodic steady state of the full equations from ``start`` to ``stop``.

    Parameters
    ----------
    system : NonlinearSystem
        The full equations, compiled (:func:`resonant.system.nonlinear_system`).
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
    deadline : Deadline, optional

    Returns
    -------
    NonlinearResponse

    Raises
    ------
    AnalysisError
        For a ``[matrices]`` model, a non-periodic excitation, an unknown parameter,
        or when Newton does not converge at the start.
    """
    system = nonlinear_only(system, "the full harmonic balance")
    _check(system, param, start, stop, harmonics, points)
    hb, branch = _branch(system, param, start, stop, harmonics, points, deadline)
    lam, Ws, amps, residual = _points(hb, branch, deadline)
    values = np.array(branch.p)
    coeffs = np.array(branch.x).reshape(values.size, hb.n, hb.m)
    mult = np.exp(lam * (2 * np.pi / Ws)[:, None])
    stable = np.all(np.abs(mult) <= 1 + STABILITY_TOL, axis=1)
    special = special_points(hb, branch, lam, Ws, amps, deadline)
    warnings = list(branch.warnings)
    shares = truncation(coeffs, hb.H) if values.size else np.zeros(1)
    trunc, worst = float(shares.max()), int(np.argmax(shares))
    if hb.H > 1 and trunc > TRUNCATION_TOL:
        warnings.append(truncation_warning(
            trunc, hb.H, harmonics is not None, f"{param} = {values[worst]:.6g}",
            "" if hb.H >= MAX_HARMONICS else "the automatic choice stopped there"))
    linear_response = _linear_sweep(system, param, start, stop, points, warnings,
                                    deadline) if linear else None
    return NonlinearResponse(
        title=system.title, parameter=param, coordinates=system.coordinates,
        values=values, amplitudes=MappingProxyType(
            {name: amps[:, j] for j, name in enumerate(hb.names())}),
        coefficients=coeffs, base_frequencies=Ws, stable=stable, multipliers=mult,
        special_points=special, harmonics=hb.H, residual=residual, truncation=trunc,
        start=float(start), stop=float(stop), linear=linear_response,
        warnings=tuple(warnings), outputs=system.outputs,
        output_coefficients=hb.output_coefficients(branch.x, branch.p)
        if system.outputs else None)


__all__ = ["NonlinearResponse", "SpecialPoint", "balance_for", "full_sweep", "nonlinear_sweep",
           "SPECIAL_KINDS", "DEFAULT_HARMONICS", "MAX_HARMONICS", "MAX_GIVEN_HARMONICS",
           "TRUNCATION_TOL", "STABILITY_TOL"]
