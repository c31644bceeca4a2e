"""Matrix models: ``[matrices]`` with M, K, optional C and ``[[harmonic]]`` loads.

Matrices are inline arrays (numbers or expressions of the parameters) or
paths, relative to the model file, to ``.npy``, ``.npz`` (the array named
like the matrix, or the only one) or Matrix Market ``.mtx`` files.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy

from .errors import AnalysisError, ModelError, Problem
from .expr import Num, Expression, ExpressionError, parse
from .numeric import NumericEOM, NumericHarmonic

if TYPE_CHECKING:  # pragma: no cover
    from .linearize import LinearEOM
    from .model import MatrixSpec, Model

MATRIX_KEYS = ("M", "K", "C")
FILE_SUFFIXES = (".npy", ".npz", ".mtx")


SPARSE_NPZ_KEYS = {"format", "shape", "data"}


def _read_file(path: Path, key: str) -> Any:
    suffix = path.suffix.lower()
    if suffix == ".npy":
        return np.load(path, allow_pickle=False)
    if suffix == ".npz":
        with np.load(path, allow_pickle=False) as archive:
            names = list(archive.keys())
            if SPARSE_NPZ_KEYS <= set(names):  # written by scipy.sparse.save_npz
                import scipy.sparse

                return scipy.sparse.load_npz(path).tocsr()
            if key in names:
                return archive[key]
            if len(names) == 1:
                return archive[names[0]]
            raise ValueError(f"the archive holds {', '.join(names)} but no array named '{key}'")
    if suffix == ".mtx":
        import scipy.io

        return scipy.io.mmread(str(path))
    raise ValueError(f"unknown matrix file type '{suffix}'; use {', '.join(FILE_SUFFIXES)}")


def read_matrix_spec(section: Any, harmonics: Any, params: Sequence[str],
                     coordinates: Sequence[str], source: str, base_dir: Path) -> "MatrixSpec":
    """Validate ``[matrices]`` and ``[[harmonic]]``; every problem in one ModelError."""
    from .model import Harmonic, MatrixSpec

    problems: list[Problem] = []
    if not isinstance(section, dict):
        raise ModelError(Problem("[matrices] must be a table with M, K and optionally C",
                                 source, "matrices"))
    if isinstance(section.get("harmonic"), list) and not harmonics:
        harmonics = section["harmonic"]
    matrices: dict[str, Any] = {}
    for key, value in section.items():
        if key == "harmonic":
            continue
        if key not in MATRIX_KEYS:
            problems.append(Problem(f"unknown key '{key}'; [matrices] takes M, K and C",
                                    source, "matrices", key))
            continue
        if isinstance(value, str) and value.lower().endswith(FILE_SUFFIXES):
            try:
                array = _read_file((base_dir / value), key)
            except Exception as exc:  # noqa: BLE001 - any unreadable file is the user's input
                problems.append(Problem(f"cannot read '{value}': {exc}", source, "matrices", key))
                continue
            if not (hasattr(array, "shape") and len(array.shape) == 2
                    and array.shape[0] == array.shape[1]):
                problems.append(Problem(f"'{value}' does not hold a square matrix", source,
                                        "matrices", key))
                continue
            if not (np.issubdtype(array.dtype, np.integer)
                    or np.issubdtype(array.dtype, np.floating)) or \
                    not np.all(np.isfinite(array.data if hasattr(array, "tocsr") else array)):
                problems.append(Problem(f"'{value}' holds non-real, non-numeric or non-finite "
                                        "entries", source, "matrices", key))
                continue
            matrices[key] = array.tocsr().astype(float) if hasattr(array, "tocsr") else \
                np.asarray(array, dtype=float)
        elif isinstance(value, list) and value and all(isinstance(r, list) for r in value):
            n = len(value)
            if any(len(row) != n for row in value):
                problems.append(Problem(f"{key} must be square: {n} rows of {n} entries",
                                        source, "matrices", key))
                continue
            rows = []
            for i, row in enumerate(value):
                parsed = []
                for j, entry in enumerate(row):
                    try:
                        parsed.append(_entry(entry, params, source, f"{key}[{i + 1}][{j + 1}]"))
                    except ModelError as exc:
                        problems.extend(exc.problems)
                rows.append(parsed)
            matrices[key] = rows
        else:
            problems.append(Problem(
                f"{key} must be an array of rows ([[1, 0], [0, 1]]) or a path to a "
                f"{'/'.join(FILE_SUFFIXES)} file", source, "matrices", key))
    for key in ("M", "K"):
        if key not in section:
            problems.append(Problem(f"{key} is missing", source, "matrices", key))
    sizes = {k: (m.shape[0] if hasattr(m, "shape") else len(m)) for k, m in matrices.items()}
    if len(set(sizes.values())) > 1:
        problems.append(Problem("M, K and C must have the same size; got " + ", ".join(
            f"{k}: {v}x{v}" for k, v in sizes.items()), source, "matrices"))
    n = sizes.get("M", 0)
    if coordinates and n and len(coordinates) != n:
        problems.append(Problem(f"{len(coordinates)} coordinates for {n}x{n} matrices",
                                source, "coordinates"))
    parsed_harmonics = []
    if not isinstance(harmonics, list):
        harmonics = [harmonics]
    for i, entry in enumerate(harmonics, start=1):
        where = f"harmonic {i}"
        if not isinstance(entry, dict) or "omega" not in entry:
            problems.append(Problem("a harmonic needs omega and F_S and/or F_C", source, where))
            continue
        unknown = set(entry) - {"omega", "F_S", "F_C"}
        if unknown:
            problems.append(Problem(f"unknown keys {sorted(unknown)}; a harmonic has omega, "
                                    "F_S, F_C", source, where))
        try:
            omega = _entry(entry["omega"], params, source, "omega", where)
            vectors = []
            for key in ("F_S", "F_C"):
                vec = entry.get(key, [0] * n)
                if not isinstance(vec, list) or (n and len(vec) != n):
                    raise ModelError(Problem(f"{key} must be a list of {n} entries", source,
                                             where, key))
                vectors.append(tuple(_entry(v, params, source, f"{key}[{j + 1}]", where)
                                     for j, v in enumerate(vec)))
            parsed_harmonics.append(Harmonic(omega, vectors[0], vectors[1]))
        except ModelError as exc:
            problems.extend(exc.problems)
    if problems:
        raise ModelError(problems)
    return MatrixSpec(M=matrices["M"], K=matrices["K"], C=matrices.get("C"),
                      harmonics=tuple(parsed_harmonics))


def _entry(value: Any, params: Sequence[str], source: str, key: str,
           section: str = "matrices") -> Expression:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ModelError(Problem(f"expected a number or an expression, got "
                                 f"{type(value).__name__}", source, section, key))
    try:
        return parse(value, allowed=params, file=source, section=section, key=key)
    except ExpressionError as exc:
        raise ModelError(list(exc.problems)) from None


# -- numeric evaluation (no sympy) -----------------------------------------------------------

class FloatOps:
    """Fold operations evaluating a parsed expression with numpy floats.

    Names resolve through ``values`` (parameter name -> float or array), so
    an expression is evaluated for a whole array of parameter values at once.

    Examples
    --------
    >>> import numpy as np
    >>> parse("k*(2 + x^2)").fold(FloatOps({"k": 2.0, "x": np.array([0.0, 1.0])}))
    array([4., 6.])
    """

    _FUNCS = {"sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin,
              "acos": np.arccos, "atan": np.arctan, "atan2": np.arctan2, "sinh": np.sinh,
              "cosh": np.cosh, "tanh": np.tanh, "exp": np.exp, "log": np.log, "sqrt": np.sqrt}

    def __init__(self, values: Any) -> None:
        self.values = values

    def num(self, text: str) -> float:
        return float(text)

    def name(self, name: str, primes: int) -> Any:
        if primes:
            return 0.0  # parameters are constants: their time derivatives vanish
        return self.values[name]

    def pi(self) -> float:
        return float(np.pi)

    def add(self, a: Any, b: Any) -> Any:
        return a + b

    def sub(self, a: Any, b: Any) -> Any:
        return a - b

    def mul(self, a: Any, b: Any) -> Any:
        return a * b

    def div(self, a: Any, b: Any) -> Any:
        return np.divide(a, b)

    def neg(self, a: Any) -> Any:
        return -a

    def pow(self, a: Any, b: Any) -> Any:
        return np.power(np.asarray(a, dtype=float), b)

    def call(self, func: str, args: list[Any]) -> Any:
        return self._FUNCS[func](*args)


def numeric_value(expression: Expression, values: Any) -> Any:
    """The float (or array) value of a parsed expression; ``values`` maps names to numbers."""
    with np.errstate(all="ignore"):
        return expression.fold(FloatOps(values))


@dataclass(frozen=True)
class MatrixSystem:
    """A matrix model with numbers: M, C, K dense (numpy) or sparse (scipy CSR).

    This is the numeric path for matrix models: nothing goes through sympy,
    so models with 10^4 - 10^5 coordinates stay cheap.  ``harmonics`` has the
    same meaning as in :class:`~resonant.numeric.NumericEOM`.
    """

    coordinates: tuple[str, ...]
    M: Any
    C: Any
    K: Any
    harmonics: tuple[NumericHarmonic, ...] = ()
    parameters: Mapping[str, float] = field(default_factory=dict)
    title: str = ""
    source: str = ""

    @property
    def n(self) -> int:
        return len(self.coordinates)

    @property
    def sparse(self) -> bool:
        return any(hasattr(a, "tocsr") for a in (self.M, self.C, self.K))

    def dense(self, symbolic: "LinearEOM | None" = None) -> NumericEOM:
        """The same system as a dense :class:`~resonant.numeric.NumericEOM`."""
        if self.n > DENSE_LIMIT:
            raise AnalysisError(
                f"the model has {self.n} coordinates; dense analyses (resonant solve) are "
                f"limited to {DENSE_LIMIT}: use `resonant modes --count K` or `resonant sweep`, "
                "which work with sparse matrices")
        return NumericEOM(
            coordinates=self.coordinates, M=_dense(self.M), C=_dense(self.C),
            K=_dense(self.K), harmonics=self.harmonics, harmonic=True, outputs={},
            parameters=self.parameters, title=self.title, source=self.source,
            symbolic=symbolic)


#: largest matrix model turned into dense matrices (solve, dense modes)
DENSE_LIMIT = 4000


def _dense(matrix: Any) -> np.ndarray:
    return matrix.toarray() if hasattr(matrix, "toarray") else np.asarray(matrix, dtype=float)


def matrix_values(model: "Model", key: str, values: Any) -> Any:
    """M, C or K of a matrix model for the parameter ``values``.

    File matrices are returned as read (dense array or CSR); inline matrices
    as an (n, n) array, or (N, n, n) when an entry depends on an array value.
    A missing C is an all-zero matrix of M's kind.
    """
    spec = model.matrices
    assert spec is not None
    matrix = getattr(spec, key)
    n = len(model.coordinates)
    if matrix is None:
        if hasattr(spec.M, "tocsr"):
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
    _check_finite(out, model, key)
    return out


def _check_finite(array: Any, model: "Model", key: str, section: str = "matrices") -> None:
    if not np.all(np.isfinite(array)):
        raise ModelError(Problem(f"{key} is not finite (or not real) for the given parameter "
                                 "values", model.source, section, key))


def harmonic_values(model: "Model", values: Any) -> list[tuple[Any, Any, Any]]:
    """``[(omega, F_S, F_C)]`` of a matrix model's harmonics for the parameter ``values``.

    omega may be an array (shape (N,)), F_S and F_C then (N, n) or (n,).
    """
    spec = model.matrices
    assert spec is not None
    out = []
    for j, h in enumerate(spec.harmonics, start=1):
        omega = np.asarray(numeric_value(h.omega, values), dtype=float)
        vectors = []
        for label, vector in (("F_S", h.F_S), ("F_C", h.F_C)):
            # plain numbers (the bulk of a large model's load vectors) skip the fold
            entries = [float(e.root.value) if type(e.root) is Num else numeric_value(e, values)
                       for e in vector]
            shape = np.broadcast_shapes(*(np.shape(v) for v in entries)) if entries else ()
            vec = np.empty((*shape, len(entries)))
            for i, v in enumerate(entries):
                vec[..., i] = v
            _check_finite(vec, model, label, f"harmonic {j}")
            vectors.append(vec)
        _check_finite(omega, model, "omega", f"harmonic {j}")
        out.append((omega, vectors[0], vectors[1]))
    return out


def numeric_system(model: "Model") -> MatrixSystem:
    """The matrix model with its parameter values substituted, without sympy."""
    from .numeric import NumericHarmonic

    values = dict(model.parameter_values)
    M, C, K = (matrix_values(model, key, values) for key in ("M", "C", "K"))
    merged: dict[float, list] = {}
    for j, (omega, f_s, f_c) in enumerate(harmonic_values(model, values), start=1):
        w, sign = float(omega), 1.0
        if w < 0:  # sin(-w t) = -sin(w t)
            w, sign = -w, -1.0
        if w == 0:
            f_s = np.zeros_like(f_s)
        key = next((k for k in merged if math.isclose(k, w, rel_tol=1e-12, abs_tol=0.0)), w)
        entry = merged.setdefault(key, [np.zeros(len(f_s)), np.zeros(len(f_c)), {}])
        entry[0] = entry[0] + sign * f_s
        entry[1] = entry[1] + f_c
        if np.any(f_s):
            entry[2][(f"harmonic{j}_s", 0)] = (sign, 0.0) if w else (0.0, 0.0)
        if np.any(f_c):
            entry[2][(f"harmonic{j}_c", 0)] = (0.0, 1.0)
    harmonics = tuple(NumericHarmonic(w, fs, fc, MappingProxyType(sig))
                      for w, (fs, fc, sig) in sorted(merged.items()))
    return MatrixSystem(model.coordinates, M, C, K, harmonics,
                        MappingProxyType(dict(model.parameter_values)), model.title,
                        model.source)


#: matrix models above this size use :func:`large_stationary` in ``resonant solve``
FAST_STATIONARY = 200


def _undamped_eigenvalues(M: Any, K: Any) -> np.ndarray:
    """omega^2 of K x = omega^2 M x, ascending, without eigenvectors.

    A diagonal M and a banded symmetric K use LAPACK's banded symmetric
    eigensolver on M^-1/2 K M^-1/2 (cost n b^2); anything else the dense one.
    """
    import scipy.linalg

    Md, Kd = _dense(M), _dense(K)
    diag = np.diag(Md)
    lower = 0
    rows, cols = np.nonzero(Kd)
    if rows.size:
        lower = int(np.abs(rows - cols).max())
    symmetric = np.allclose(Kd, Kd.T, rtol=1e-12, atol=1e-12 * np.abs(Kd).max(initial=0))
    if symmetric and np.all(diag > 0) and np.count_nonzero(Md - np.diag(diag)) == 0 and \
            lower + 1 <= max(8, Kd.shape[0] // 20):
        scale = 1 / np.sqrt(diag)
        S = Kd * scale[:, None] * scale[None, :]
        band = np.zeros((lower + 1, S.shape[0]))
        for d in range(lower + 1):  # lower band storage: band[d, j] = S[j + d, j]
            band[d, :S.shape[0] - d] = np.diagonal(S, -d)
        return scipy.linalg.eig_banded(band, lower=True, eigvals_only=True)
    try:
        return scipy.linalg.eigh(Kd, Md, eigvals_only=True)
    except (np.linalg.LinAlgError, ValueError):
        return np.sort(scipy.linalg.eigvals(Kd, Md).real)


def large_stationary(system: MatrixSystem, symbolic: "LinearEOM | None" = None) -> Any:
    """The stationary solution of a large matrix model (same result as ``stationary``).

    Exact like :func:`resonant.stationary.stationary`; only the bookkeeping
    around the solves is cheaper: the undamped eigenvalues by a banded
    eigensolver where possible, the state eigenvalues from them when
    C = a M + b K (roots of s^2 + (a + b w^2) s + w^2 = 0), sparse LU solves,
    and a cheap lower bound of the condition number instead of an SVD.
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    from .modes import _rayleigh
    from .stability import classify, frequencies_from_eigenvalues, state_eigenvalues
    from .stationary import (LOSS_CONDITION, SINGULAR_CONDITION, HarmonicResponse,
                             StationarySolution, _output_pairs, peak, resonance_warnings,
                             system_warnings)

    eom = system.dense(symbolic=symbolic)
    n = system.n
    M, C, K = (sp.csc_matrix(a) for a in (system.M, system.C, system.K))
    if np.any(np.asarray(abs(M).sum(axis=1)).ravel() == 0):
        row = int(np.argmax(np.asarray(abs(M).sum(axis=1)).ravel() == 0))
        raise AnalysisError(f"the mass matrix M is singular ({system.coordinates[row]} has no "
                            "inertia)")
    try:
        splu(M)
    except RuntimeError:
        raise AnalysisError("the mass matrix M is singular: every coordinate needs mass or "
                            "inertia") from None
    lam = _undamped_eigenvalues(eom.M, eom.K)
    omegas = frequencies_from_eigenvalues(lam)
    rayleigh = _rayleigh(M, C, K) if C.nnz else (0.0, 0.0)
    if rayleigh is not None:
        c = rayleigh[0] + rayleigh[1] * lam
        root = np.sqrt((c * c - 4 * lam).astype(complex))
        eigenvalues = np.concatenate([(-c + root) / 2, (-c - root) / 2])
    else:
        eigenvalues = state_eigenvalues(eom.M, eom.C, eom.K)
    stability = classify(eigenvalues)
    warnings = system_warnings(lam, stability) + resonance_warnings(
        [h.omega for h in system.harmonics], omegas)
    responses = []
    for h in system.harmonics:
        w = h.omega
        A = (K - w * w * M + 1j * w * C).tocsc()
        rhs = h.F_C - 1j * h.F_S
        try:
            X = splu(A).solve(rhs.astype(complex))
            norm_a = float(abs(A).sum(axis=1).max())
            condition = norm_a * np.abs(X).max() / max(np.abs(rhs).max(), 1e-300)
        except RuntimeError:
            X, condition = np.full(n, np.nan), math.inf
        if not np.all(np.isfinite(X)) or not condition <= SINGULAR_CONDITION:
            if w == 0:
                raise AnalysisError(
                    "a static load acts on a system with a zero-stiffness (rigid-body) mode: "
                    "the static deflection is unbounded; support the system or remove the "
                    "constant part of the excitation")
            raise AnalysisError(
                f"resonance: the excitation frequency {w:.6g} rad/s is a natural frequency and "
                "the system has no damping in that mode, so the stationary amplitude is "
                "unbounded; change the frequency or add damping")
        if condition > LOSS_CONDITION:
            warnings.append(f"ill-conditioned system at omega = {w:.6g} rad/s (condition number "
                            f"at least {condition:.2g}): about {int(math.log10(condition))} of "
                            "16 digits are lost")
        responses.append(HarmonicResponse(w, h.F_S, h.F_C, X.real.copy(), -X.imag.copy(),
                                          float(condition)))
    responses_t = tuple(responses)
    pairs = _output_pairs(eom, responses_t)
    freqs = [r.omega for r in responses_t]
    amplitudes = {name: peak(freqs, p) for name, p in pairs.items()}
    moving = [i for i, w in enumerate(freqs) if w > 0]
    phases = {}
    if len(moving) == 1:
        for name, p in pairs.items():
            L, N = p[moving[0]]
            if math.hypot(L, N) > 0:
                phases[name] = math.atan2(L, N)
    order = np.lexsort((eigenvalues.imag, np.abs(eigenvalues)))
    return StationarySolution(eom, omegas, eigenvalues[order], stability, responses_t,
                              MappingProxyType(pairs), MappingProxyType(amplitudes),
                              MappingProxyType(phases), tuple(warnings))


