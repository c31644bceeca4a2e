"""ANSYS ``.full`` files named in a model: ``K = "file.full"``, ``M = "file.full"``.

Read by ansys-mapdl-reader (``ansys.mapdl.reader``, the optional extra ``resonant[ansys]``;
imported when a model names a ``.full`` file): the stiffness and mass matrices of the
unconstrained DOFs, sorted by node and direction, and the DOF reference (``dofs =
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
import re
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


def _load(path: str) -> tuple[np.ndarray, Any, Any]:
    try:
        from ansys.mapdl import reader
    except ImportError:
        raise FileRefused("reading ANSYS .full files needs ansys-mapdl-reader (pip install "
                          "ansys-mapdl-reader, or pip install 'resonant[ansys]')") from None
    with open_regular_file(path, follow_symlinks=False,
                           max_bytes=limits.MAX_MATRIX_FILE_BYTES):
        pass
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            full = reader.read_binary(path)
            header = full._header
            rows = int(header["neqn"])
            if rows > limits.MAX_MATRIX_DIMENSION:
                raise FileRefused(f"its matrices have {rows} rows; matrices are limited to "
                                  f"{limits.MAX_MATRIX_DIMENSION}")
            dof_ref, k, m = full.load_km(sort=True)
    except FileRefused:
        raise
    except MemoryError:
        raise FileRefused("not enough memory to read it") from None
    except NotImplementedError:
        raise FileRefused("it holds a lumped or unsymmetric matrix, which "
                          "ansys-mapdl-reader does not read") from None
    except Exception:  # noqa: BLE001 - never echo the reader's message about the file
        raise FileRefused("it is truncated or not a valid ANSYS .full file") from None
    return np.asarray(dof_ref), k, m


def _symmetric(triangle: Matrix) -> Any:
    import scipy.sparse as sp

    upper = sp.triu(triangle, format="csr")
    return (upper + sp.triu(upper, 1).T).tocsr()


def read_full_matrix(path: str, name: str | None, key: str) -> Any:
    """The mass or stiffness matrix of a ``.full`` file as a symmetric CSR matrix.

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
        For a missing mass matrix, a damping matrix (not read), a damaged file.

    Examples
    --------
    >>> from ansys.mapdl.reader import examples  # doctest: +SKIP
    >>> read_full_matrix(examples.fullfile, None, "K").shape  # doctest: +SKIP
    (963, 963)
    >>> try:
    ...     read_full_matrix("model.full", "C", "C")
    ... except FileRefused as exc:
    ...     print(str(exc)[:43])
    ansys-mapdl-reader reads K and M of a .full
    """
    which = name or key
    if which == "C":
        raise FileRefused("ansys-mapdl-reader reads K and M of a .full file, not its damping "
                          'matrix; give C as Rayleigh damping (C = "alpha*M + beta*K") or '
                          "modal_damping")
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


__all__ = ["split_full", "read_full_matrix", "full_dof_names", "ANSYS_DIRECTIONS", "NO_MASS"]
