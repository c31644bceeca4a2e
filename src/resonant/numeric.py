"""The numeric equation of motion: parameter values substituted into M, C, K, Q.

Symbolic entries are compiled once with :func:`sympy.lambdify` (common
subexpressions shared) and evaluated for the parameter values, so a sweep over
a parameter costs one compiled call per point, never a symbolic substitution.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy

from .errors import AnalysisError, ModelError, Problem
from .jet import Var
from .model import Model, symbol

if TYPE_CHECKING:  # pragma: no cover
    from .linearize import LinearEOM
    from .stationary import StationarySolution


@dataclass(frozen=True)
class NumericHarmonic:
    """One excitation frequency: Q = F_S sin(omega t) + F_C cos(omega t).

    ``signals`` holds the (S, C) pair of every signal derivative at this
    frequency (needed for outputs that depend on signals). ``omega = 0`` is a
    static load (F_C only).
    """

    omega: float
    F_S: np.ndarray
    F_C: np.ndarray
    signals: Mapping[Var, tuple[float, float]] = field(default_factory=dict)


@dataclass(frozen=True)
class NumericOutput:
    """A linearized output y = value + sum coefficient * (coordinate or signal derivative)."""

    value: float
    terms: Mapping[Var, float]


@dataclass(frozen=True)
class NumericEOM:
    """M q'' + C q' + K q = Q(t) with numbers.

    Attributes
    ----------
    harmonics : tuple of NumericHarmonic
        The excitation, grouped by numeric frequency (ascending); None-free.
    harmonic : bool
        False when some signal is not a sum of harmonics (no stationary solution).
    """

    coordinates: tuple[str, ...]
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    harmonics: tuple[NumericHarmonic, ...] = ()
    harmonic: bool = True
    outputs: Mapping[str, NumericOutput] = field(default_factory=dict)
    parameters: Mapping[str, float] = field(default_factory=dict)
    title: str = ""
    source: str = ""
    symbolic: "LinearEOM | None" = None

    @property
    def n(self) -> int:
        return len(self.coordinates)

    def stationary(self) -> "StationarySolution":
        from .stationary import stationary

        return stationary(self)


def compile_expressions(expressions: Sequence[sympy.Expr], symbols: Sequence[sympy.Symbol]
                        ) -> Callable[..., np.ndarray]:
    """One compiled function returning all expressions as a float array."""
    if not expressions:
        return lambda *args: np.zeros(0)
    expressions = list(expressions)
    # zoo, nan, oo cannot be compiled (lambdify fails on them): they evaluate to NaN,
    # which the callers turn into an error naming the entry
    infinite = [i for i, e in enumerate(expressions)
                if isinstance(e, sympy.Basic) and e.has(sympy.zoo, sympy.nan, sympy.oo)]
    for i in infinite:
        expressions[i] = sympy.Integer(0)
    fn = sympy.lambdify(list(symbols), expressions, modules="numpy", cse=True)

    def call(*args: Any) -> np.ndarray:
        shape = np.broadcast(*args).shape if args else ()
        try:
            with np.errstate(all="ignore"):
                values = fn(*args)
        except ArithmeticError:  # Python floats raise on overflow and division by zero
            values = _one_by_one(expressions, symbols, args)
        out = np.array([np.broadcast_to(v, shape) for v in values], dtype=complex)
        if infinite:
            out[infinite] = np.nan
        return out
    return call


def _one_by_one(expressions: Sequence[sympy.Expr], symbols: Sequence[sympy.Symbol],
                args: Sequence[Any]) -> list[Any]:
    """Evaluate each expression alone, NaN where the arithmetic fails (the slow path)."""
    values: list[Any] = []
    for expression in expressions:
        try:
            with np.errstate(all="ignore"):
                values.append(sympy.lambdify(list(symbols), expression, modules="numpy")(*args))
        except ArithmeticError:
            values.append(np.nan)
    return values


@dataclass(frozen=True)
class ExpressionLayout:
    """Every symbolic quantity of a LinearEOM in one flat list, in reading order.

    M, C, K (row-major); per frequency: omega, F_S, F_C and the (S, C) pair of
    each signal variable in ``frequencies[i]``; per output: its value and the
    coefficients of the variables in ``outputs[j][1]``.  Compiled once, it is
    read back with :class:`FlatReader`.
    """

    expressions: tuple[sympy.Expr, ...]
    frequencies: tuple[tuple[Var, ...], ...]
    outputs: tuple[tuple[str, tuple[Var, ...]], ...]


def expression_layout(eom: "LinearEOM") -> ExpressionLayout:
    n = len(eom.coordinates)
    harmonics = eom.harmonics
    exprs: list[sympy.Expr] = [*eom.M, *eom.C, *eom.K]
    frequencies = []
    if harmonics is not None:
        variables = tuple(harmonics.parts)
        for w in harmonics.frequencies:
            f_s, f_c = harmonics.forcing(eom.excitation, w)
            if len(f_s) != n or len(f_c) != n:  # no excitation column at all: Q = 0
                f_s = f_c = [sympy.Integer(0)] * n
            exprs += [w, *f_s, *f_c]
            for var in variables:
                s, c = harmonics.parts[var].get(w, (0, 0))
                exprs += [sympy.sympify(s), sympy.sympify(c)]
            frequencies.append(variables)
    outputs = []
    for name, out in eom.outputs.items():
        exprs += [out.value, *out.terms.values()]
        outputs.append((name, tuple(out.terms)))
    return ExpressionLayout(tuple(exprs), tuple(frequencies), tuple(outputs))


class FlatReader:
    """Reads consecutive blocks (along the first axis) of compiled values."""

    def __init__(self, flat: np.ndarray) -> None:
        self.flat, self.pos = flat, 0

    def take(self, count: int) -> np.ndarray:
        out = self.flat[self.pos:self.pos + count]
        self.pos += count
        return out


def evaluate(eom: "LinearEOM", model: Model) -> NumericEOM:
    """Substitute the model's parameter values into a symbolic equation of motion."""
    names = list(model.parameters)
    values = [model.parameter_values[n] for n in names]
    symbols = [symbol(n) for n in names]
    n = len(eom.coordinates)
    layout = expression_layout(eom)
    flat = compile_expressions(layout.expressions, symbols)(*values)
    bad = ~np.isfinite(flat)
    if bad.any() or np.any(np.abs(flat.imag) > 1e-9 * (1 + np.abs(flat.real))):
        _raise_not_finite(eom, model, flat)
    take = FlatReader(flat.real).take
    M = take(n * n).reshape(n, n)
    C = take(n * n).reshape(n, n)
    K = take(n * n).reshape(n, n)
    merged: dict[float, list] = {}
    for variables in layout.frequencies:
        omega = float(take(1)[0])
        f_s, f_c = take(n), take(n)
        sig = take(2 * len(variables)).reshape(-1, 2)
        sign = 1.0
        if omega < 0:  # sin(-w t) = -sin(w t)
            omega, sign = -omega, -1.0
        if omega == 0:
            f_s, sig = np.zeros(n), np.column_stack([np.zeros(len(variables)), sig[:, 1]])
        key = next((k for k in merged if math.isclose(k, omega, rel_tol=1e-12, abs_tol=0.0)),
                   omega)
        entry = merged.setdefault(key, [np.zeros(n), np.zeros(n), {}])
        entry[0] = entry[0] + sign * f_s
        entry[1] = entry[1] + f_c
        for var, (s, c) in zip(variables, sig):
            old = entry[2].get(var, (0.0, 0.0))
            entry[2][var] = (old[0] + sign * s, old[1] + c)
    outputs = {}
    for name, variables in layout.outputs:
        value = float(take(1)[0])
        coefs = take(len(variables))
        outputs[name] = NumericOutput(value, MappingProxyType(dict(zip(variables, coefs))))
    return NumericEOM(
        coordinates=eom.coordinates, M=M, C=C, K=K,
        harmonics=tuple(NumericHarmonic(w, fs, fc, MappingProxyType(sig))
                        for w, (fs, fc, sig) in sorted(merged.items())),
        harmonic=eom.harmonics is not None, outputs=MappingProxyType(outputs),
        parameters=MappingProxyType(dict(model.parameter_values)),
        title=model.title, source=model.source, symbolic=eom)


