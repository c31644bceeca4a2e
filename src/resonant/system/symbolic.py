"""The linear system of a model given by its energies: entries in the model's own symbols.

Examples
--------
>>> from resonant.model import loads
>>> eom = loads('''
... [parameters]
... m = 1
... k = 4
... c = 0.1
... [coordinates]
... x = "displacement"
... [signals]
... y = "sin(2*t)"
... [energy]
... T = "m*x'^2/2"
... U = "k*(x - y)^2/2"
... D = "c*x'^2/2"
... ''').linearize()
>>> eom.M, eom.C, eom.K
(Matrix([[m]]), Matrix([[c]]), Matrix([[k]]))
>>> eom.Q
Matrix([[k*sin(2*t)]])
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import sympy

from ..deadline import NO_DEADLINE, Deadline
from ..derivation import Linearization, LinearMap, SignalHarmonics, decompose_signals
from ..derivation.lagrange import signal_derivatives, signal_symbol
from ..errors import ModelError, Problem
from ..model import Model, symbol
from .base import LinearSystem
from .batch import (
    Batch,
    BatchHarmonic,
    FlatReader,
    compile_expressions,
    not_finite_problem,
)

Var = tuple[str, int]


@dataclass(frozen=True, eq=False)
class LinearEOM(LinearSystem):
    """The symbolic linearized equation of motion of a model given by its energies.

    Attributes
    ----------
    M, C, K : sympy.ImmutableMatrix
        Mass, damping and stiffness matrices in the model's own symbols.
    excitation : mapping
        ``(signal, order) -> column`` such that
        Q(t) = sum of column * d^order signal / dt^order.
    residual : sympy.ImmutableMatrix
        The generalized forces left at the reference state with all signals
        zero (zero at an equilibrium).
    outputs : mapping
        Each output as a :class:`~resonant.derivation.LinearMap`.
    """

    model: Model
    coordinates: tuple[str, ...]
    M: sympy.ImmutableMatrix
    C: sympy.ImmutableMatrix
    K: sympy.ImmutableMatrix
    excitation: Mapping[Var, sympy.ImmutableMatrix]
    residual: sympy.ImmutableMatrix
    outputs: Mapping[str, LinearMap] = field(default_factory=dict)

    @classmethod
    def from_linearization(cls, lin: Linearization) -> LinearEOM:
        """The system of a derivation's result."""
        return cls(lin.model, lin.coordinates, lin.M, lin.C, lin.K, lin.excitation,
                   lin.residual, lin.outputs)

    @cached_property
    def signal_functions(self) -> dict[Var, sympy.Expr]:
        """d^order s/dt^order as functions of t for every signal derivative in Q or outputs."""
        needed = set(self.excitation)
        for out in self.outputs.values():
            needed |= {v for v in out.terms if v[0] in self.model.signals}
        return signal_derivatives(self.model, needed)

    @cached_property
    def Q(self) -> sympy.ImmutableMatrix:
        """Q(t) with the signals written out as functions of time (Eq. (32))."""
        q = sympy.zeros(self.n, 1)
        for var, column in self.excitation.items():
            q += column * self.signal_functions[var]
        return sympy.ImmutableMatrix(q)

    @cached_property
    def Q_signals(self) -> sympy.ImmutableMatrix:
        """Q(t) written with the signal names (r, r', ...) as symbols."""
        q = sympy.zeros(self.n, 1)
        for (name, order), column in self.excitation.items():
            q += column * signal_symbol(name, order)
        return sympy.ImmutableMatrix(q)

    @cached_property
    def harmonics(self) -> SignalHarmonics | None:
        """The harmonic decomposition of the signals, or None if some are not harmonic."""
        return decompose_signals(self.signal_functions)

    @cached_property
    def _layout(self) -> _Layout:
        return _Layout.of(self)

    def evaluate(self, values: Mapping[str, Any], count: int,
                 deadline: Deadline = NO_DEADLINE) -> Batch:
        # the symbolic work of the first evaluation (harmonic split, compilation) is part
        # of the derivation: timed as such, once
        if "harmonics" not in self.__dict__:
            self.harmonics  # noqa: B018 - computed here so that a slow split is named
            deadline.check("while splitting the signals into harmonics", "signals")
        if "_layout" not in self.__dict__:
            self._layout  # noqa: B018
            deadline.check("while compiling the equation of motion")
        layout = self._layout
        names = list(self.model.parameters)
        flat = layout.compiled(*(values[name] for name in names))
        flat = np.broadcast_to(flat.reshape(len(layout.expressions), -1),
                               (len(layout.expressions), count))
        bad = ~np.isfinite(flat) | (np.abs(flat.imag) > 1e-9 * (1 + np.abs(flat.real)))
        if bad.any():
            self._raise_not_finite(layout, bad, values, count)
        return layout.read(flat.real, self, count)

    def _raise_not_finite(self, layout: _Layout, bad: np.ndarray, values: Mapping[str, Any],
                          count: int) -> None:
        n = self.n
        point = int(np.argmax(bad.any(axis=0)))
        varying = [(k, np.asarray(v)) for k, v in values.items() if np.ndim(v)]
        where = (f" at {varying[0][0]} = {float(varying[0][1].ravel()[point]):.6g}"
                 if varying and count > 1 else "")
        for label, matrix, offset in (("M", self.M, 0), ("C", self.C, n * n),
                                      ("K", self.K, 2 * n * n)):
            for idx in range(n * n):
                if bad[offset + idx, point]:
                    i, j = divmod(idx, n)
                    raise not_finite_problem(label, i, j, str(matrix[i, j]), self.source, where)
        raise ModelError(Problem("the excitation or an output is not finite (or not real) for "
                                 f"the given parameter values{where}", self.source,
                                 "parameters"))

    def symbolic_dict(self) -> dict[str, Any] | None:
        return self.to_dict()

    def to_dict(self) -> dict[str, Any]:
        return {
            "coordinates": list(self.coordinates),
            "M": matrix_strings(self.M), "C": matrix_strings(self.C), "K": matrix_strings(self.K),
            "Q": [str(e) for e in self.Q],
        }


