"""ANSYS ``.full`` files named in a model: ``K = "file.full"``, ``M = "file.full"``.

Read by ansys-mapdl-reader (``ansys.mapdl.reader``, the optional extra ``resonant[ansys]``;
imported when a model names a ``.full`` file): the stiffness and mass matrices of the
unconstrained DOFs, sorted by node and direction, the damping matrix where the file holds
one (``C = "file.full"``: the library's record reader at the file's damping pointer, the
same layout as K), and the DOF reference (``dofs =
"file.full"`` names the coordinates ``n12_ux``).  The file stores one triangle of each
symmetric matrix; resonant adds the other.  A ``.full`` file of a static analysis holds
no mass matrix: that is an error naming the file and the analysis types that write one.
The file policy and the limits of every matrix file apply (the size from the file's
header before the matrices are read).

Examples
--------
>>> split_full("model.full:M"), split_full("model.full"), split_full("m.op4") is None
(('model.full', 'M'), ('model.full', None), True)
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

import resonant.model.limits as limits

from ..arrays import Matrix
from .files import FileRefused, open_regular_file

_REFERENCE = re.compile(r"(?P<path>.+\.full)(?::(?P<name>[MKC]))?", re.IGNORECASE)
#: ANSYS's structural DOFs in the order of the DOF reference (0-based)
ANSYS_DIRECTIONS = ("ux", "uy", "uz", "rx", "ry", "rz")
NO_MASS = ("it holds no mass matrix: ANSYS writes one to the .full file only in a modal, "
           "harmonic or transient analysis (ANTYPE,MODAL with WRFULL), never in a static "
           "one")
NO_DAMPING = ("it holds no damping matrix (ANSYS writes one only for a model with damping "
              "elements or damping specified, in a modal, harmonic or transient analysis); "
              'give C as Rayleigh damping (C = "alpha*M + beta*K") or modal_damping')


def split_full(value: str) -> tuple[str, str | None] | None:
    """The path and the matrix (M, K or C) of a ``.full`` reference (None: none).

    Parameters
    ----------
    value : str
        ``"file.full"`` or ``"file.full:M"``.

    Returns
    -------
    tuple or None

    Examples
    --------
    >>> split_full("a.FULL:k")
    ('a.FULL', 'K')
    """
    match = _REFERENCE.fullmatch(value)
    if match is None:
        return None
    name = match.group("name")
    return match.group("path"), name.upper() if name else None


def _reader_module() -> Any:
    """ansys-mapdl-reader, or a refusal that says how to install it."""
    try:
        from ansys.mapdl import reader
    except ImportError:
        raise FileRefused("reading ANSYS .full files needs ansys-mapdl-reader (pip install "
                          "ansys-mapdl-reader, or pip install 'resonant[ansys]')") from None
    return reader


@contextlib.contextmanager
def _reader_failures_refused() -> Iterator[None]:
    """The reader's failures as `FileRefused`, its printing silenced: never its own message
    about the file."""
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            yield
    except FileRefused:
        raise
    except MemoryError:
        raise FileRefused("not enough memory to read it") from None
    except NotImplementedError:
        raise FileRefused("it holds a lumped or unsymmetric matrix, which "
                          "ansys-mapdl-reader does not read") from None
    except Exception:  # noqa: BLE001 - never echo the reader's message about the file
        raise FileRefused("it is truncated or not a valid ANSYS .full file") from None


def _opened(path: str) -> Any:
    """The ``.full`` file opened by ansys-mapdl-reader, its order within the limits."""
    reader = _reader_module()
    with open_regular_file(path, follow_symlinks=False,
                           max_bytes=limits.MAX_MATRIX_FILE_BYTES):
        pass
    with _reader_failures_refused():
        full = reader.read_binary(path)
        rows = int(full._header["neqn"])
        pointers = {key[3:]: int(value) for key, value in full._header.items()
                    if key.startswith("ptr") and key[-1] not in "lh"}
    _within_the_file(path, pointers)
    if rows > limits.MAX_MATRIX_DIMENSION:
        raise FileRefused(f"its matrices have {rows} rows; matrices are limited to "
                          f"{limits.MAX_MATRIX_DIMENSION}")
    return full


def _within_the_file(path: str, pointers: Mapping[str, int]) -> None:
    """Refuse a file that ends before the records its header points to (words of 4 bytes;
    the data end at ``ptrEND``): ansys-mapdl-reader's compiled reader, given one, aborted
    the process (``std::bad_alloc``) instead of raising."""
    size = os.path.getsize(path)
    end = pointers.get("END", 0)
    beyond = {name: at for name, at in pointers.items() if at < 0 or 4 * at > size}
    if end <= 0 or beyond:
        name, at = next(iter(beyond.items())) if beyond else ("END", end)
        raise FileRefused(f"it is truncated or not a valid ANSYS .full file (its header "
                          f"puts the {name} record at byte {4 * at}, the file has {size} "
                          "bytes)")


def _load(path: str) -> tuple[np.ndarray, Any, Any]:
    full = _opened(path)
    with _reader_failures_refused():
        dof_ref, k, m = full.load_km(sort=True)
    return np.asarray(dof_ref), k, m


def _damping_entries(path: str, header: Mapping[str, int]
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, int] | None:
    """The stored triangle of the damping matrix (rows, columns, values, order), None when
    the file holds none.

    ansys-mapdl-reader's ``load_km`` reads K and M only. The damping matrix is stored like
    them (fdfull.inc: DMP "same format as the stiffness matrix", at ``ptrDMP``, ``ntermD``
    terms), so it is read by the library's own record reader (``read_array``), its
    constrained DOFs removed and its rows put in the node and direction order of the DOF
    reference, as ``load_km(sort=True)`` does for K and M."""
    from ansys.mapdl.reader import _binary_reader
    from ansys.mapdl.reader.common import read_table, two_ints_to_long

    terms = two_ints_to_long(header["ntermDl"], header["ntermDh"])
    pointer = header["ptrDMP"]
    if not terms or not pointer:
        return None
    order = int(header["neqn"])
    with open(path, "rb") as handle:
        for _ in range(3):  # the standard header, the full header, the number of DOFs
            read_table(handle, skip=True)
        equivalence = read_table(handle, cython=True)
        handle.seek(header["ptrDOF"] * 4)
        per_node = read_table(handle, cython=True)
        constrained = read_table(handle, cython=True)
    rows, columns, values = _binary_reader.read_array(path, pointer, terms, order,
                                                      constrained)[:3]
    removed = np.flatnonzero(np.asarray(constrained) < 0)
    if removed.size:
        kept = ~(np.isin(rows, removed) | np.isin(columns, removed))
        rows, columns, values = rows[kept], columns[kept], values[kept]
    index = _binary_reader.sort_nodal_eqlv(order, equivalence, per_node)[1]
    rows, columns = np.sort(np.vstack((index[rows], index[columns])), 0)
    return rows, columns, np.asarray(values, dtype=float), order


def _load_damping(path: str) -> Any:
    """The damping matrix of a ``.full`` file as stored (one triangle), None when absent."""
    import scipy.sparse as sp

    full = _opened(path)
    with _reader_failures_refused():
        entries = _damping_entries(path, full._header)
    if entries is None:
        return None
    rows, columns, values, order = entries
    return sp.coo_matrix((values, (rows, columns)), shape=(order, order)).tocsr()


def has_damping(path: str) -> bool:
    """Whether a ``.full`` file holds a damping matrix (from its header; False for a file
    that cannot be read, which the load that follows reports).

    Parameters
    ----------
    path : str
        A checked path.

    Returns
    -------
    bool

    Examples
    --------
    >>> from ansys.mapdl.reader import examples  # doctest: +SKIP
    >>> has_damping(examples.fullfile)  # doctest: +SKIP
    False
    """
    try:
        header = _opened(path)._header
    except Exception:  # noqa: BLE001 - the load that follows names what is wrong
        return False
    return bool(header["ptrDMP"]) and bool(header["ntermDl"] or header["ntermDh"])


def _symmetric(triangle: Matrix) -> Any:
    import scipy.sparse as sp

    upper = sp.triu(triangle, format="csr")
    return (upper + sp.triu(upper, 1).T).tocsr()


def read_full_matrix(path: str, name: str | None, key: str) -> Any:
    """The mass, stiffness or damping matrix of a ``.full`` file as a symmetric CSR matrix.

    Parameters
    ----------
    path : str
        A checked path.
    name : {"M", "K", "C"} or None
        The matrix (None: the one ``key`` names).
    key : str
        The ``[matrices]`` key it is for.

    Returns
    -------
    scipy.sparse.csr_matrix

    Raises
    ------
    FileRefused
        For a missing mass or damping matrix, a damaged file.

    Examples
    --------
    >>> from ansys.mapdl.reader import examples  # doctest: +SKIP
    >>> read_full_matrix(examples.fullfile, None, "K").shape  # doctest: +SKIP
    (963, 963)
    >>> read_full_matrix(examples.fullfile, "C", "C")  # doctest: +SKIP
    Traceback (most recent call last):
    FileRefused: it holds no damping matrix (ANSYS writes one only for a model with ...
    """
    which = name or key
    if which == "C":
        matrix = _load_damping(path)
        if matrix is None:
            raise FileRefused(NO_DAMPING)
    else:
        _, k, m = _load(path)
        matrix = m if which == "M" else k
    if which == "M" and (matrix is None or matrix.nnz == 0 or not abs(matrix).max() > 0):
        raise FileRefused(NO_MASS)
    out = _symmetric(matrix)
    if not np.all(np.isfinite(out.data)):
        raise FileRefused(f"its {which} matrix holds non-finite entries (inf or nan)")
    return out


def full_dof_names(path: str) -> list[str]:
    """The coordinate names of a ``.full`` file's DOF reference: ``n12_ux``.

    Parameters
    ----------
    path : str
        A checked path.

    Returns
    -------
    list of str

    Examples
    --------
    >>> from ansys.mapdl.reader import examples  # doctest: +SKIP
    >>> full_dof_names(examples.fullfile)[:4]  # doctest: +SKIP
    ['n1_ux', 'n1_uy', 'n1_uz', 'n2_ux']
    """
    dof_ref, _, _ = _load(path)
    if dof_ref.ndim != 2 or dof_ref.shape[1] != 2 or np.any(dof_ref[:, 1] < 0) or \
            np.any(dof_ref[:, 1] >= len(ANSYS_DIRECTIONS)):
        raise FileRefused("its DOF reference holds DOFs other than UX UY UZ ROTX ROTY ROTZ")
    return [f"n{int(node)}_{ANSYS_DIRECTIONS[int(d)]}" for node, d in dof_ref]


__all__ = ["split_full", "read_full_matrix", "full_dof_names", "has_damping",
           "ANSYS_DIRECTIONS", "NO_MASS", "NO_DAMPING"]
