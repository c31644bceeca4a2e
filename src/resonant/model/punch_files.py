"""Nastran DMIG entries of a punch (or bulk data) file: ``K = "model.pch:KAAX"``.

Read by pyYeti's DMIG reader (``pyyeti.nastran.bulk.rddmig``, the optional extra
``resonant[fe]``), which builds each matrix dense with its (grid, component) labels; the
matrices of one model are assembled on the union of their DOFs and the coordinates named
like those of every FE file (``n1042_uz``; a scalar point ``n10``).  Because the reader
is dense, a punch file is limited to :data:`MAX_PUNCH_LINES` lines, which bounds the
matrix to :data:`~resonant.model.limits.MAX_DENSE_ENTRIES` entries before it is read
(each line adds at most one DOF); write large matrices as OP4.

Examples
--------
>>> split_punch("model.pch:KAAX"), split_punch("k.op4:KAA") is None
(('model.pch', 'KAAX'), True)
"""

from __future__ import annotations

import contextlib
import io
import math
import re

import numpy as np

import resonant.model.limits as limits

from .abaqus_files import AbaqusEntries
from .files import FileRefused, open_regular_file, read_bounded
from .op4_files import numpy_print_options_kept

_REFERENCE = re.compile(r"(?P<path>.+\.(?:pch|bdf|dat))(?::(?P<name>[A-Za-z0-9_]{1,8}))",
                        re.IGNORECASE)
#: most lines of a punch file (pyYeti reads DMIG dense: n <= lines, n^2 within the limit)
MAX_PUNCH_LINES = math.isqrt(limits.MAX_DENSE_ENTRIES)


def split_punch(value: str) -> tuple[str, str] | None:
    """The path and the DMIG name of a punch-file reference (None: none).

    Parameters
    ----------
    value : str
        ``"file.pch:NAME"`` (also ``.bdf``, ``.dat``).

    Returns
    -------
    tuple or None

    Examples
    --------
    >>> split_punch("a.pch")
    """
    match = _REFERENCE.fullmatch(value)
    if match is None:
        return None
    return match.group("path"), match.group("name")


def read_dmig(path: str, name: str, key: str) -> AbaqusEntries:
    """The entries of one real DMIG matrix, labelled by (grid, component).

    Parameters
    ----------
    path : str
        A checked path.
    name : str
        The DMIG name (any case).
    key : str
        The ``[matrices]`` key it is for.

    Returns
    -------
    AbaqusEntries
        Assembled with the model's other FE entries by
        :func:`resonant.model.abaqus_files.assemble_abaqus`.

    Examples
    --------
    >>> read_dmig("tests/data/dmig/matrix_factory.pch", "IDENT", "M").values[:2].tolist()
    [1.0, 1.0]
    """
    try:
        with numpy_print_options_kept():
            from pyyeti.nastran import bulk
    except ImportError:
        raise FileRefused("reading DMIG entries needs pyYeti (pip install pyyeti, or pip "
                          "install 'resonant[fe]')") from None
    with open_regular_file(path, follow_symlinks=False,
                           max_bytes=limits.MAX_MATRIX_FILE_BYTES) as handle:
        text = read_bounded(handle, limits.MAX_MATRIX_FILE_BYTES)
    if text.count(b"\n") > MAX_PUNCH_LINES:
        raise FileRefused(f"it has more than {MAX_PUNCH_LINES} lines; DMIG matrices are read "
                          "dense, so punch files are limited to that many (write large "
                          "matrices as OUTPUT4)")
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            found = bulk.rddmig(path, [name.lower()])
    except MemoryError:
        raise FileRefused("not enough memory to read it") from None
    except Exception:  # noqa: BLE001 - never echo the reader's message about the file
        raise FileRefused("its DMIG entries are damaged (not the card layout Nastran "
                          "punches)") from None
    frame = found.get(name.lower()) if isinstance(found, dict) else None
    if frame is None:
        raise FileRefused(f"it holds no DMIG named {name.upper()}")
    values = np.asarray(frame.to_numpy())
    if np.iscomplexobj(values):
        raise FileRefused(f"DMIG {name.upper()} holds complex numbers; M, K and C are real")
    try:
        rows = np.array([[int(g), int(c)] for g, c in frame.index], dtype=np.int64)
        cols = np.array([[int(g), int(c)] for g, c in frame.columns], dtype=np.int64)
    except (TypeError, ValueError):
        raise FileRefused(f"DMIG {name.upper()} is not labelled by grid and component on "
                          "both sides (a square matrix)") from None
    values = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(values)):
        raise FileRefused(f"DMIG {name.upper()} holds non-finite entries (inf or nan)")
    i, j = np.nonzero(values)
    return AbaqusEntries(np.concatenate([rows[i], cols[j]]), values[i, j], key)


__all__ = ["split_punch", "read_dmig", "MAX_PUNCH_LINES"]