def matrix_strings(matrix: sympy.MatrixBase) -> list[list[str]]:
    """The entries as text, each distinct entry printed once (symmetric matrices: half).

    Parameters
    ----------
    matrix : sympy matrix

    Returns
    -------
    list of list of str
    """
    printed: dict[sympy.Expr, str] = {}

    def text(entry: sympy.Expr) -> str:
        if entry not in printed:
            printed[entry] = str(entry)
        return printed[entry]

    return [[text(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)]


@dataclass(frozen=True)
class _Layout:
    """Every symbolic quantity of a LinearEOM in one flat list, compiled once.

    M, C, K (row-major); per frequency: omega, F_S, F_C and the (S, C) pair of
    each signal variable in ``frequencies[i]``; per output: its value and the
    coefficients of the variables in ``outputs[j][1]``.
    """

    expressions: tuple[sympy.Expr, ...]
    frequencies: tuple[tuple[Var, ...], ...]
    outputs: tuple[tuple[str, tuple[Var, ...]], ...]
    harmonic: bool
    compiled: Callable[..., np.ndarray]

    @classmethod
    def of(cls, eom: LinearEOM) -> _Layout:
        n = eom.n
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
        symbols = [symbol(name) for name in eom.model.parameters]
        return cls(tuple(exprs), tuple(frequencies), tuple(outputs), harmonics is not None,
                   compile_expressions(exprs, symbols))

    def read(self, flat: np.ndarray, eom: LinearEOM, count: int) -> Batch:
        """The batch from the compiled values, shape (expressions, count)."""
        n = eom.n
        take = FlatReader(flat).take

        def matrix() -> np.ndarray:
            a = take(n * n).T.reshape(count, n, n)
            return a[0].copy() if np.all(a == a[:1]) else a

        M, C, K = matrix(), matrix(), matrix()
        harmonics = []
        for variables in self.frequencies:
            omega = take(1)[0]
            f_s, f_c = take(n).T, take(n).T
            sig = take(2 * len(variables)).reshape(len(variables), 2, count)
            sign = np.where(omega < 0, -1.0, 1.0)  # sin(-w t) = -sin(w t)
            static = omega == 0
            f_s = np.where(static[:, None], 0.0, sign[:, None] * f_s)
            signals = {var: (np.where(static, 0.0, sign * sig[k, 0]), sig[k, 1].copy())
                       for k, var in enumerate(variables)}
            harmonics.append(BatchHarmonic(np.abs(omega), _squeeze(f_s), _squeeze(f_c),
                                           signals))
        outputs = {}
        for name, variables in self.outputs:
            value = take(1)[0].copy()
            coefs = take(len(variables))
            outputs[name] = (value, dict(zip(variables, coefs)))
        return Batch(eom.coordinates, M, C, K, harmonics, outputs, eom.title, self.harmonic,
                     count)


def _squeeze(vectors: np.ndarray) -> np.ndarray:
    """(N, n) -> (n,) when every row is the same (a constant force vector)."""
    return vectors[0].copy() if np.all(vectors == vectors[:1]) else vectors


__all__ = ["LinearEOM", "matrix_strings"]
