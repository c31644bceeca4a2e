"""Nastran OUTPUT4 (``.op4``) matrices named in a model: ``M = "model.op4:MGG"``.

The file is read by resonant's own reader (:mod:`resonant.model.op4_records`): ASCII and
binary, dense and sparse (bigmat and non-bigmat), single and double precision, either byte
order, 4- or 8-byte integers; only the record headers are walked in Python, the values are
gathered in bulk (bit for bit what pyYeti's reader gives, several times faster on large
files: docs/performance-large.md). pyYeti (the optional extra ``resonant[fe]``) is used to
write OP4 files (:func:`write_op4`). resonant keeps the file policy of every matrix file
(docs/security.md): the path is resolved and checked by
:func:`resonant.model.matrix_files.resolve_matrix_path`, the file opened non-blocking and
refused unless regular and within :data:`~resonant.model.limits.MAX_MATRIX_FILE_BYTES`;
the directory of the file (names and sizes, from the headers) is checked against the
limits before a matrix is read; a matrix above
:data:`~resonant.model.limits.MAX_DENSE_ENTRIES` entries is read sparse.  Every failure
(a truncated record, a header that is no OP4 header) becomes one message naming the file,
the matrix and what is wrong, never a traceback.

Examples
--------
>>> split_reference("inboard.op4:KXX")
('inboard.op4', 'KXX')
>>> split_reference("stiffness.mtx") is None
True
"""

from __future__ import annotations

import contextlib
import os
import re
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

import resonant.model.limits as limits

from .files import FileRefused, open_regular_file, read_bounded
from .op4_records import Op4Entry, Op4Runs, forget_parsed_text, op4_entries, op4_runs

#: ``file.op4`` or ``file.op4:NAME`` (a Nastran matrix name: letters, digits, underscores)
_REFERENCE = re.compile(r"(?P<path>.+\.op4)(?::(?P<name>[A-Za-z0-9_]{1,64}))?", re.IGNORECASE)
#: Nastran's matrix types: 1 real single, 2 real double, 3 complex single, 4 complex double
_REAL_TYPES = (1, 2)


def split_reference(value: str) -> tuple[str, str | None] | None:
    """The path and the matrix name of an OP4 reference (None when it is none).

    Parameters
    ----------
    value : str
        ``"file.op4"`` or ``"file.op4:NAME"``.

    Returns
    -------
    tuple or None
        ``(path, name or None)``.

    Examples
    --------
    >>> split_reference("a/b.OP4")
    ('a/b.OP4', None)
    """
    match = _REFERENCE.fullmatch(value)
    if match is None:
        return None
    return match.group("path"), match.group("name")


@contextlib.contextmanager
def numpy_print_options_kept() -> Iterator[None]:
    """Keep numpy's print options across an import of pyYeti's ``nastran`` package, which
    sets them for the whole process (``legacy="1.13"``): reading a file must not change how
    the user's arrays print.

    Examples
    --------
    >>> with numpy_print_options_kept():
    ...     np.set_printoptions(precision=2)
    >>> np.get_printoptions()["precision"]
    8
    """
    options = np.get_printoptions()
    try:
        yield
    finally:
        np.set_printoptions(**options)


def _reader() -> Any:
    try:
        with numpy_print_options_kept():
            from pyyeti.nastran import op4
    except ImportError:
        raise FileRefused("reading Nastran OUTPUT4 files needs pyYeti (pip install pyyeti, "
                          "or pip install 'resonant[fe]')") from None
    return op4


def _file_bytes(path: str) -> bytes:
    """The whole file (regular, within the size limit), read once."""
    with open_regular_file(path, follow_symlinks=False,
                           max_bytes=limits.MAX_MATRIX_FILE_BYTES) as handle:
        try:
            return read_bounded(handle, limits.MAX_MATRIX_FILE_BYTES)
        except MemoryError:
            raise FileRefused("not enough memory to read it") from None


def _entries(data: bytes) -> list[Op4Entry]:
    entries = op4_entries(data)
    if not entries:
        raise FileRefused("it holds no matrix (an empty or damaged OUTPUT4 file)")
    return entries