# -- the symbolic form ------------------------------------------------------------------------

def _to_sympy(matrix: Any, n: int) -> sympy.ImmutableMatrix:
    from .model import symbol

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


class _LazyMatrix:
    """A data descriptor: M, C, K of a matrix model become sympy matrices only when read."""

    def __init__(self, key: str) -> None:
        self.key = key
        self.slot = f"_symbolic_{key}"

    def __set__(self, obj: Any, value: Any) -> None:
        obj.__dict__[self.slot] = value

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        value = obj.__dict__.get(self.slot)
        if value is None:
            spec = obj.model.matrices
            value = _to_sympy(getattr(spec, self.key), len(obj.coordinates))
            obj.__dict__[self.slot] = value
        return value


def _matrix_eom_class() -> type:
    from .linearize import LinearEOM

    @dataclass(frozen=True, eq=False)
    class MatrixEOM(LinearEOM):
        """The equation of motion of a ``[matrices]`` model.

        M, C and K are built as sympy matrices only when read; :meth:`numeric`
        substitutes the parameters without sympy (see :class:`MatrixSystem`),
        so large file-based models are cheap.
        """

        def system(self, **overrides: float) -> MatrixSystem:
            """The numeric matrices (dense or sparse, as given) and harmonics."""
            model = self.model.with_parameters(**overrides) if overrides else self.model
            return numeric_system(model)

        def numeric(self, **overrides: float) -> NumericEOM:
            return self.system(**overrides).dense(symbolic=self)

        def stationary(self, **overrides: float) -> Any:
            """As :meth:`LinearEOM.stationary`; large models take a sparse path.

            Up to :data:`FAST_STATIONARY` coordinates this is exactly
            :func:`resonant.stationary.stationary`.  Above, the same result is
            computed without the dense 2n x 2n state eigenproblem when the
            damping is Rayleigh (C = a M + b K): eigenvalues from the undamped
            ones, sparse LU solves, the condition number estimated as
            ||A|| ||X|| / ||F|| (see :func:`large_stationary`).
            """
            system = self.system(**overrides)
            if system.n <= FAST_STATIONARY:
                from .stationary import stationary

                return stationary(system.dense(symbolic=self))
            return large_stationary(system, symbolic=self)

    for key in MATRIX_KEYS:
        setattr(MatrixEOM, key, _LazyMatrix(key))
    MatrixEOM.__module__ = __name__
    return MatrixEOM


