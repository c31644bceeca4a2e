"""Matrix models: ``[matrices]`` with M, K, optional C and ``[[harmonic]]`` loads.

Matrices are inline arrays (numbers or expressions of the parameters) or
paths, relative to the model file, to ``.npy``, ``.npz`` (the array named
like the matrix, or the only one) or Matrix Market ``.mtx`` files.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy

from .errors import ModelError, Problem
from .expr import Expression, ExpressionError, parse

if TYPE_CHECKING:  # pragma: no cover
    from .linearize import LinearEOM
    from .model import MatrixSpec, Model

MATRIX_KEYS = ("M", "K", "C")
FILE_SUFFIXES = (".npy", ".npz", ".mtx")


def _read_file(path: Path, key: str) -> Any:
    suffix = path.suffix.lower()
    if suffix == ".npy":
        return np.load(path, allow_pickle=False)
    if suffix == ".npz":
        with np.load(path, allow_pickle=False) as archive:
            names = list(archive.keys())
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
            except (OSError, ValueError) as exc:
                problems.append(Problem(f"cannot read '{value}': {exc}", source, "matrices", key))
                continue
            if not (hasattr(array, "shape") and len(array.shape) == 2
                    and array.shape[0] == array.shape[1]):
                problems.append(Problem(f"'{value}' does not hold a square matrix", source,
                                        "matrices", key))
                continue
            if not np.issubdtype(array.dtype, np.number) or \
                    not np.all(np.isfinite(array.data if hasattr(array, "tocsr") else array)):
                problems.append(Problem(f"'{value}' holds non-numeric or non-finite entries",
                                        source, "matrices", key))
                continue
            matrices[key] = array.tocsr() if hasattr(array, "tocsr") else np.asarray(
                array, dtype=float)
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


def _to_sympy(matrix: Any, n: int) -> sympy.ImmutableMatrix:
    from .model import symbol

    if matrix is None:
        return sympy.ImmutableMatrix.zeros(n, n)
    if hasattr(matrix, "toarray"):
        matrix = matrix.toarray()
    if isinstance(matrix, np.ndarray):
        return sympy.ImmutableMatrix(matrix.shape[0], matrix.shape[1],
                                     [sympy.Float(float(v)) for v in matrix.ravel()])
    return sympy.ImmutableMatrix([[e.to_sympy(lambda name, p: symbol(name) if p == 0 else 0)
                                   for e in row] for row in matrix])


def linearize_matrices(model: "Model") -> "LinearEOM":
    """The equation of motion of a matrix model, in the same form as for energies.

    Each harmonic j becomes two internal signals ``sin(omega_j t)`` and
    ``cos(omega_j t)`` whose columns are F_S and F_C, so every later stage
    treats both kinds of model alike.
    """
    from .linearize import LinearEOM
    from .model import TIME, symbol

    spec = model.matrices
    assert spec is not None
    n = len(model.coordinates)
    M, K, C = _to_sympy(spec.M, n), _to_sympy(spec.K, n), _to_sympy(spec.C, n)
    resolve = lambda name, p: symbol(name) if p == 0 else 0  # noqa: E731
    excitation, signals = {}, {}
    for j, h in enumerate(spec.harmonics):
        w = h.omega.to_sympy(resolve)
        for label, vector, fn in (("s", h.F_S, sympy.sin), ("c", h.F_C, sympy.cos)):
            column = sympy.ImmutableMatrix([e.to_sympy(resolve) for e in vector])
            if any(e != 0 for e in column):
                var = (f"harmonic{j + 1}_{label}", 0)
                excitation[var] = column
                signals[var] = fn(w * TIME)
    return LinearEOM(model=model, coordinates=model.coordinates, M=M, C=C, K=K,
                     excitation=MappingProxyType(excitation),
                     residual=sympy.ImmutableMatrix.zeros(n, 1),
                     outputs=MappingProxyType({}), given_signals=MappingProxyType(signals))


__all__ = ["read_matrix_spec", "linearize_matrices"]