def op4_directory(path: str) -> list[tuple[str, tuple[int, int], int]]:
    """The matrices of an OP4 file: (lower-case name, (rows, columns), Nastran type).

    Parameters
    ----------
    path : str
        A checked path (:func:`resonant.model.matrix_files.resolve_matrix_path`).

    Returns
    -------
    list of tuple

    Raises
    ------
    FileRefused
        With a message safe to show for every problem.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "k.op4")
    ...     write_op4(path, {"kaa": np.eye(2)})
    ...     op4_directory(path)
    [('kaa', (2, 2), 2)]
    """
    try:
        return [(e.name, (e.rows, e.columns), e.kind) for e in _entries(_file_bytes(path))]
    finally:
        forget_parsed_text()


def _choose(directory: Sequence[Op4Entry], name: str | None, key: str) -> Op4Entry:
    listed = ", ".join(e.name.upper() for e in directory[:12]) + \
        (", ..." if len(directory) > 12 else "")
    if name is None:
        if len(directory) == 1:
            return directory[0]
        raise FileRefused(f"it holds {len(directory)} matrices ({listed}); name the one for "
                          f"{key}: \"file.op4:NAME\"")
    found = [entry for entry in directory if entry.name == name.lower()]
    if not found:
        raise FileRefused(f"it holds no matrix named {name.upper()} (it holds {listed})")
    return found[0]


def read_op4_matrix(path: str, name: str | None, key: str, *, square: bool = True) -> Any:
    """One real matrix of an OP4 file: a float64 ndarray, or a CSR matrix when large.

    The file is read once, by resonant's own reader (:mod:`resonant.model.op4_records`:
    the record headers walked, the values gathered in bulk); pyYeti is not needed.

    Parameters
    ----------
    path : str
        A checked path.
    name : str or None
        The matrix name (any case); None for a file of one matrix.
    key : str
        What it is for (``M``, ``K``, ``C``, ``dofs``), for the messages.
    square : bool
        Whether it must be square (M, K, C).

    Returns
    -------
    ndarray or scipy.sparse.csr_matrix

    Raises
    ------
    FileRefused
        With a message safe to show.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = os.path.join(folder, "m.op4")
    ...     write_op4(path, {"maa": 2 * np.eye(2), "kaa": np.eye(2)})
    ...     read_op4_matrix(path, "MAA", "M").tolist()
    [[2.0, 0.0], [0.0, 2.0]]
    """
    try:
        return _read(path, name, key, square)
    finally:
        forget_parsed_text()


def _read(path: str, name: str | None, key: str, square: bool) -> Any:
    data = _file_bytes(path)
    entry = _choose(_entries(data), name, key)
    shown = entry.name.upper()
    rows, columns, kind = entry.rows, entry.columns, entry.kind
    if kind not in _REAL_TYPES:
        raise FileRefused(f"matrix {shown} holds complex numbers (Nastran type {kind}); M, K "
                          "and C must be real")
    if square and rows != columns:
        raise FileRefused(f"matrix {shown} is {rows}x{columns}, not a square matrix")
    if max(rows, columns) > limits.MAX_MATRIX_DIMENSION:
        raise FileRefused(f"matrix {shown} is {rows}x{columns}; matrices are limited to "
                          f"{limits.MAX_MATRIX_DIMENSION} rows "
                          "(resonant.model.limits.MAX_MATRIX_DIMENSION)")
    try:
        runs = op4_runs(data, entry)
    except FileRefused as exc:
        raise FileRefused(f"matrix {shown}: {exc}") from None
    except MemoryError:
        raise FileRefused(f"not enough memory to read matrix {shown}") from None
    del data
    return _assembled(entry, runs)


