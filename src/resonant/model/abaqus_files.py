"""Abaqus matrix output named in a model: ``K = "job_STIF2.mtx"``, ``M = "job_MASS2.mtx"``.

``*MATRIX GENERATE`` with ``*MATRIX OUTPUT, FORMAT=MATRIX INPUT`` (Abaqus's default)
writes one text line per entry: row node, row DOF, column node, column DOF, value
(``1,1, 2,3, -1.5e3``), a symmetric matrix as its lower or upper triangle or in full.
resonant reads it with its own small parser (no library; numbers by numpy's C reader,
never ``eval``), strictly: five comma-separated fields per line, integer nodes and DOFs,
finite values, no entry twice, a full symmetric listing equal across the diagonal; lines
starting with ``**`` are comments.  The matrices of one model are assembled on the union
of their DOFs, sorted by node and DOF, and the coordinates named ``n12_uz`` (Abaqus's DOFs
1-6 are ux uy uz rx ry rz; others ``n12_d11``).  A file's first line tells it from a
Matrix Market ``.mtx``: those start with ``%%MatrixMarket``.

Examples
--------
>>> entries = parse_abaqus(b"** stiffness\\n1,1, 1,1, 2.0\\n2,1, 1,1, -1.0\\n2,1, 2,1, 2.0\\n",
...                        "K")
>>> entries.dofs.tolist(), entries.values.tolist()
([[1, 1], [2, 1], [2, 1], [1, 1], [1, 1], [2, 1]], [2.0, -1.0, 2.0])
"""

from __future__ import annotations

import io
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

import resonant.model.limits as limits

from .files import FileRefused

#: the first entry line of Abaqus's MATRIX INPUT format
_ENTRY = re.compile(rb"\s*-?\d+\s*,\s*\d+\s*,\s*-?\d+\s*,\s*\d+\s*,\s*[-+0-9.eEdD]+\s*")
DIRECTIONS = {1: "ux", 2: "uy", 3: "uz", 4: "rx", 5: "ry", 6: "rz"}


def looks_like_abaqus(head: bytes) -> bool:
    """Whether a file's first bytes are Abaqus matrix output (not Matrix Market).

    Parameters
    ----------
    head : bytes
        The first few hundred bytes.

    Returns
    -------
    bool

    Examples
    --------
    >>> looks_like_abaqus(b"1,1, 1,1, 1.0\\n"), looks_like_abaqus(b"%%MatrixMarket matrix")
    (True, False)
    """
    for line in head.split(b"\n")[:50]:
        if not line.strip() or line.lstrip().startswith(b"**"):
            continue
        return _ENTRY.fullmatch(line.rstrip(b"\r")) is not None
    return False


@dataclass(frozen=True)
class AbaqusEntries:
    """The entries of one Abaqus matrix file before assembly.

    Parameters
    ----------
    dofs : ndarray
        (2 E, 2) integers: the (node, DOF) of each entry's row, then of its column.
    values : ndarray
        (E,) the entries.
    key : str
        The matrix (M, K, C) it is for.

    Examples
    --------
    >>> parse_abaqus(b"1,1, 1,1, 4.0\\n", "M").values.tolist()
    [4.0]
    """

    dofs: np.ndarray
    values: np.ndarray
    key: str