def _raise_not_finite(eom: "LinearEOM", model: Model, flat: np.ndarray) -> None:
    n = len(eom.coordinates)
    for label, matrix, offset in (("M", eom.M, 0), ("C", eom.C, n * n), ("K", eom.K, 2 * n * n)):
        for idx in range(n * n):
            v = flat[offset + idx]
            if not np.isfinite(v):
                i, j = divmod(idx, n)
                entry = str(matrix[i, j])
                entry = entry if len(entry) <= 80 else entry[:77] + "..."
                raise ModelError(Problem(
                    f"{label}[{i + 1},{j + 1}] = {entry} is not finite for the given "
                    "parameter values (a zero mass or length?)", model.source, "parameters"))
    raise ModelError(Problem("the excitation or an output is not finite (or not real) for the "
                             "given parameter values", model.source, "parameters"))


def check_finite(name: str, array: np.ndarray) -> np.ndarray:
    """Guard: NaN or infinity never reaches the output silently."""
    if not np.all(np.isfinite(array)):
        raise AnalysisError(f"{name} is not finite: the computation overflowed or divided "
                            "by zero; check the parameter values")
    return array


__all__ = ["NumericEOM", "NumericHarmonic", "NumericOutput", "evaluate", "compile_expressions",
           "check_finite"]
