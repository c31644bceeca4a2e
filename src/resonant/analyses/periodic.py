"""The periodic steady state of the full equations at fixed parameters (one Newton solve).

:func:`periodic_solution` solves the harmonic balance of
:mod:`resonant.analyses.harmonic_balance` at the model's parameter values, from
the linear stationary solution, with Newton's method and the exact Jacobian:
no continuation.  H is raised from 7 until the highest harmonics carry less
than 1e-6 of the amplitude (at most 40) unless given.  The result carries the
Fourier coefficients, the initial state q(0), q'(0) (so that a simulation can
start on the periodic orbit), the peak amplitudes, the linear stationary
amplitudes and their relative difference, and the Floquet multipliers (Hill's
method).

It is what ``simulate(..., nonlinear=True)`` starts on for an undamped or
lightly damped model (start ``"periodic"``): a run from rest, or from the
linear stationary state, would beat forever around the periodic orbit, so its
peak over a window is not a steady state.

Examples
--------
>>> from resonant.api import loads
>>> model = loads('''
... [parameters]
... omega = 3
... [coordinates]
... x = ""
... [signals]
... F = "2*cos(omega*t)"
... [energy]
... T = "x'^2/2"
... U = "x^2/2 + x^4/4"
... [[force]]
... generalized = { x = "F" }
... ''')
>>> from resonant.system import nonlinear_system
>>> p = periodic_solution(nonlinear_system(model), harmonics=5)
>>> p.residual < 1e-12, round(p.amplitudes["x"], 6), round(p.linear_amplitudes["x"], 6)
(True, 0.251541, 0.25)
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
from ..system.nonlinear import NonlinearSystem, nonlinear_only
from .hb_solver import (
    DEFAULT_HARMONICS,
    TRUNCATION_TOL,
    HarmonicBalance,
    raise_harmonics,
    start_coefficients,
    truncation,
    truncation_warning,
)
from .result_fields import COMPLEX_PAIRS, HARMONIC_LISTS, FieldsJSON, saved
from .results_json import Saved
from .special_points import STABILITY_TOL
from .stationary import stationary


@dataclass(frozen=True)
class PeriodicSolution(FieldsJSON):
    """One periodic solution of the full equations (harmonic balance at fixed parameters).

    Attributes
    ----------
    coefficients : numpy.ndarray
        (n, 2H+1): per coordinate ``[a_0, a_1, b_1, ..., a_H, b_H]`` of the deviation
        from the reference state, in the time ``tau = W t``.
    base_frequency : float
        W (rad/s); the period is ``2 pi / W``.
    initial : mapping
        ``{x: q(0), x': q'(0)}``: deviations and velocities at t = 0.
    amplitudes : mapping
        Peak |deviation| over one period of every coordinate and output.
    linear_amplitudes, relative_difference : mapping
        The linear stationary amplitudes and ``amplitude / linear - 1``.
    multipliers : numpy.ndarray
        The 2n Floquet multipliers (Hill's method); ``stable`` when all |mu| <= 1 + 1e-6.
    residual : float
        max |R| of the harmonic balance; ``truncation`` the relative amplitude of the
        highest harmonic pair.

    Examples
    --------
    Saved by its fields (:class:`~resonant.analyses.result_fields.FieldsJSON`), each
    coordinate's coefficients as ``[[a_0], [a_1, b_1], ...]``, and read back:

    >>> import json, resonant
    >>> from resonant.system import nonlinear_system
    >>> s = periodic_solution(nonlinear_system(resonant.load("examples/duffing.toml")),
    ...                       harmonics=3)
    >>> s.to_dict()["coefficients"]["x"][0] == [s.coefficients[0, 0]]
    True
    >>> back = PeriodicSolution.from_dict(json.loads(json.dumps(s.to_dict())))
    >>> back.to_dict() == s.to_dict(), (back.multipliers == s.multipliers).all()
    (True, np.True_)
    """

    #: the keys of to_dict() (resonant.analyses.result_fields.FieldsJSON); the coordinates
    #: are the keys of ``coefficients``, in order
    _json_order = ("title", "harmonics", "base_frequency", "period", "initial", "amplitudes",
                   "linear_amplitudes", "relative_difference", "stable", "multipliers",
                   "residual", "truncation", "coefficients", "warnings")

    title: str
    coordinates: tuple[str, ...] = saved(keys_of="coefficients")
    harmonics: int = saved()
    coefficients: np.ndarray = saved(rows_by="coordinates", codec=HARMONIC_LISTS)
    base_frequency: float = saved()
    initial: Mapping[str, float] = saved()
    amplitudes: Mapping[str, float] = saved()
    linear_amplitudes: Mapping[str, float] = saved()
    relative_difference: Mapping[str, float] = saved()
    multipliers: np.ndarray = saved(codec=COMPLEX_PAIRS)
    stable: bool = saved()
    residual: float = saved()
    truncation: float = saved()
    warnings: tuple[str, ...] = saved(default=())

    def __post_init__(self) -> None:
        freeze_fields(self)

    @property
    def period(self) -> float:
        return 2 * math.pi / self.base_frequency

    def response(self, t: np.ndarray) -> dict[str, np.ndarray]:
        """The deviations q(t) of the periodic solution at times t."""
        tau = self.base_frequency * np.asarray(t, dtype=float)
        k = np.arange(1, self.harmonics + 1)
        c, s = np.cos(np.multiply.outer(tau, k)), np.sin(np.multiply.outer(tau, k))
        return {name: self.coefficients[j, 0] + c @ self.coefficients[j, 1::2]
                + s @ self.coefficients[j, 2::2] for j, name in enumerate(self.coordinates)}

    def _derived_json(self) -> dict[str, Any]:
        return {"period": self.period}

    @classmethod
    def _check_saved(cls, values: Mapping[str, Any], saved_data: Saved) -> None:
        width = 2 * values["harmonics"] + 1
        if values["harmonics"] < 1 or np.shape(values["coefficients"])[1:] != (width,):
            raise saved_data.error(f"does not hold {width} coefficients of each coordinate "
                                   f"([[a_0], [a_1, b_1], ...] up to H = harmonics)",
                                   "coefficients")

    def summary(self) -> str:
        lines = [f"{self.title or 'model'}: periodic solution of the full equations "
                 f"(harmonic balance, H = {self.harmonics}, period {self.period:.6g} s, "
                 f"{'stable' if self.stable else 'unstable'})"]
        for name in self.amplitudes:
            lin = self.linear_amplitudes.get(name)
            diff = self.relative_difference.get(name)
            lines.append(f"  {name}: amplitude {self.amplitudes[name]:.6g}"
                         + (f", linear {lin:.6g}" if lin is not None else "")
                         + (f" ({100 * diff:+.3g}%)" if diff is not None else ""))
        return "\n".join(lines) + "\n"


def _solve(system: NonlinearSystem, harmonics: int | None, deadline: Deadline
           ) -> tuple[HarmonicBalance, np.ndarray, Any]:
    """(harmonic balance, coefficients, linear stationary solution) at the model's values,
    with H raised until the truncation is small (H not given)."""
    param = system.parameters[0]
    p = float(system.parameter_values[0])
    solution = stationary(system.linear.numeric(deadline), deadline)
    H = harmonics or DEFAULT_HARMONICS
    hb = HarmonicBalance(system, param, H)
    X = start_coefficients(solution, hb.n, H, system.base_frequency(hb.pvals(p)))
    scale = max(float(np.abs(X).max()), 1e-300)
    deadline.check("before the harmonic balance", analysis=True)
    x, ok = hb.newton(X.ravel(), p, scale)
    if not ok:
        raise AnalysisError("harmonic balance did not converge from the linear stationary "
                            "solution: no periodic solution of the full equations near it "
                            "(the response is far from linear)")
    if harmonics is None:
        trials = {H: hb}

        def converge(x_new: np.ndarray, H_new: int) -> tuple[np.ndarray, bool]:
            trials[H_new] = HarmonicBalance(system, param, H_new)
            return trials[H_new].newton(x_new, p, scale)

        H, x = raise_harmonics(x, hb.n, H, converge, check=lambda: deadline.check(
            "while raising the number of harmonics", analysis=True))
        hb = trials[H]
    return hb, x, solution


def periodic_solution(system: NonlinearSystem,
                      harmonics: int | None = None, *,
                      deadline: Deadline = NO_DEADLINE) -> PeriodicSolution:
    """The periodic solution of the full equations near the linear stationary solution.

    Parameters
    ----------
    system : NonlinearSystem
        The full equations, compiled (:func:`resonant.system.nonlinear_system`), with a
        periodic excitation.
    harmonics : int, optional
        H; default: 7, raised by 4 until the highest harmonics carry less than 1e-6 (at
        most 40).
    deadline : Deadline, optional

    Returns
    -------
    PeriodicSolution

    Raises
    ------
    AnalysisError
        When Newton's method does not converge from the linear stationary solution (the
        response is too far from linear, or there is no periodic solution nearby), for a
        ``[matrices]`` model or a non-periodic excitation.
    """
    system = nonlinear_only(system, "the periodic solution")
    if harmonics is not None and not 1 <= harmonics <= 200:
        raise AnalysisError(f"harmonics must be between 1 and 200, not {harmonics}")
    if not system.parameters:
        raise AnalysisError("the model has no parameters, so no excitation frequency")
    hb, x, solution = _solve(system, harmonics, deadline)
    p = float(system.parameter_values[0])
    R, J, blocks = hb.jacobian(x, p)
    W = float(blocks[3])
    mult = np.exp(hb.exponents(J, blocks) * 2 * np.pi / W)
    coeffs = x.reshape(hb.n, hb.m)
    amps = hb.amplitudes(x, p)
    q0 = coeffs[:, 0] + coeffs[:, 1::2].sum(axis=1)
    v0 = W * (coeffs[:, 2::2] @ np.arange(1, hb.H + 1))
    names = system.coordinates
    amplitudes = {c: float(amps[j]) for j, c in enumerate(hb.names())}
    linear = {c: float(solution.amplitudes[c]) for c in amplitudes if c in solution.amplitudes}
    relative = {c: amplitudes[c] / a - 1 for c, a in linear.items() if a > 0}
    trunc = float(truncation(coeffs[None], hb.H)[0])
    warnings = []
    if trunc > TRUNCATION_TOL:
        warnings.append(truncation_warning(trunc, hb.H, harmonics is not None))
    return PeriodicSolution(
        title=system.title, coordinates=names, harmonics=hb.H, coefficients=coeffs,
        base_frequency=W,
        initial=MappingProxyType({**{c: float(q0[j]) for j, c in enumerate(names)},
                                  **{c + "'": float(v0[j]) for j, c in enumerate(names)}}),
        amplitudes=MappingProxyType(amplitudes), linear_amplitudes=MappingProxyType(linear),
        relative_difference=MappingProxyType(relative), multipliers=mult,
        stable=bool(np.all(np.abs(mult) <= 1 + STABILITY_TOL)),
        residual=float(np.abs(R).max()), truncation=trunc, warnings=tuple(warnings))


__all__ = ["PeriodicSolution", "periodic_solution"]
