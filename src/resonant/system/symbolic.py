"""The linear system of a model given by its energies: entries in the model's own symbols.

Examples
--------
>>> from resonant.api import loads
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
from ..derivation import (
    Linearization,
    LinearMap,
    SignalHarmonics,
    decompose_signals,
    linearize,
)
from ..derivation.lagrange import (
    NumericLinearization,
    RawLinearization,
    linearize_numeric,
    linearize_raw,
    signal_derivatives,
    signal_symbol,
)
from ..errors import ModelError, Problem
from ..model import Model, symbol
from .base import LinearSystem
from .batch import (
    SYMENGINE_MIN_EXPRESSIONS,
    Batch,
    BatchHarmonic,
    CompiledExpressions,
    FlatReader,
    compile_expressions,
    not_finite_problem,
)
from .latex import SymbolicEquations, eom_latex

Var = tuple[str, int]


def loads_in_time(excitation: Mapping[Var, Any], signals: Mapping[Var, Any],
                  n: int) -> sympy.ImmutableMatrix:
    """Q(t): each excitation column times its signal derivative written out in time."""
    q = sympy.zeros(n, 1)
    for var, column in excitation.items():
        q += column * signals[var]
    return sympy.ImmutableMatrix(q)


def loads_in_signals(excitation: Mapping[Var, Any], n: int) -> sympy.ImmutableMatrix:
    """Q(t) written with the signals' names (r, r', ...) as symbols."""
    q = sympy.zeros(n, 1)
    for (name, order), column in excitation.items():
        q += column * signal_symbol(name, order)
    return sympy.ImmutableMatrix(q)


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
    model : Model
        The model derived.
    coordinates : tuple of str
        The generalized coordinates, in order.

    Examples
    --------
    >>> import resonant
    >>> from resonant.system import linear_system
    >>> eom = linear_system(resonant.load("examples/cart_pendulum.toml"))
    >>> eom.K.tolist()
    [[k, 0], [0, g*m2/(2*l)]]
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

    @classmethod
    def of_model(cls, model: Model, deadline: Deadline = NO_DEADLINE,
                 numeric: bool | None = None) -> LinearEOM:
        """The system of a model given by its energies.

        A large model (:data:`NUMERIC_MIN_COORDINATES` coordinates or more) is
        derived numerically at its parameter values first
        (:func:`~resonant.derivation.lagrange.linearize_numeric`, which also checks
        the model and the equilibrium); its symbolic matrices are derived only when
        asked for (:class:`DeferredEOM`).  When the numbers cannot decide (see
        there), or for a small model, the symbolic derivation runs at once.

        Parameters
        ----------
        model : Model
        deadline : Deadline, optional
            Checked throughout the derivation (also the deferred one).
        numeric : bool, optional
            Force (True) or forbid (False) the numeric path; by default by size.

        Returns
        -------
        LinearEOM

        Raises
        ------
        ModelError
            If the derivation fails (see :func:`resonant.derivation.linearize`).
        """
        if numeric is None:
            numeric = len(model.coordinates) >= NUMERIC_MIN_COORDINATES
        if numeric:
            values = dict(model.parameter_values)
            found = linearize_numeric(model, values, deadline)
            if found is not None:
                return DeferredEOM(model, found, values, deadline)
        return cls.from_linearization(linearize(model, deadline=deadline))

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
        return loads_in_time(self.excitation, self.signal_functions, self.n)

    @cached_property
    def Q_signals(self) -> sympy.ImmutableMatrix:
        """Q(t) written with the signal names (r, r', ...) as symbols."""
        return loads_in_signals(self.excitation, self.n)

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
        flat, varying = layout.compiled.rows(*(values[name] for name in names))
        flat = np.broadcast_to(flat.reshape(len(layout.expressions), -1),
                               (len(layout.expressions), count))
        # the rows that vary are checked everywhere, the constant ones once
        if _not_finite_or_real(flat[varying]).any() or \
                _not_finite_or_real(flat[~varying, :1]).any():
            self._raise_not_finite(layout, _not_finite_or_real(flat), values, count)
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

    def derived_matrices(self) -> tuple[Any, Any, Any, Any] | None:
        return self.M, self.C, self.K, self.Q

    def to_dict(self) -> dict[str, Any]:
        return {
            "coordinates": list(self.coordinates),
            "M": matrix_strings(self.M), "C": matrix_strings(self.C), "K": matrix_strings(self.K),
            "Q": [str(e) for e in self.Q],
        }

    def symbolic(self) -> SymbolicEquations | None:
        return self

    def _repr_latex_(self) -> str:
        return eom_latex(self)


#: from this many coordinates on, a model's numbers come from the numeric derivation
#: (:meth:`LinearEOM.of_model`); its symbolic matrices are derived when asked for
NUMERIC_MIN_COORDINATES = 12

#: numeric derivations kept per system (one per distinct parameter point)
NUMERIC_CACHE = 8


class DeferredEOM(LinearEOM):
    """A :class:`LinearEOM` whose numbers come from the numeric derivation.

    ``numeric()`` and ``batch()`` evaluate the jets with floats at the
    parameter point (:func:`~resonant.derivation.lagrange.linearize_numeric`)
    and compile only the signals' harmonic parts; M, C, K, the excitation,
    the residual and the outputs as expressions (for reports, LaTeX,
    ``to_dict``) are derived symbolically on first access, under the time limit
    the system was made with (counted from then, see :meth:`raw`).  A batch in
    which a parameter of the matrices varies is compiled from the symbolic
    derivation's own (symengine) coefficients, without sympy (:meth:`raw`); a
    point where the numbers cannot decide, or a value that is not finite, is
    evaluated exactly as by a :class:`LinearEOM` (which names the culprit).

    Parameters
    ----------
    model : Model
    found : NumericLinearization
        The numeric derivation at ``values``.
    values : mapping
        The parameter values of ``found``.
    deadline : Deadline, optional
        For the symbolic derivation, when it is needed.
    """

    _deadline: Deadline
    _used: tuple[str, ...]
    _points: dict[tuple[float, ...], NumericLinearization]

    def __new__(cls, *args: Any, **fields: Any) -> Any:
        # dataclasses.replace() calls the class with every field of a LinearEOM: the copy
        # is then a LinearEOM with those (symbolic) fields
        if "M" in fields:
            return LinearEOM(*args, **fields)
        return super().__new__(cls)

    def __init__(self, model: Model, found: NumericLinearization,
                 values: Mapping[str, float], deadline: Deadline = NO_DEADLINE) -> None:
        object.__setattr__(self, "model", model)
        object.__setattr__(self, "coordinates", tuple(model.coordinates))
        object.__setattr__(self, "_deadline", deadline)
        object.__setattr__(self, "_used", tuple(sorted(found.parameters)))
        object.__setattr__(self, "_points", {self._key(values): found})

    def __repr__(self) -> str:
        return f"DeferredEOM({self.title or self.source!r}, n={self.n})"

    # -- the symbolic form, derived on first use ---------------------------------------
    @cached_property
    def linearization(self) -> Linearization:
        """The symbolic derivation (run once, when a symbolic quantity is first asked for)."""
        return self.raw().linearization()

    @cached_property
    def M(self) -> sympy.ImmutableMatrix:
        """The symbolic mass matrix (derived on first access)."""
        return self.linearization.M

    @cached_property
    def C(self) -> sympy.ImmutableMatrix:
        """The symbolic damping matrix (derived on first access)."""
        return self.linearization.C

    @cached_property
    def K(self) -> sympy.ImmutableMatrix:
        """The symbolic stiffness matrix (derived on first access)."""
        return self.linearization.K

    @cached_property
    def excitation(self) -> Mapping[Var, sympy.ImmutableMatrix]:
        """The symbolic excitation columns (derived on first access)."""
        return self.linearization.excitation

    @cached_property
    def residual(self) -> sympy.ImmutableMatrix:
        """The symbolic residual (derived on first access)."""
        return self.linearization.residual

    @cached_property
    def outputs(self) -> Mapping[str, LinearMap]:
        """The symbolic linearized outputs (derived on first access)."""
        return self.linearization.outputs

    # -- numbers -------------------------------------------------------------------------
    def _key(self, values: Mapping[str, Any]) -> tuple[float, ...]:
        return tuple(float(values[name]) for name in self._used)

    def point(self, values: Mapping[str, Any], deadline: Deadline = NO_DEADLINE
              ) -> NumericLinearization | None:
        """The numeric derivation at ``values`` (None when it cannot decide, or when a
        parameter it depends on is an array)."""
        if any(np.ndim(values[name]) for name in self._used):
            return None
        key = self._key(values)
        if key not in self._points:
            scalars = {k: (v if not np.ndim(v) else 0.0) for k, v in values.items()}
            found = linearize_numeric(self.model, scalars, deadline, check_equilibrium=False)
            if found is None:
                return None
            if len(self._points) >= NUMERIC_CACHE:
                self._points.pop(next(iter(self._points)))
            self._points[key] = found
        return self._points[key]

    def raw(self, deadline: Deadline | None = None) -> RawLinearization:
        """The symbolic derivation before its conversion to sympy (run once).

        Under ``deadline`` when it has a limit, else under the time limit the system
        was made with, counted afresh (the deferred derivation is new work: a limit
        that ran out while the numbers were used must not fail it).
        """
        if "_raw" not in self.__dict__:
            if deadline is None or deadline.seconds is None:
                deadline = Deadline(self._deadline.seconds, self._deadline.source)
            self.__dict__["_raw"] = linearize_raw(self.model, deadline=deadline)
        raw: RawLinearization = self.__dict__["_raw"]
        return raw

    def _compiled_numbers(self, values: Mapping[str, Any], count: int, deadline: Deadline
                          ) -> _Numbers | None:
        """The numbers from the symbolic derivation compiled without sympy (symengine's
        coefficients straight into its ``Lambdify``); None for a small system."""
        n = self.n
        if 3 * n * n < SYMENGINE_MIN_EXPRESSIONS:
            return None
        if "_raw_compiled" not in self.__dict__:
            raw = self.raw(deadline)
            deadline.check("while compiling the equation of motion")
            zero = sympy.Integer(0)
            exprs = [raw.entries[order].get((i, j), zero) for order in (2, 1, 0)
                     for i in range(n) for j in range(n)]
            columns = tuple(sorted(raw.excitation))
            for var in columns:
                exprs += [raw.excitation[var].get(k, zero) for k in range(n)]
            outputs = []
            for name, (value, terms) in raw.outputs.items():
                exprs += [value, *terms.values()]
                outputs.append((name, tuple(terms)))
            symbols = [symbol(name) for name in self.model.parameters]
            self.__dict__["_raw_compiled"] = (len(exprs), columns, tuple(outputs),
                                              compile_expressions(exprs, symbols))
        size, columns, outputs, compiled = self.__dict__["_raw_compiled"]
        flat = compiled(*(values[name] for name in self.model.parameters))
        take = FlatReader(np.broadcast_to(flat.reshape(size, -1), (size, count))).take
        matrices = (take(n * n), take(n * n), take(n * n))
        excitation = {var: -take(n) for var in columns}
        out = {}
        for name, variables in outputs:
            value = take(1)[0]
            out[name] = (value, dict(zip(variables, take(len(variables)))))
        return _Numbers(matrices, excitation, out)

    def evaluate(self, values: Mapping[str, Any], count: int,
                 deadline: Deadline = NO_DEADLINE) -> Batch:
        found = self.point(values, deadline)
        numbers = (_Numbers.of(found) if found is not None
                   else self._compiled_numbers(values, count, deadline))
        if numbers is None:
            return super().evaluate(values, count, deadline)
        signals = _NumericSignals.of(self, numbers, deadline)
        names = list(self.model.parameters)
        parts = np.zeros((0, count), dtype=complex)
        if signals.expressions:
            parts = signals.compiled(*(values[name] for name in names))
            parts = np.broadcast_to(parts.reshape(len(signals.expressions), -1),
                                    (len(signals.expressions), count))
        n = self.n
        rows: list[np.ndarray] = [np.broadcast_to(np.asarray(a, dtype=complex), (n * n, count))
                                  for a in numbers.matrices]
        take = FlatReader(parts).take
        for variables in signals.layout.frequencies:
            rows.append(take(1))
            f_s = np.zeros((n, count), dtype=complex)
            f_c = np.zeros((n, count), dtype=complex)
            sig = take(2 * len(variables)).reshape(len(variables), 2, count)
            for k, var in enumerate(variables):
                column = numbers.excitation.get(var)
                if column is not None:
                    f_s += column * sig[k, 0]
                    f_c += column * sig[k, 1]
            rows += [f_s, f_c, sig.reshape(2 * len(variables), count)]
        for name, variables in signals.layout.outputs:
            value, terms = numbers.outputs[name]
            rows.append(np.broadcast_to(np.asarray(value, dtype=complex), (1, count)))
            rows += [np.broadcast_to(np.asarray(terms[v], dtype=complex), (1, count))
                     for v in variables]
        flat = np.concatenate(rows, axis=0)
        bad = ~np.isfinite(flat) | (np.abs(flat.imag) > 1e-9 * (1 + np.abs(flat.real)))
        if bad.any():  # the symbolic evaluation names the culprit
            return super().evaluate(values, count, deadline)
        return signals.layout.read(flat.real, self, count)


@dataclass(frozen=True)
class _Numbers:
    """M, C, K (rows of the flattened matrices, (n*n, count) or (n*n, 1)), the excitation
    columns ((n, count) or (n, 1), Q = sum column * signal derivative) and the outputs
    (value, {variable: coefficient}) of a :class:`DeferredEOM` at the points."""

    matrices: tuple[np.ndarray, np.ndarray, np.ndarray]
    excitation: Mapping[Var, np.ndarray]
    outputs: Mapping[str, tuple[Any, Mapping[Var, Any]]]

    @classmethod
    def of(cls, found: NumericLinearization) -> _Numbers:
        """The numbers of a numeric derivation (one point)."""
        return cls((found.M.reshape(-1, 1), found.C.reshape(-1, 1), found.K.reshape(-1, 1)),
                   {var: c[:, None] for var, c in found.excitation.items()}, found.outputs)


@dataclass(frozen=True)
class _NumericSignals:
    """The signal part of a :class:`DeferredEOM`'s layout: the harmonic split of the
    signal derivatives its numbers need, compiled once (frequencies, S and C)."""

    expressions: tuple[sympy.Expr, ...]
    layout: _Layout
    compiled: Callable[..., np.ndarray]

    @classmethod
    def of(cls, eom: DeferredEOM, numbers: _Numbers, deadline: Deadline) -> _NumericSignals:
        model = eom.model
        needed = set(numbers.excitation)
        for _, terms in numbers.outputs.values():
            needed |= {v for v in terms if v[0] in model.signals}
        outputs = tuple((name, tuple(terms)) for name, (_, terms) in numbers.outputs.items())
        cache: dict[tuple[Any, ...], _NumericSignals] = eom.__dict__.setdefault(
            "_signal_layouts", {})
        key = (frozenset(needed), outputs)
        if key in cache:
            return cache[key]
        harmonics = decompose_signals(signal_derivatives(model, needed))
        deadline.check("while splitting the signals into harmonics", "signals")
        exprs: list[sympy.Expr] = []
        frequencies = []
        if harmonics is not None:
            variables = tuple(harmonics.parts)
            for w in harmonics.frequencies:
                exprs.append(w)
                for var in variables:
                    s, c = harmonics.parts[var].get(w, (0, 0))
                    exprs += [sympy.sympify(s), sympy.sympify(c)]
                frequencies.append(variables)
        symbols = [symbol(name) for name in model.parameters]
        layout = _Layout((), tuple(frequencies), outputs, harmonics is not None,
                         compile_expressions([], symbols))
        out = cls(tuple(exprs), layout, compile_expressions(exprs, symbols))
        cache[key] = out
        return out


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
    compiled: CompiledExpressions

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


def _not_finite_or_real(values: np.ndarray) -> np.ndarray:
    """Entries that are not finite, or complex with an imaginary part beyond rounding."""
    if not np.iscomplexobj(values):
        return np.asarray(~np.isfinite(values))
    return np.asarray(~np.isfinite(values)
                      | (np.abs(values.imag) > 1e-9 * (1 + np.abs(values.real))))


def _squeeze(vectors: np.ndarray) -> np.ndarray:
    """(N, n) -> (n,) when every row is the same (a constant force vector)."""
    return vectors[0].copy() if np.all(vectors == vectors[:1]) else vectors


__all__ = ["LinearEOM", "DeferredEOM", "NUMERIC_MIN_COORDINATES", "matrix_strings"]
