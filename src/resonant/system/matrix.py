"""The linear system of a ``[matrices]`` model: M, K, optional C and ``[[harmonic]]`` loads.

Inline matrices hold expressions of the parameters (evaluated with numpy, no
sympy); file matrices hold numbers, dense or sparse, used as read.  The
symbolic form (sympy matrices) is built only when asked for (reports, JSON).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from types import MappingProxyType
from typing import Any

import numpy as np
import numpy.typing as npt
import sympy

from ..arrays import Matrix
from ..deadline import NO_DEADLINE, Deadline
from ..derivation import LinearMap, SignalHarmonics, decompose_signals
from ..errors import ModelError, Problem
from ..expressions import Expression, Num, numeric_value
from ..memory import dense_matrix
from ..model import TIME, Model, symbol
from ..model.rotor import SpeedTable
from .base import LinearSystem
from .batch import Batch, BatchHarmonic, compile_expressions
from .latex import SymbolicEquations, eom_latex
from .symbolic import loads_in_signals, loads_in_time, matrix_strings

Var = tuple[str, int]


@dataclass(frozen=True, eq=False)
class MatrixEOM(LinearSystem):
    """The equation of motion of a ``[matrices]`` model.

    Each harmonic j acts as two signals ``sin(omega_j t)`` and ``cos(omega_j t)``
    whose columns are F_S and F_C (:attr:`excitation`), so reports and
    outputs treat both kinds of model alike.

    Parameters
    ----------
    model : Model
        A model with ``[matrices]``.
    coordinates : tuple of str
        Its coordinates (``q1`` ... unless named).

    Examples
    --------
    >>> from resonant.model import loads
    >>> from resonant.system import linear_system
    >>> eom = linear_system(loads("[matrices]\\nM = [[2]]\\nK = [[8]]\\n"))
    >>> type(eom).__name__, eom.numeric().K.tolist()
    ('MatrixEOM', [[8.0]])
    """

    model: Model
    coordinates: tuple[str, ...]

    def _spec_matrix(self, key: str) -> Any:
        spec = self.model.matrices
        if spec is None:
            raise ModelError(Problem("the model has no [matrices] section", self.source))
        return getattr(spec, key)

    # the symbolic form, built on first use
    @cached_property
    def M(self) -> sympy.ImmutableMatrix:
        return _to_sympy(self._spec_matrix("M"), self.n)

    @cached_property
    def C(self) -> sympy.ImmutableMatrix:
        """C + speed G: the damping with the gyroscopic part (docs/rotors.md)."""
        damping = self._symbolic_terms("C", _to_sympy(self._spec_matrix("C"), self.n))
        speed = self._spec_matrix("speed")
        if self._spec_matrix("G") is None or speed is None:
            return damping
        return sympy.ImmutableMatrix(damping + symbol(speed) *
                                     _to_sympy(self._spec_matrix("G"), self.n))

    @cached_property
    def K(self) -> sympy.ImmutableMatrix:
        return self._symbolic_terms("K", _to_sympy(self._spec_matrix("K"), self.n))

    def _symbolic_terms(self, key: str, matrix: sympy.ImmutableMatrix
                        ) -> sympy.ImmutableMatrix:
        """The matrix with a rotor's parameter-dependent entries added (a table in speed
        as ``table_<entry>(speed)``)."""
        terms = [t for t in self._spec_matrix("speed_terms") if t.key == key]
        if not terms:
            return matrix
        out = sympy.Matrix(matrix)
        speed = symbol(self._spec_matrix("speed"))
        for term in terms:
            if isinstance(term.value, SpeedTable):
                name = "table_" + term.where.replace("rotor.", "").replace(" ", "_")
                out[term.row, term.column] += int(term.sign) * sympy.Function(name)(speed)
            else:
                out[term.row, term.column] += int(term.sign) * term.value.to_sympy(
                    lambda label, primes: symbol(label) if primes == 0 else 0)
        return sympy.ImmutableMatrix(out)

    @cached_property
    def _signals(self) -> tuple[dict[Var, sympy.ImmutableMatrix], dict[Var, sympy.Expr]]:
        spec = self.model.matrices
        assert spec is not None
        n = self.n
        resolve = lambda name, p: symbol(name) if p == 0 else 0  # noqa: E731
        excitation, signals = {}, {}
        for j, h in enumerate(spec.harmonics):
            w = h.omega.to_sympy(resolve)
            for label, vector, fn in (("s", h.F_S, sympy.sin), ("c", h.F_C, sympy.cos)):
                nonzero = {i: e.to_sympy(resolve) for i, e in enumerate(vector)
                           if e.text.strip() not in ("0", "0.0")}
                nonzero = {i: v for i, v in nonzero.items() if v != 0}
                if nonzero:
                    var = (f"harmonic{j + 1}_{label}", 0)
                    excitation[var] = sympy.ImmutableSparseMatrix(
                        n, 1, {(i, 0): v for i, v in nonzero.items()})
                    signals[var] = fn(w * TIME)
        return excitation, signals

    @property
    def excitation(self) -> Mapping[Var, sympy.ImmutableMatrix]:
        """``(signal, 0) -> column``: F_S and F_C of each harmonic."""
        return self._signals[0]

    @property
    def signal_functions(self) -> dict[Var, sympy.Expr]:
        """The internal signals sin(omega_j t) and cos(omega_j t)."""
        return dict(self._signals[1])

    @cached_property
    def harmonics(self) -> SignalHarmonics | None:
        """The harmonic decomposition of the internal signals."""
        return decompose_signals(self.signal_functions)

    @cached_property
    def outputs(self) -> Mapping[str, LinearMap]:
        """The ``[outputs]`` linearized at q = 0: value and the coefficients of the
        coordinates and their rates, in the parameters' symbols."""
        return MappingProxyType({name: _linear_output(expression, self.coordinates,
                                                      self.source, name)
                                 for name, expression in self.model.outputs.items()})

    @cached_property
    def _compiled_outputs(self) -> tuple[tuple[tuple[str, tuple[Var, ...]], ...],
                                         tuple[str, ...], Callable[..., np.ndarray]]:
        """(name, variables) per output, the parameters used, and the values and
        coefficients of all outputs as one compiled function of those parameters."""
        layout, expressions = [], []
        for name, out in self.outputs.items():
            layout.append((name, tuple(out.terms)))
            expressions += [out.value, *out.terms.values()]
        params = tuple(sorted({str(s) for e in expressions for s in e.free_symbols}))
        return tuple(layout), params, compile_expressions(expressions,
                                                          [symbol(p) for p in params])

    def _output_values(self, values: Mapping[str, Any], count: int
                       ) -> dict[str, tuple[np.ndarray, dict[Var, np.ndarray]]]:
        """The batch's outputs: name -> (value (count,), {variable: coefficient (count,)})."""
        layout, params, compiled = self._compiled_outputs
        if not layout:
            return {}
        raw = compiled(*(np.asarray(values[p], dtype=float) for p in params))
        raw = np.broadcast_to(raw.reshape(len(raw), -1), (len(raw), count))
        out, row = {}, 0
        for name, variables in layout:
            block = raw[row:row + 1 + len(variables)]
            if not (np.all(np.isfinite(block)) and np.all(block.imag == 0)):
                raise ModelError(Problem("the output is not finite (or not real) for the "
                                         "given parameter values", self.source, "outputs",
                                         name))
            out[name] = (block[0].real.copy(),
                         {v: block[1 + k].real.copy() for k, v in enumerate(variables)})
            row += 1 + len(variables)
        return out

    @cached_property
    def Q(self) -> sympy.ImmutableMatrix:
        """Q(t) with the harmonics written out."""
        return loads_in_time(self.excitation, self.signal_functions, self.n)

    @cached_property
    def Q_signals(self) -> sympy.ImmutableMatrix:
        """Q(t) written with the internal harmonic signals' names as symbols."""
        return loads_in_signals(self.excitation, self.n)

    @property
    def residual(self) -> sympy.ImmutableMatrix:
        return sympy.ImmutableSparseMatrix(self.n, 1, {})

    # numbers, without sympy
    def evaluate(self, values: Mapping[str, Any], count: int,
                 deadline: Deadline = NO_DEADLINE) -> Batch:
        spec = self.model.matrices
        assert spec is not None
        M, C, K = (self._with_terms(key, self._matrix_values(key, values), values)
                   for key in ("M", "C", "K"))
        C = self._with_gyroscopic(C, values)
        harmonics = []
        for j, h in enumerate(spec.harmonics, start=1):
            deadline.check("while evaluating the harmonic loads", f"harmonic {j}",
                           analysis=True)
            where = f"harmonic {j}"
            omega = np.asarray(numeric_value(h.omega, values), dtype=float)
            self._check_finite(omega, "omega", where)
            omega = np.broadcast_to(omega, (count,)).astype(float)
            vectors = []
            for label, (base, expressions) in zip(("F_S", "F_C"), self._loads[j - 1]):
                # the plain numbers (the bulk of a large model's load vectors) are read once
                entries = [numeric_value(e, values) for _, e in expressions]
                shape = np.broadcast_shapes(*(np.shape(v) for v in entries)) if entries else ()
                vec = np.broadcast_to(base, (*shape, base.size)).copy()
                for (i, _), v in zip(expressions, entries):
                    vec[..., i] = v
                self._check_finite(vec, label, where)
                vectors.append(vec)
            f_s, f_c = vectors
            sign = np.where(omega < 0, -1.0, 1.0)  # sin(-w t) = -sin(w t)
            static = omega == 0
            if (sign < 0).any() or static.any():
                f_s = np.where(static[:, None], 0.0, sign[:, None] * f_s)
                if np.all(f_s == f_s[:1]):
                    f_s = f_s[0].copy()
            signals = {}
            if np.any(f_s):
                signals[(f"harmonic{j}_s", 0)] = (np.where(static, 0.0, sign), np.zeros(count))
            if np.any(f_c):
                signals[(f"harmonic{j}_c", 0)] = (np.zeros(count), np.ones(count))
            harmonics.append(BatchHarmonic(np.abs(omega), f_s, f_c, signals))
        return Batch(self.coordinates, M, C, K, harmonics, self._output_values(values, count),
                     self.title, True, count)

    @cached_property
    def _loads(self) -> list[tuple[tuple[np.ndarray, list[tuple[int, Any]]], ...]]:
        """Per harmonic, F_S and F_C as (the numbers, 0 where an expression is, and the
        expressions by index)."""
        spec = self.model.matrices
        assert spec is not None
        out = []
        for h in spec.harmonics:
            parts = []
            for vector in (h.F_S, h.F_C):
                base = np.array([float(e.root.value) if type(e.root) is Num else 0.0
                                 for e in vector])
                parts.append((base, [(i, e) for i, e in enumerate(vector)
                                     if type(e.root) is not Num]))
            out.append(tuple(parts))
        return out

    def _matrix_values(self, key: str, values: Mapping[str, Any]) -> Any:
        """File matrices as read (dense or CSR); inline ones as (n, n) or (N, n, n)."""
        matrix = self._spec_matrix(key)
        n = self.n
        if matrix is None:
            M = self._spec_matrix("M")
            if hasattr(M, "tocsr"):
                import scipy.sparse

                return scipy.sparse.csr_matrix((n, n))
            return np.zeros((n, n))
        if not isinstance(matrix, list):
            return matrix
        entries = [[numeric_value(e, values) for e in row] for row in matrix]
        shape = np.broadcast_shapes(*(np.shape(v) for row in entries for v in row))
        out = np.empty((*shape, n, n))
        for i, row in enumerate(entries):
            for j, v in enumerate(row):
                out[..., i, j] = v
        self._check_finite(out, key)
        return out

    def _with_terms(self, key: str, matrix: Matrix, values: Mapping[str, Any]) -> Any:
        """The matrix with the entries that depend on the parameters added (a rotor's
        bearing coefficients; tables interpolated in the speed): a stack (N, n, n) where
        they vary."""
        terms = [t for t in self._spec_matrix("speed_terms") if t.key == key]
        if not terms:
            return matrix
        speed = self._spec_matrix("speed")
        added = []
        for term in terms:
            value = term.value(values[speed]) if isinstance(term.value, SpeedTable) else \
                numeric_value(term.value, values)
            value = np.asarray(value, dtype=float)
            if not np.all(np.isfinite(value)):
                raise ModelError(Problem("is not finite for the given parameter values",
                                         self.source, term.where, key))
            added.append(term.sign * value.reshape(-1))
        size = max(len(a) for a in added)
        if hasattr(matrix, "tolil") and size == 1:   # one point of a sparse model stays sparse
            sparse = matrix.tolil(copy=True)
            for term, value in zip(terms, added):
                sparse[term.row, term.column] += float(value[0])
            return sparse.tocsr()
        out = np.array(matrix.toarray() if hasattr(matrix, "toarray") else matrix, dtype=float)
        out = np.broadcast_to(out, (size, self.n, self.n) if size > 1 or out.ndim == 3
                              else out.shape).copy()
        for term, value in zip(terms, added):
            out[..., term.row, term.column] += value if out.ndim == 3 else value[0]
        return out

    def _with_gyroscopic(self, C: Matrix, values: Mapping[str, Any]) -> Any:
        """C + speed G at the parameter values: (n, n) where the speed is one number (dense
        or sparse, as given), else a stack (N, n, n)."""
        G, speed = self._spec_matrix("G"), self._spec_matrix("speed")
        if G is None or speed is None:
            return C
        G = self._matrix_values("G", values)
        omega = np.asarray(values[speed], dtype=float)
        self._check_finite(omega, "speed")
        if omega.size == 1 and np.ndim(G) <= 2 and np.ndim(C) <= 2:
            return C + float(omega.reshape(-1)[0]) * G
        dense = [dense_matrix(a, None) for a in (C, G)]
        return dense[0] + omega.reshape(-1, 1, 1) * dense[1]

    def _check_finite(self, array: npt.ArrayLike, key: str, section: str = "matrices") -> None:
        if not np.all(np.isfinite(array)):
            raise ModelError(Problem(f"{key} is not finite (or not real) for the given "
                                     "parameter values", self.source, section, key))

    def to_dict(self) -> dict[str, Any]:
        if self.n > 200:  # the symbolic text of a large model is no use to anyone
            return {}
        return {"coordinates": list(self.coordinates),
                "M": matrix_strings(self.M), "C": matrix_strings(self.C),
                "K": matrix_strings(self.K),
                "Q": [str(e) for e in self.Q]}

    def symbolic(self) -> SymbolicEquations | None:
        return self

    def _repr_latex_(self) -> str:
        return eom_latex(self)


