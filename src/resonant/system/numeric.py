"""Numbers: the system at one parameter point (:class:`NumericEOM`) or at many (:class:`Batch`).

Symbolic entries are compiled once with :func:`sympy.lambdify` (common
subexpressions shared) and evaluated for all parameter values at once, so a
sweep over a parameter costs one compiled call, never a symbolic substitution.

Examples
--------
>>> import numpy as np
>>> eom = NumericEOM(("x",), np.eye(1), np.zeros((1, 1)), 4 * np.eye(1),
...                  (NumericHarmonic(1.0, np.array([3.0]), np.array([0.0])),))
>>> eom.n, eom.numeric() is eom
(1, True)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
import sympy

from ..deadline import NO_DEADLINE, Deadline
from ..errors import AnalysisError, ModelError, Problem
from ..model import Model
from .base import LinearSystem, parameter_values

Var = tuple[str, int]

#: two excitation frequencies closer than this (relative) are one frequency
SAME_FREQUENCY = 1e-12


def frozen_array(a: Any) -> Any:
    """A read-only view of an array (sparse matrices and non-arrays pass unchanged)."""
    if isinstance(a, np.ndarray):
        a = a.view()
        a.flags.writeable = False
    return a


def group_frequencies(omegas: Sequence[float]) -> list[list[int]]:
    """Indices of equal frequencies (within :data:`SAME_FREQUENCY`), in first-seen order.

    The one rule by which excitations are merged: terms at the same frequency
    superpose into one harmonic.

    Parameters
    ----------
    omegas : sequence of float

    Returns
    -------
    list of list of int

    Examples
    --------
    >>> group_frequencies([2.0, 1.0, 2.0 * (1 + 1e-14), 0.0])
    [[0, 2], [1], [3]]
    """
    groups: list[tuple[float, list[int]]] = []
    for i, w in enumerate(omegas):
        for key, members in groups:
            if math.isclose(key, w, rel_tol=SAME_FREQUENCY, abs_tol=0.0):
                members.append(i)
                break
        else:
            groups.append((float(w), [i]))
    return [members for _, members in groups]


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

    def __post_init__(self) -> None:
        object.__setattr__(self, "F_S", frozen_array(np.asarray(self.F_S, dtype=float)))
        object.__setattr__(self, "F_C", frozen_array(np.asarray(self.F_C, dtype=float)))


@dataclass(frozen=True)
class NumericOutput:
    """A linearized output y = value + sum coefficient * (coordinate or signal derivative)."""

    value: float
    terms: Mapping[Var, float]


@dataclass(frozen=True, eq=False)
class NumericEOM(LinearSystem):
    """M q'' + C q' + K q = Q(t) with numbers (dense arrays or scipy sparse matrices).

    Attributes
    ----------
    harmonics : tuple of NumericHarmonic
        The excitation, grouped by frequency (ascending).
    harmonic : bool
        False when some signal is not a sum of harmonics (no stationary solution).
    outputs : mapping
        name -> NumericOutput.
    parameters : mapping
        The parameter values these numbers are for.
    system : LinearSystem or None
        The system these numbers were evaluated from.
    """

    coordinates: tuple[str, ...]
    M: Any
    C: Any
    K: Any
    harmonics: tuple[NumericHarmonic, ...] = ()
    harmonic: bool = True
    outputs: Mapping[str, NumericOutput] = field(default_factory=dict)
    parameters: Mapping[str, float] = field(default_factory=dict)
    title_: str = ""
    source_: str = ""
    system: LinearSystem | None = None

    def __post_init__(self) -> None:
        for key in ("M", "C", "K"):
            object.__setattr__(self, key, frozen_array(getattr(self, key)))

    @property
    def model(self) -> Model | None:  # type: ignore[override]
        return self.system.model if self.system is not None else None

    @property
    def title(self) -> str:
        return self.title_ or (self.system.title if self.system is not None else "")

    @property
    def source(self) -> str:
        return self.source_ or (self.system.source if self.system is not None else "")

    @property
    def sparse(self) -> bool:
        """True when M, C or K is a scipy sparse matrix."""
        return any(hasattr(a, "tocsr") for a in (self.M, self.C, self.K))

    def dense(self) -> "NumericEOM":
        """The same system with dense M, C, K (itself when they are dense)."""
        if not self.sparse:
            return self
        from dataclasses import replace

        return replace(self, M=_dense(self.M), C=_dense(self.C), K=_dense(self.K))

    def evaluate(self, values: Mapping[str, Any], count: int,
                 deadline: Deadline = NO_DEADLINE) -> "Batch":
        return Batch.constant_system(self, count)

    def numeric(self, deadline: Deadline = NO_DEADLINE, **overrides: float | str
                ) -> "NumericEOM":
        if not overrides:
            return self
        if self.system is None:
            raise ModelError("a numeric system without its model cannot change its parameters")
        return self.system.numeric(deadline, **{**dict(self.parameters), **overrides})

    def batch(self, param: str, values: np.ndarray, deadline: Deadline = NO_DEADLINE
              ) -> "Batch":
        values = np.asarray(values, dtype=float)
        if self.system is not None and self.system.model is not None:
            return self.system.evaluate(parameter_values(self.system.model, param, values,
                                                         base=self.parameters),
                                        len(values), deadline)
        moving = [h for h in self.harmonics if h.omega > 0]
        if param != "omega" or len(moving) != 1:
            raise AnalysisError(
                "without its model, a numeric equation of motion can only be swept over the "
                "excitation frequency 'omega' of a single harmonic; pass the model's system "
                "to sweep other parameters")
        batch = Batch.constant_system(self, len(values))
        h = moving[0]
        static = [BatchHarmonic(np.zeros_like(values), np.zeros(self.n), s.F_C)
                  for s in self.harmonics if s.omega == 0]
        return Batch(batch.coordinates, batch.M, batch.C, batch.K,
                     [*static, BatchHarmonic(values.copy(), h.F_S, h.F_C)], batch.outputs,
                     batch.title)

    def to_dict(self) -> dict[str, Any]:
        return self.system.to_dict() if self.system is not None else {}

    def symbolic_dict(self) -> dict[str, Any] | None:
        return self.system.symbolic_dict() if self.system is not None else None


def _dense(a: Any) -> np.ndarray:
    return a.toarray() if hasattr(a, "toarray") else np.asarray(a, dtype=float)


# -- the batch: everything evaluated for all values at once ------------------------------

@dataclass
class BatchHarmonic:
    """One excitation frequency of a batch: omega (N,), F_S and F_C (N, n) or (n,)."""

    omega: np.ndarray
    F_S: np.ndarray
    F_C: np.ndarray
    #: signal variable -> (S (N,), C (N,)), for outputs that depend on signals
    signals: dict[Var, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)


@dataclass
class Batch:
    """The system at N parameter points.

    M, C, K are (n, n) (dense or sparse) when they do not change, else (N, n, n).
    ``outputs`` maps a name to ``(value (N,), {variable: coefficient (N,)})``.
    """

    coordinates: tuple[str, ...]
    M: Any
    C: Any
    K: Any
    harmonics: list[BatchHarmonic]
    outputs: dict[str, tuple[np.ndarray, dict[Var, np.ndarray]]]
    title: str = ""
    harmonic: bool = True
    count: int = 1

    @property
    def constant(self) -> bool:
        """True when M, C and K do not change with the parameter."""
        return all(hasattr(a, "tocsr") or np.ndim(a) == 2 for a in (self.M, self.C, self.K))

    @classmethod
    def constant_system(cls, eom: NumericEOM, count: int) -> "Batch":
        """A batch of ``count`` copies of a numeric system."""
        return cls(tuple(eom.coordinates), eom.M, eom.C, eom.K,
                   [BatchHarmonic(np.full(count, h.omega), h.F_S, h.F_C,
                                  {v: (np.full(count, s), np.full(count, c))
                                   for v, (s, c) in h.signals.items()})
                    for h in eom.harmonics],
                   {name: (np.full(count, out.value),
                           {v: np.full(count, c) for v, c in out.terms.items()})
                    for name, out in eom.outputs.items()},
                   eom.title, eom.harmonic, count)

    def matrix(self, key: str, i: int) -> Any:
        """M, C or K at point ``i``."""
        a = getattr(self, key)
        return a if hasattr(a, "tocsr") or np.ndim(a) == 2 else a[i]

    def point(self, i: int, system: LinearSystem | None = None,
              parameters: Mapping[str, Any] | None = None) -> NumericEOM:
        """The numeric system at point ``i``, its excitations merged by frequency."""
        n = len(self.coordinates)
        entries = []
        for h in self.harmonics:
            f_s = np.asarray(h.F_S, dtype=float)
            f_c = np.asarray(h.F_C, dtype=float)
            entries.append((float(h.omega[i]), f_s[i] if f_s.ndim == 2 else f_s,
                            f_c[i] if f_c.ndim == 2 else f_c,
                            {v: (float(s[i]), float(c[i])) for v, (s, c) in h.signals.items()}))
        harmonics = []
        for members in group_frequencies([e[0] for e in entries]):
            f_s, f_c, sig = np.zeros(n), np.zeros(n), {}
            for k in members:
                f_s = f_s + entries[k][1]
                f_c = f_c + entries[k][2]
                for var, (s, c) in entries[k][3].items():
                    old = sig.get(var, (0.0, 0.0))
                    sig[var] = (old[0] + s, old[1] + c)
            harmonics.append(NumericHarmonic(entries[members[0]][0], f_s, f_c,
                                             MappingProxyType(sig)))
        harmonics.sort(key=lambda h: h.omega)
        outputs = {name: NumericOutput(float(value[i]), MappingProxyType(
            {v: float(c[i]) for v, c in terms.items()}))
            for name, (value, terms) in self.outputs.items()}
        params = {k: float(np.asarray(v).ravel()[i] if np.ndim(v) else v)
                  for k, v in (parameters or {}).items()}
        return NumericEOM(
            coordinates=tuple(self.coordinates), M=self.matrix("M", i), C=self.matrix("C", i),
            K=self.matrix("K", i), harmonics=tuple(harmonics), harmonic=self.harmonic,
            outputs=MappingProxyType(outputs), parameters=MappingProxyType(params),
            system=system)


# -- compiled symbolic expressions -----------------------------------------------------------

def compile_expressions(expressions: Sequence[sympy.Expr], symbols: Sequence[sympy.Symbol]
                        ) -> Callable[..., np.ndarray]:
    """One compiled function returning all expressions as a complex array.

    Parameters
    ----------
    expressions : sequence of sympy.Expr
    symbols : sequence of sympy.Symbol
        The arguments, in order (any number of them).

    Returns
    -------
    callable
        ``f(*values)``: values are numbers or arrays of one shape; the result has
        shape ``(len(expressions), *shape)``; NaN where an entry is not finite.
    """
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
        # np.broadcast takes at most 64 arguments; the shapes alone have no limit
        shape = np.broadcast_shapes(*(np.shape(a) for a in args)) if args else ()
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


class FlatReader:
    """Reads consecutive blocks (along the first axis) of compiled values."""

    def __init__(self, flat: np.ndarray) -> None:
        self.flat, self.pos = flat, 0

    def take(self, count: int) -> np.ndarray:
        out = self.flat[self.pos:self.pos + count]
        self.pos += count
        return out


def check_finite(name: str, array: np.ndarray) -> np.ndarray:
    """Guard: NaN or infinity never reaches the output silently.

    Parameters
    ----------
    name : str
        What the array is, for the message.
    array : ndarray

    Returns
    -------
    ndarray
        ``array`` itself.

    Raises
    ------
    AnalysisError
        If an entry is NaN or infinite.
    """
    if not np.all(np.isfinite(array)):
        raise AnalysisError(f"{name} is not finite: the computation overflowed or divided "
                            "by zero; check the parameter values")
    return array


def not_finite_problem(label: str, i: int, j: int, entry: str, source: str,
                       where: str = "") -> ModelError:
    """The error for a matrix entry that is not finite at the given parameter values."""
    entry = entry if len(entry) <= 80 else entry[:77] + "..."
    return ModelError(Problem(
        f"{label}[{i + 1},{j + 1}] = {entry} is not finite for the given parameter values"
        f"{where} (a zero mass or length?)", source, "parameters"))


__all__ = ["NumericEOM", "NumericHarmonic", "NumericOutput", "Batch", "BatchHarmonic",
           "compile_expressions", "FlatReader", "check_finite", "group_frequencies",
           "frozen_array", "SAME_FREQUENCY"]
