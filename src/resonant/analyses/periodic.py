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
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from ..arrays import freeze_fields
from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError
from ..model import Model
from ..system.base import LinearSystem
from ..system.build import nonlinear_system
from ..system.nonlinear import NonlinearSystem
from .hb_solver import (
    DEFAULT_HARMONICS,
    TRUNCATION_TOL,
    HarmonicBalance,
    raise_harmonics,
    start_coefficients,
    truncation,
    truncation_warning,
)
from .results_json import Saved
from .special_points import STABILITY_TOL
from .stationary import stationary


@dataclass(frozen=True)
class PeriodicSolution:
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
    """

    title: str
    coordinates: tuple[str, ...]
    harmonics: int
    coefficients: np.ndarray
    base_frequency: float
    initial: Mapping[str, float]
    amplitudes: Mapping[str, float]
    linear_amplitudes: Mapping[str, float]
    relative_difference: Mapping[str, float]
    multipliers: np.ndarray
    stable: bool
    residual: float
    truncation: float
    warnings: tuple[str, ...] = field(default=())

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

    def to_dict(self) -> dict[str, Any]:
        return {
            "title": self.title,
            "harmonics": self.harmonics,
            "base_frequency": self.base_frequency,
            "period": self.period,
            "initial": dict(self.initial),
            "amplitudes": dict(self.amplitudes),
            "linear_amplitudes": dict(self.linear_amplitudes),
            "relative_difference": dict(self.relative_difference),
            "stable": self.stable,
            "multipliers": [[float(m.real), float(m.imag)] for m in self.multipliers],
            "residual": self.residual,
            "truncation": self.truncation,
            "coefficients": {name: [[float(c[0])]] + [[float(c[2 * k - 1]), float(c[2 * k])]
                                                      for k in range(1, self.harmonics + 1)]
                             for name, c in zip(self.coordinates, self.coefficients)},
            "warnings": list(self.warnings),
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> PeriodicSolution:
        """The solution back from its :meth:`to_dict` (the coordinates are the keys of
        ``coefficients``, in order).

        Parameters
        ----------
        data : mapping
            What :meth:`to_dict` gave (read back from JSON).

        Returns
        -------
        PeriodicSolution

        Raises
        ------
        AnalysisError
            When a key is missing or holds the wrong kind of value (the message names it).

        Examples
        --------
        >>> import json, resonant
        >>> s = periodic_solution(resonant.load("examples/duffing.toml"), harmonics=3)
        >>> back = PeriodicSolution.from_dict(json.loads(json.dumps(s.to_dict())))
        >>> back.to_dict() == s.to_dict(), (back.multipliers == s.multipliers).all()
        (True, np.True_)
        """
        saved = Saved(data, "PeriodicSolution")
        H = saved.integer("harmonics", minimum=1)
        lists = saved.mapping("coefficients")
        coordinates = tuple(str(k) for k in lists.data)
        coefficients = np.empty((len(coordinates), 2 * H + 1))
        for j, name in enumerate(coordinates):
            pairs = lists.value(name)
            flat = [c for pair in pairs for c in pair] if isinstance(pairs, list) and \
                all(isinstance(pair, list) for pair in pairs) else pairs
            coefficients[j] = lists.array_of(flat, name, shape=(2 * H + 1,))
        pairs = saved.floats("multipliers", ndim=2)
        if pairs.size == 0:
            pairs = pairs.reshape(0, 2)
        if pairs.shape[1] != 2:
            raise saved.error("is not a list of [real, imaginary] pairs", "multipliers")
        multipliers = np.empty(len(pairs), dtype=complex)
        multipliers.real, multipliers.imag = pairs[:, 0], pairs[:, 1]
        return cls(title=saved.string("title"), coordinates=coordinates, harmonics=H,
                   coefficients=coefficients, base_frequency=saved.number("base_frequency"),
                   initial=saved.numbers_of("initial"),
                   amplitudes=saved.numbers_of("amplitudes"),
                   linear_amplitudes=saved.numbers_of("linear_amplitudes"),
                   relative_difference=saved.numbers_of("relative_difference"),
                   multipliers=multipliers, stable=saved.boolean("stable"),
                   residual=saved.number("residual"), truncation=saved.number("truncation"),
                   warnings=saved.strings("warnings", ()))

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


def periodic_solution(system: NonlinearSystem | LinearSystem | Model,
                      harmonics: int | None = None, *,
                      deadline: Deadline = NO_DEADLINE) -> PeriodicSolution:
    """The periodic solution of the full equations near the linear stationary solution.

    Parameters
    ----------
    system : NonlinearSystem
        The full equations (:func:`resonant.system.nonlinear_system`; a model or its
        linear system is turned into one), with a periodic excitation.
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
    system = nonlinear_system(system, deadline)
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
