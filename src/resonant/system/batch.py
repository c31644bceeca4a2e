"""Numbers of a system at many parameter points (:class:`Batch`), and the compiled
evaluation of symbolic entries.

Symbolic entries are compiled once with :func:`sympy.lambdify` (common
subexpressions shared) and evaluated for all parameter values at once, so a
sweep over a parameter costs one compiled call, never a symbolic substitution.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

import numpy as np
import numpy.typing as npt
import sympy

from ..arrays import Matrix
from ..errors import AnalysisError, ModelError, Problem
from ..expressions import compilable

_T = TypeVar("_T")

Var = tuple[str, int]

#: two excitation frequencies closer than this (relative) are one frequency
SAME_FREQUENCY = 1e-12


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


# -- the batch: everything evaluated for all values at once ------------------------------

@dataclass
class BatchHarmonic:
    """One excitation frequency of a batch: omega (N,), F_S and F_C (N, n) or (n,).

    Parameters
    ----------
    omega : ndarray
        The frequency at each of the N points.
    F_S, F_C : ndarray
        Sine and cosine amplitudes, (N, n), or (n,) when they do not change.
    signals : dict
        ``(signal, order)`` -> (S, C) arrays at this frequency.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> eom.batch("omega", [10.0, 20.0]).harmonics[-1].omega.tolist()
    [10.0, 20.0]
    """

    omega: np.ndarray
    F_S: np.ndarray
    F_C: np.ndarray
    #: signal variable -> (S (N,), C (N,)), for outputs that depend on signals
    signals: dict[Var, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)

    @property
    def complex_load(self) -> np.ndarray:
        """The load as the kernel solves for it, F_C - i F_S ((N, n) or (n,) complex): the
        generalized forces' complex amplitudes, Q = Re((F_C - i F_S) e^(i omega t)).

        Returns
        -------
        ndarray
        """
        return np.asarray(self.F_C, dtype=complex) - 1j * np.asarray(self.F_S, dtype=float)


@dataclass
class Batch:
    """The system at N parameter points.

    Parameters
    ----------
    coordinates : tuple of str
        The generalized coordinates.
    M, C, K : ndarray or sparse matrix
        (n, n) (dense or sparse) when they do not change, else (N, n, n).
    harmonics : list of BatchHarmonic
        The excitation frequencies.
    outputs : dict
        name -> ``(value (N,), {variable: coefficient (N,)})``.
    title : str
        The model's title.
    harmonic : bool
        False when some signal is not a sum of harmonics.
    count : int
        N, the number of parameter points.

    Examples
    --------
    >>> import resonant
    >>> eom = resonant.load("examples/cart_pendulum.toml").linearize()
    >>> batch = eom.batch("k", [100.0, 200.0])
    >>> batch.count, batch.K.shape
    (2, (2, 2, 2))
    """

    coordinates: tuple[str, ...]
    M: Matrix
    C: Matrix
    K: Matrix
    harmonics: list[BatchHarmonic]
    outputs: dict[str, tuple[np.ndarray, dict[Var, np.ndarray]]]
    title: str = ""
    harmonic: bool = True
    count: int = 1

    @property
    def constant(self) -> bool:
        """True when M, C and K do not change with the parameter."""
        return all(hasattr(a, "tocsr") or np.ndim(a) == 2 for a in (self.M, self.C, self.K))

    def matrix(self, key: str, i: int) -> Matrix:
        """M, C or K at point ``i``."""
        a = getattr(self, key)
        return a if hasattr(a, "tocsr") or np.ndim(a) == 2 else a[i]


# -- compiled symbolic expressions -----------------------------------------------------------

#: lambdify's modules for numpy code: the module itself, not ``"numpy"``, whose namespace is
#: made by ``from numpy import *`` -- in numpy 2 that loads numpy.f2py, numpy.testing
#: (unittest, email, ...) and more, 0.1 to 0.15 s of a short process.  The printer is the
#: same (NumPyPrinter); names of numpy.linalg it prints are imported by lambdify itself.
NUMPY_MODULES = [np]


class CompiledExpressions:
    """Expressions compiled into one function (see :func:`compile_expressions`).

    ``compiled(*values)`` gives every expression's values as a complex array
    (expressions, *shape); ``compiled.rows(*values)`` gives them as they came: real
    (float) when every value is real, and which rows vary with the values (the others
    are constants broadcast along the shape), so that a caller checks a constant once.
    """

    def __init__(self, call: Callable[..., np.ndarray],
                 rows: Callable[..., tuple[np.ndarray, np.ndarray]] | None = None) -> None:
        self._call, self._rows = call, rows

    def __call__(self, *args: npt.ArrayLike) -> np.ndarray:
        return self._call(*args)

    def rows(self, *args: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """The values (float or complex, (expressions, *shape)) and the mask of the rows
        that vary (every row when not known)."""
        if self._rows is not None:
            return self._rows(*args)
        values = self._call(*args)
        return values, np.ones(len(values), dtype=bool)


def compile_expressions(expressions: Sequence[sympy.Expr], symbols: Sequence[sympy.Symbol]
                        ) -> CompiledExpressions:
    """One compiled function returning all expressions as a complex array.

    Parameters
    ----------
    expressions : sequence of sympy.Expr
    symbols : sequence of sympy.Symbol
        The arguments, in order (any number of them).

    Returns
    -------
    CompiledExpressions
        ``f(*values)``: values are numbers or arrays of one shape; the result has
        shape ``(len(expressions), *shape)``; NaN where an entry is not finite.
        ``f.rows(*values)``: the same values, real where they all are, and the mask
        of the rows that vary.
    """
    if not expressions:
        return CompiledExpressions(lambda *args: np.zeros(0))
    expressions = list(expressions)
    if len(expressions) >= SYMENGINE_MIN_EXPRESSIONS:
        # symengine evaluates in doubles: infinities give NaN/inf, exact integers of any
        # size become floats, so no pass over the (large) expressions is needed first
        compiled = _symengine_compiled(expressions, symbols)
        if compiled is not None:
            return CompiledExpressions(compiled)
    # zoo, nan, oo cannot be compiled (lambdify fails on them): they evaluate to NaN,
    # which the callers turn into an error naming the entry
    infinite = [i for i, e in enumerate(expressions)
                if isinstance(e, sympy.Basic) and e.has(sympy.zoo, sympy.nan, sympy.oo)]
    for i in infinite:
        expressions[i] = sympy.Integer(0)
    expressions = [compilable(e) for e in expressions]
    fn = sympy.lambdify(list(symbols), expressions, modules=NUMPY_MODULES, cse=True)

    def evaluated(args: Sequence[npt.ArrayLike]) -> tuple[tuple[int, ...], list[Any]]:
        # np.broadcast takes at most 64 arguments; the shapes alone have no limit
        shape = np.broadcast_shapes(*(np.shape(a) for a in args)) if args else ()
        try:
            with np.errstate(all="ignore"):
                values = fn(*args)
        except ArithmeticError:  # Python floats raise on overflow and division by zero
            values = _one_by_one(expressions, symbols, args)
        return shape, values

    def call(*args: npt.ArrayLike) -> np.ndarray:
        shape, values = evaluated(args)
        out = np.array([np.broadcast_to(v, shape) for v in values], dtype=complex)
        if infinite:
            out[infinite] = np.nan
        return out

    def rows(*args: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        shape, values = evaluated(args)
        varying = np.array([np.ndim(v) > 0 for v in values], dtype=bool)
        real = not any(np.iscomplexobj(v) for v in values)
        out = np.empty((len(values), *shape), dtype=float if real else complex)
        for i, v in enumerate(values):
            out[i] = v
        if infinite:
            out[infinite] = np.nan
            varying[infinite] = False
        return out, varying
    return CompiledExpressions(call, rows)


#: from this many expressions on, they are compiled by symengine: sympy's lambdify with
#: common subexpressions takes tens of seconds for the 7,500 entries of a 50-link chain,
#: symengine's (without them) a fraction of a second, and evaluates as fast
SYMENGINE_MIN_EXPRESSIONS = 300


def _symengine_compiled(expressions: Sequence[sympy.Expr], symbols: Sequence[sympy.Symbol]
                        ) -> Callable[..., np.ndarray] | None:
    """The expressions compiled by symengine's ``Lambdify`` (None if it cannot)."""
    import symengine

    try:
        # each distinct expression once: a symmetric matrix's mirrored entries and the
        # zeros are compiled (and evaluated) a single time
        unique: dict[Any, int] = {}
        where = np.array([unique.setdefault(symengine.sympify(e), len(unique))
                          for e in expressions], dtype=np.intp)
        fn = symengine.Lambdify([symengine.sympify(s) for s in symbols], list(unique),
                                backend="lambda", real=True)
    except (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError):
        return None
    count = len(unique)

    def call(*args: npt.ArrayLike) -> np.ndarray:
        shape = np.broadcast_shapes(*(np.shape(a) for a in args)) if args else ()
        if not args:
            return np.asarray(fn([]), dtype=complex).reshape(count, *shape)[where]
        table = np.stack([np.broadcast_to(np.asarray(a, dtype=float), shape) for a in args],
                         axis=-1)
        with np.errstate(all="ignore"):
            values = np.asarray(fn(table), dtype=float)  # (*shape, count)
        return np.moveaxis(values.reshape(*shape, count), -1, 0)[where].astype(complex)
    return call


def _one_by_one(expressions: Sequence[sympy.Expr], symbols: Sequence[sympy.Symbol],
                args: Sequence[npt.ArrayLike]) -> list[Any]:
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


__all__ = ["Batch", "BatchHarmonic", "CompiledExpressions", "compile_expressions",
           "SYMENGINE_MIN_EXPRESSIONS",
           "FlatReader", "check_finite", "group_frequencies", "SAME_FREQUENCY",
           "not_finite_problem"]