_MATRIX_EOM: type | None = None


def linearize_matrices(model: "Model") -> "LinearEOM":
    """The equation of motion of a matrix model, in the same form as for energies.

    Each harmonic j becomes two internal signals ``sin(omega_j t)`` and
    ``cos(omega_j t)`` whose columns are F_S and F_C, so every later stage
    treats both kinds of model alike.  M, C and K are sympy matrices built on
    first use; ``numeric()`` never needs them.
    """
    global _MATRIX_EOM
    from .model import TIME, symbol

    if _MATRIX_EOM is None:
        _MATRIX_EOM = _matrix_eom_class()
    spec = model.matrices
    assert spec is not None
    n = len(model.coordinates)
    resolve = lambda name, p: symbol(name) if p == 0 else 0  # noqa: E731
    excitation, signals = {}, {}
    for j, h in enumerate(spec.harmonics):
        w = h.omega.to_sympy(resolve)
        for label, vector, fn in (("s", h.F_S, sympy.sin), ("c", h.F_C, sympy.cos)):
            nonzero = {i: e.to_sympy(resolve) for i, e in enumerate(vector)
                       if e.text.strip() not in ("0", "0.0")}
            nonzero = {i: v for i, v in nonzero.items() if v != 0}
            if nonzero:
                column = sympy.ImmutableSparseMatrix(n, 1, {(i, 0): v
                                                            for i, v in nonzero.items()})
                var = (f"harmonic{j + 1}_{label}", 0)
                excitation[var] = column
                signals[var] = fn(w * TIME)
    return _MATRIX_EOM(model=model, coordinates=model.coordinates, M=None, C=None, K=None,
                       excitation=MappingProxyType(excitation),
                       residual=sympy.ImmutableSparseMatrix(n, 1, {}),
                       outputs=MappingProxyType({}), given_signals=MappingProxyType(signals))


def is_matrix_eom(eom: Any) -> bool:
    """True for the equation of motion of a ``[matrices]`` model (has ``system()``)."""
    return _MATRIX_EOM is not None and isinstance(eom, _MATRIX_EOM)


__all__ = ["read_matrix_spec", "linearize_matrices", "numeric_system", "MatrixSystem",
           "FloatOps", "numeric_value", "matrix_values", "harmonic_values", "is_matrix_eom",
           "DENSE_LIMIT", "large_stationary", "FAST_STATIONARY"]