def _assembled(entry: Op4Entry, runs: Op4Runs) -> Any:
    """The matrix from its stored entries: dense up to ``MAX_DENSE_ENTRIES``, else CSR
    (checked against ``MAX_MATRIX_NONZEROS`` before it is built)."""
    import scipy.sparse as sp

    shown = entry.name.upper()
    if not np.all(np.isfinite(runs.values)):
        raise FileRefused(f"matrix {shown} holds non-finite entries (inf or nan)")
    if entry.rows * entry.columns <= limits.MAX_DENSE_ENTRIES:
        return runs.dense()
    if len(runs.values) > limits.MAX_MATRIX_NONZEROS:
        raise FileRefused(f"matrix {shown} has {len(runs.values)} stored entries; sparse "
                          f"matrices are limited to {limits.MAX_MATRIX_NONZEROS}")
    rows, columns, values = runs.coo()
    return sp.coo_matrix((values, (rows, columns)), shape=(entry.rows, entry.columns)).tocsr()


#: Nastran's components 1..6 as the directions of a coordinate's name
DIRECTIONS = {1: "ux", 2: "uy", 3: "uz", 4: "rx", 5: "ry", 6: "rz"}


def dof_names(pairs: np.ndarray) -> list[str]:
    """Coordinate names from (node, component) pairs: ``n1042_uz`` (component 0, a scalar
    point: ``n1042``).

    Parameters
    ----------
    pairs : ndarray
        (n, 2) integers: grid or scalar point id, Nastran component 0..6.

    Returns
    -------
    list of str

    Raises
    ------
    FileRefused
        For a pair that is no (node, component) or a DOF listed twice.

    Examples
    --------
    >>> dof_names(np.array([[1042, 3], [7, 0]]))
    ['n1042_uz', 'n7']
    """
    pairs = np.asarray(pairs)
    if pairs.ndim != 2 or pairs.shape[1] != 2 or pairs.shape[0] == 0:
        raise FileRefused("the DOF map must be a list of [node, component] pairs")
    if np.any(pairs != np.round(pairs)) or np.any(pairs[:, 0] < 0) or \
            np.any((pairs[:, 1] < 0) | (pairs[:, 1] > 6)):
        raise FileRefused("every DOF is [node, component] with a node id >= 0 and a Nastran "
                          "component 0 (scalar point) or 1..6 (ux uy uz rx ry rz)")
    names = [f"n{int(node)}_{DIRECTIONS[int(c)]}" if c else f"n{int(node)}"
             for node, c in pairs]
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise FileRefused(f"the DOF map lists {name} twice")
        seen.add(name)
    return names


def dof_of(name: str) -> tuple[int, int] | None:
    """The node and component a coordinate's name gives, the inverse of :func:`dof_names`:
    ``n1042_uz`` is (1042, 3), a scalar point ``n7`` is (7, 0); None for any other name.

    The components 1..6 (ux uy uz rx ry rz) are also the Universal File's direction codes
    (+X ... +RZ).

    Parameters
    ----------
    name : str

    Returns
    -------
    tuple of int or None

    Examples
    --------
    >>> dof_of("n1042_uz"), dof_of("n7"), dof_of("x1"), dof_of("n1_uw")
    ((1042, 3), (7, 0), None, None)
    """
    match = _DOF_NAME.fullmatch(name)
    if match is None:
        return None
    node, direction = match.groups()
    return int(node), _COMPONENTS[direction] if direction else 0


_DOF_NAME = re.compile(r"n([0-9]+)(?:_(ux|uy|uz|rx|ry|rz))?")
_COMPONENTS = {v: k for k, v in DIRECTIONS.items()}


def write_op4(path: str | os.PathLike[str], matrices: dict[str, Any], *,
              binary: bool = True, sparse: str = "auto") -> None:
    """Write matrices to an OP4 file through pyYeti (tests, ``resonant import``).

    Parameters
    ----------
    path : str or path
        The file to write.
    matrices : dict
        name -> dense or sparse matrix.
    binary : bool
        Binary (native byte order) or ASCII.
    sparse : {"auto", "dense", "bigmat", "nonbigmat"}
        The record layout ("auto": dense for ndarrays, bigmat for sparse matrices).

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     write_op4(os.path.join(folder, "x.op4"), {"kaa": np.eye(2)}, binary=False)
    """
    op4 = _reader()
    op4.write(str(Path(path)), matrices, binary=binary, sparse=sparse)


__all__ = ["split_reference", "op4_directory", "read_op4_matrix", "dof_names", "dof_of",
           "write_op4", "DIRECTIONS"]