def _linear_output(expression: Expression, coordinates: tuple[str, ...], source: str,
                   name: str) -> LinearMap:
    """An output's value and first-order coefficients at q = q' = q'' = 0."""
    small: dict[Var, sympy.Symbol] = {}
    known = set(coordinates)

    def resolve(label: str, primes: int) -> sympy.Expr:
        if label not in known:
            return symbol(label) if primes == 0 else sympy.Integer(0)
        var = (label, primes)
        small.setdefault(var, sympy.Dummy(f"{label}_{primes}"))
        return small[var]

    full = expression.to_sympy(resolve)
    zero = {s: 0 for s in small.values()}
    value = full.subs(zero)
    terms = {var: sympy.diff(full, s).subs(zero) for var, s in small.items()}
    terms = {var: c for var, c in terms.items() if c != 0}
    if any(e.has(sympy.zoo, sympy.nan, sympy.oo) for e in (value, *terms.values())):
        raise ModelError(Problem("the output has no first-order expansion at q = 0 (e.g. "
                                 "abs(q1) or sqrt(q1)); write it in a form that is smooth "
                                 "at rest", source, "outputs", name))
    return LinearMap(value, MappingProxyType(terms))


def _to_sympy(matrix: Matrix | Sequence[Sequence[Expression]] | None, n: int
              ) -> sympy.ImmutableMatrix:
    if matrix is None:
        return sympy.ImmutableSparseMatrix(n, n, {})
    if hasattr(matrix, "tocoo"):
        coo = matrix.tocoo()
        return sympy.ImmutableSparseMatrix(n, n, {
            (int(i), int(j)): sympy.Float(float(v))
            for i, j, v in zip(coo.row, coo.col, coo.data) if v != 0})
    if isinstance(matrix, np.ndarray):
        return sympy.ImmutableMatrix(matrix.shape[0], matrix.shape[1],
                                     [sympy.Float(float(v)) for v in matrix.ravel()])
    return sympy.ImmutableMatrix([[e.to_sympy(lambda name, p: symbol(name) if p == 0 else 0)
                                   for e in row] for row in matrix])


__all__ = ["MatrixEOM"]