def parse_abaqus(text: bytes, key: str) -> AbaqusEntries:
    """The entries of an Abaqus MATRIX INPUT file (strict; FileRefused names the problem).

    Parameters
    ----------
    text : bytes
        The file.
    key : str
        The matrix it is for.

    Returns
    -------
    AbaqusEntries

    Examples
    --------
    >>> try:
    ...     parse_abaqus(b"1,1, 1,1, x\\n", "K")
    ... except FileRefused as exc:
    ...     print(str(exc)[:40])
    it is not valid Abaqus matrix output: ev
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            table = np.loadtxt(io.BytesIO(text.replace(b"D", b"E").replace(b"d", b"e")),
                               delimiter=",", comments="**", ndmin=2, dtype=np.float64,
                               max_rows=limits.MAX_MATRIX_NONZEROS + 1, encoding="latin-1")
        except (ValueError, UnicodeError):
            raise FileRefused("it is not valid Abaqus matrix output: every line is row node, "
                              "row DOF, column node, column DOF, value (5 numbers separated "
                              "by commas)") from None
    if table.shape[0] == 0:
        raise FileRefused("it holds no matrix entry")
    if table.shape[1] != 5:
        raise FileRefused(f"a line holds {table.shape[1]} numbers; Abaqus matrix output has "
                          "5 (row node, row DOF, column node, column DOF, value)")
    if table.shape[0] > limits.MAX_MATRIX_NONZEROS:
        raise FileRefused(f"it holds more than {limits.MAX_MATRIX_NONZEROS} entries "
                          "(resonant.model.limits.MAX_MATRIX_NONZEROS)")
    index = table[:, :4]
    if np.any(index != np.round(index)) or np.any(np.abs(index) > 2**53):
        raise FileRefused("a node or DOF number is not an integer")
    dofs = index.astype(np.int64)
    if np.any(dofs[:, [1, 3]] < 1):
        raise FileRefused("a DOF number is below 1")
    values = np.ascontiguousarray(table[:, 4])
    if not np.all(np.isfinite(values)):
        raise FileRefused("it holds non-finite entries (inf or nan)")
    return AbaqusEntries(np.concatenate([dofs[:, :2], dofs[:, 2:]]), values, key)


def dof_name(node: int, dof: int) -> str:
    """The coordinate name of an Abaqus node and DOF.

    Parameters
    ----------
    node, dof : int

    Returns
    -------
    str

    Examples
    --------
    >>> dof_name(12, 3), dof_name(-4, 11)
    ('n12_uz', 'nm4_d11')
    """
    label = f"m{-node}" if node < 0 else str(node)
    if dof == 0:  # a Nastran scalar point (DMIG); Abaqus DOFs start at 1
        return f"n{label}"
    return f"n{label}_{DIRECTIONS.get(dof, f'd{dof}')}"


def assemble_abaqus(files: Mapping[str, AbaqusEntries]) -> tuple[dict[str, Any], list[str]]:
    """The matrices of Abaqus files on the union of their DOFs, and the coordinate names.

    Parameters
    ----------
    files : mapping
        key -> its entries.

    Returns
    -------
    tuple
        (key -> CSR matrix, names).

    Raises
    ------
    FileRefused
        For an entry listed twice or a symmetric matrix listed in full that is not
        symmetric (the message names the key).

    Examples
    --------
    >>> k = parse_abaqus(b"1,1, 1,1, 2.0\\n2,1, 1,1, -1.0\\n2,1, 2,1, 2.0\\n", "K")
    >>> m = parse_abaqus(b"2,1, 2,1, 1.0\\n", "M")
    >>> matrices, names = assemble_abaqus({"K": k, "M": m})
    >>> names, matrices["K"].toarray().tolist(), matrices["M"].toarray().tolist()
    (['n1_ux', 'n2_ux'], [[2.0, -1.0], [-1.0, 2.0]], [[0.0, 0.0], [0.0, 1.0]])
    """
    import scipy.sparse as sp

    every = np.unique(np.concatenate([f.dofs for f in files.values()]), axis=0)
    n = every.shape[0]
    if n > limits.MAX_MATRIX_DIMENSION:
        raise FileRefused(f"the files name {n} DOFs; matrices are limited to "
                          f"{limits.MAX_MATRIX_DIMENSION}")
    out = {}
    for key, entries in files.items():
        at = np.searchsorted(every[:, 0] * (2**31) + every[:, 1],
                             entries.dofs[:, 0] * (2**31) + entries.dofs[:, 1])
        count = entries.values.size
        rows, cols = at[:count], at[count:]
        pairs = rows * n + cols
        if np.unique(pairs).size != count:
            raise FileRefused(f"an entry of {key} is listed twice")
        lower, upper = rows > cols, rows < cols
        matrix = sp.coo_matrix((entries.values, (rows, cols)), shape=(n, n)).tocsr()
        if lower.any() and upper.any():  # the full square listed
            if abs(matrix - matrix.T).max() != 0:
                raise FileRefused(f"{key} is listed in full but is not symmetric (a "
                                  "symmetric matrix's entries are equal across the "
                                  "diagonal)")
        elif lower.any() or upper.any():  # one triangle: mirror it
            matrix = (matrix + sp.triu(matrix, 1).T + sp.tril(matrix, -1).T).tocsr()
        out[key] = matrix
    return out, [dof_name(int(node), int(dof)) for node, dof in every]


__all__ = ["looks_like_abaqus", "AbaqusEntries", "parse_abaqus", "assemble_abaqus",
           "dof_name", "DIRECTIONS"]
