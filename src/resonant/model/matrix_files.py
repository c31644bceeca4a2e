"""The ``[matrices]`` section and ``[[harmonic]]`` loads: validation and matrix files.

Matrices are inline arrays (numbers or expressions of the parameters) or
paths, relative to the model file, to ``.npy``, ``.npz`` (the array named
like the matrix, or the only one) or Matrix Market ``.mtx`` files.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ModelError, Problem
from ..expressions import Expression, ExpressionError, parse
from .types import Harmonic, MatrixSpec

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
                     coordinates: Sequence[str], source: str, base_dir: Path) -> MatrixSpec:
    """Validate ``[matrices]`` and ``[[harmonic]]``; every problem in one ModelError."""

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



__all__ = ["read_matrix_spec", "MATRIX_KEYS", "FILE_SUFFIXES"]
