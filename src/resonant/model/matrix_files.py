"""The ``[matrices]`` section and ``[[harmonic]]`` loads: validation and matrix files.

Matrices are inline arrays (numbers or expressions of the parameters) or
paths, relative to the model file, to ``.npy``, ``.npz`` (the array named
like the matrix, or the only one, or a sparse matrix in scipy's
``save_npz`` layout) or Matrix Market ``.mtx`` files.

Matrix files are untrusted input (docs/security.md):

* only files inside the model file's folder (symbolic links resolved) or inside
  a directory the user allows (``allow_paths``, ``--allow-path DIR``) are read;
  a path outside gets the same message whether or not it exists;
* only regular files are opened (``O_NONBLOCK``, then ``fstat``): a FIFO or a
  device never blocks or streams;
* sizes come from the headers (``.npy`` header, zip directory, Matrix Market
  size line) and are checked against :mod:`resonant.model.limits` before
  anything is allocated or decompressed; reads are bounded;
* only real integer or floating-point arrays are accepted (never pickles), and a
  sparse matrix's structure (``indptr``, ``indices``, ``row``, ``col``) is
  validated before scipy sees it;
* error messages name the problem, never archive member names or operating
  system errors about other paths.
"""

from __future__ import annotations

import io
import math
import os
import re
import struct
import warnings
import zipfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

import resonant.model.inline_matrices as inline_matrices
import resonant.model.limits as limits

from ..arrays import Matrix
from ..errors import ModelError, Problem
from ..expressions import Expression, ExpressionError, parse
from ..expressions.numeric import numeric_value
from ..modal import mass_normalized_modes
from .abaqus_files import AbaqusEntries, assemble_abaqus, looks_like_abaqus, parse_abaqus
from .files import FileRefused, open_regular_file, read_bounded
from .full_files import full_dof_names, read_full_matrix, split_full
from .matrix_spec import Harmonic, MatrixSpec
from .op4_files import dof_names, read_op4_matrix, split_reference
from .punch_files import read_dmig, split_punch
from .uset_map import UsetMap, read_usetprt, uset_from_table, uset_names

if TYPE_CHECKING:
    import pyarrow

MATRIX_KEYS = ("M", "K", "C", "G")
MODAL_KEY = "modal_damping"
#: the DOF map of matrices read from finite-element files: [node, component] per row
DOFS_KEY = "dofs"
#: drop the coordinates with neither mass nor stiffness (unconnected DOFs of an FE file)
DROP_KEY = "drop_unconnected"
#: the key naming the speed parameter that multiplies the gyroscopic matrix G
SPEED_KEY = "speed"
MODAL_DAMPING_MAX_DOF = 3000
"""Largest model modal damping builds C for: C = M Phi diag(2 zeta omega) Phi^T M is dense
(n^2 numbers) and needs the dense generalized eigenproblem; beyond this give C explicitly
or as Rayleigh damping."""
FILE_SUFFIXES = (".npy", ".npz", ".mtx")
#: finite-element files, each with the name of its matrix: ``"model.op4:KAA"``
FE_SUFFIXES = (".op4", ".full", ".pch")


def is_file_reference(value: str) -> bool:
    """Whether a ``[matrices]`` string names a matrix file (not Rayleigh damping).

    Examples
    --------
    >>> is_file_reference("k.mtx"), is_file_reference("m.op4:MGG"), is_file_reference("0.1*K")
    (True, True, False)
    """
    return value.lower().endswith(FILE_SUFFIXES) or split_reference(value) is not None or \
        split_full(value) is not None or split_punch(value) is not None
SPARSE_NPZ_KEYS = {"format", "shape", "data"}
SPARSE_FORMATS = ("csr", "csc", "coo")
OUTSIDE = ("the path leads outside the model's folder; matrix files are read only from the "
           "folder of the model file and its subfolders (allow another directory with "
           "--allow-path DIR, or allow_paths=[...] in load/loads)")


def resolve_matrix_path(value: str, base_dir: Path | None,
                        allow_paths: Sequence[str | os.PathLike[str]] = ()) -> str:
    """The real path of a matrix file named in a model, if the file policy allows it.

    The path, joined to the model's folder, must lie inside the folder or an
    allowed directory both as written (no ``..`` escape, no absolute path
    elsewhere) and with every symbolic link resolved.  Nothing outside is
    touched beyond resolving links, and the message does not depend on
    whether an outside path exists.
    """
    if base_dir is None:
        raise FileRefused("the model was given as text, so there is no folder to read matrix "
                          "files from; use load(path), or loads(text, base_dir=folder)")
    if "\x00" in value:
        raise FileRefused("the path contains a NUL character")
    roots = [os.path.abspath(base_dir), *(os.path.abspath(p) for p in allow_paths)]
    target = os.path.abspath(os.path.join(roots[0], value))
    if not any(_inside(target, root) for root in roots):
        raise FileRefused(OUTSIDE)
    real = os.path.realpath(target)
    if not any(_inside(real, os.path.realpath(root)) for root in roots):
        raise FileRefused(OUTSIDE)
    return real


#: file types of a load vector (``F_S``/``F_C``)
VECTOR_SUFFIXES = (".npy", ".mtx")


def read_vector_file(value: str, n: int, base_dir: Path | None,
                     allow_paths: Sequence[str | os.PathLike[str]] = ()) -> np.ndarray:
    """The load vector of n entries in file ``value`` (``.npy``: shape (n,) or (n, 1);
    ``.mtx``: an n x 1 Matrix Market array or coordinate file).

    Raises :class:`FileRefused` with a message safe to show for every problem.
    """
    suffix = os.path.splitext(value)[1].lower()
    if suffix not in VECTOR_SUFFIXES:
        raise FileRefused(f"unknown vector file type; use {', '.join(VECTOR_SUFFIXES)}")
    path = resolve_matrix_path(value, base_dir, allow_paths)
    with open_regular_file(path, follow_symlinks=False,
                           max_bytes=limits.MAX_MATRIX_FILE_BYTES) as handle:
        size = os.fstat(handle.fileno()).st_size
        try:
            if suffix == ".npy":
                array = _read_npy(handle, "the vector", size,
                                  max_entries=limits.MAX_MATRIX_DIMENSION)
                if array.ndim == 2 and array.shape[1] == 1:
                    array = array[:, 0]
                if array.ndim != 1:
                    raise FileRefused(f"the vector has shape {array.shape}; a load vector "
                                      "has shape (n,) or (n, 1)")
            else:
                array = _read_mtx_vector(handle, size)
            vector = _dense(array, "the vector")
        except FileRefused:
            raise
        except MemoryError:
            raise FileRefused("not enough memory to read it") from None
        except Exception:  # noqa: BLE001 - never echo a library's message about the file
            raise FileRefused(f"it is damaged or not a valid {suffix} file") from None
    if vector.shape[0] != n:
        raise FileRefused(f"it holds {vector.shape[0]} entries; the matrices have {n} "
                          "coordinates")
    return vector


def _read_mtx_vector(handle: IO[bytes], size: int) -> np.ndarray:
    """An n x 1 Matrix Market file (array or coordinate, general) as a vector."""
    text = handle.read(size + 1)
    end = text.find(b"\n")
    layout, _, symmetry = _mtx_banner(text if end < 0 else text[:end])
    if symmetry != "general":
        raise FileRefused("a load vector must be a 'general' Matrix Market file")
    fields, offset = _mtx_size_line(text)
    coordinate = layout == "coordinate"
    try:
        numbers = [int(f) for f in fields]
    except ValueError:
        raise FileRefused(f"{_MTX_INVALID}: the size line holds something other than "
                          "integers") from None
    if len(numbers) != (3 if coordinate else 2) or numbers[1] != 1:
        raise FileRefused("a load vector must be n x 1 (size line 'n 1' or 'n 1 entries')")
    n = numbers[0]
    if not 0 < n <= limits.MAX_MATRIX_DIMENSION:
        raise FileRefused(f"the vector has {n} entries; at most "
                          f"{limits.MAX_MATRIX_DIMENSION}")
    if not coordinate:
        return _mtx_numbers(text[offset:], n, 1)[:, 0]
    entries = numbers[2]
    if not 0 <= entries <= n:
        raise FileRefused(f"{_MTX_INVALID}: {entries} entries for a vector of {n}")
    values = _mtx_numbers(text[offset:], entries, 3)
    rows, columns = values[:, 0], values[:, 1]
    if np.any(rows != np.round(rows)) or np.any((rows < 1) | (rows > n)) or \
            np.any(columns != 1):
        raise FileRefused(f"{_MTX_INVALID}: an entry lies outside the {n} x 1 vector")
    out = np.zeros(n)
    np.add.at(out, rows.astype(np.int64) - 1, values[:, 2])
    return out


def _inside(path: str, root: str) -> bool:
    try:
        return os.path.commonpath([path, root]) == root
    except ValueError:  # different drives
        return False


# -- reading matrix files ----------------------------------------------------------------------

def read_matrix_file(value: str, key: str, base_dir: Path | None,
                     allow_paths: Sequence[str | os.PathLike[str]] = ()) -> Any:
    """The matrix in file ``value``: a float64 ndarray or a scipy CSR matrix.

    Raises :class:`FileRefused` with a message safe to show for every problem.
    """
    reference = split_reference(value)
    if reference is not None:
        return read_op4_matrix(resolve_matrix_path(reference[0], base_dir, allow_paths),
                               reference[1], key)
    punch = split_punch(value)
    if punch is not None:
        return read_dmig(resolve_matrix_path(punch[0], base_dir, allow_paths), punch[1], key)
    full = split_full(value)
    if full is not None:
        return read_full_matrix(resolve_matrix_path(full[0], base_dir, allow_paths),
                                full[1], key)
    suffix = os.path.splitext(value)[1].lower()
    if suffix not in FILE_SUFFIXES:
        raise FileRefused("unknown matrix file type; use "
                          f"{', '.join(FILE_SUFFIXES + FE_SUFFIXES)}")
    path = resolve_matrix_path(value, base_dir, allow_paths)
    with open_regular_file(path, follow_symlinks=False,
                           max_bytes=limits.MAX_MATRIX_FILE_BYTES) as handle:
        size = os.fstat(handle.fileno()).st_size
        try:
            if suffix == ".npy":
                return _dense(_read_npy(handle, "the array", size, matrix=True))
            if suffix == ".npz":
                return _read_npz(handle, size, key)
            head = handle.read(4096)
            handle.seek(0)
            if looks_like_abaqus(head):
                return parse_abaqus(handle.read(size + 1), key)
            return _read_mtx(handle, size)
        except FileRefused:
            raise
        except MemoryError:
            raise FileRefused("not enough memory to read it") from None
        except Exception:  # noqa: BLE001 - never echo a library's message about the file
            raise FileRefused(f"it is damaged or not a valid {suffix} file") from None


def _read_exact(handle: IO[bytes], count: int, what: str) -> bytes:
    data = handle.read(count)
    if len(data) != count:
        raise FileRefused(f"{what} is truncated")
    return data


def _check_dtype(dtype: np.dtype, what: str, text: bool = False) -> None:
    kind = dtype.kind
    if dtype.hasobject:
        reason = "holds Python objects (pickled data), which resonant never loads"
    elif dtype.names is not None or dtype.subdtype is not None or kind == "V":
        reason = "holds a structured (record) array; save a plain 2-D array of numbers"
    elif kind == "c":
        reason = "holds complex numbers; M, K and C must be real"
    elif kind in "SU" and text and dtype.itemsize:
        return
    elif kind in "SU":
        reason = "holds text, not numbers"
    elif kind == "f" and dtype.itemsize > 8:
        reason = "holds long-double (float128) numbers; save it as float64"
    elif kind == "b":
        reason = "holds booleans, not numbers"
    elif kind in "iuf" and dtype.itemsize:
        return
    else:
        reason = f"holds {dtype.name} values; save integers or floating-point numbers"
    raise FileRefused(f"{what} {reason}")


def _check_size(n: object, m: object, what: str) -> int:
    """The size n of an n x n matrix, checked against the limits."""
    if not (isinstance(n, (int, np.integer)) and isinstance(m, (int, np.integer))):
        raise FileRefused(f"{what} has no valid shape")
    n, m = int(n), int(m)
    if n <= 0 or m <= 0:
        raise FileRefused(f"{what} is {n}x{m}; a matrix needs at least one row and column")
    if n != m:
        raise FileRefused(f"{what} is {n}x{m}, not a square matrix")
    if n > limits.MAX_MATRIX_DIMENSION:
        raise FileRefused(f"{what} is {n}x{n}; matrices are limited to "
                          f"{limits.MAX_MATRIX_DIMENSION}x{limits.MAX_MATRIX_DIMENSION} "
                          "(resonant.model.limits.MAX_MATRIX_DIMENSION)")
    return n


def _read_npy(handle: IO[bytes], what: str, available: int, *, matrix: bool = False,
              text: bool = False, max_entries: int | None = None) -> np.ndarray:
    """One .npy array from ``handle``, its header checked before its data is read.

    ``available`` bounds the bytes the data may take (the file or member size).
    """
    try:
        version = np.lib.format.read_magic(handle)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(handle)
        elif version == (2, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(handle)
        else:
            raise FileRefused(f"{what} uses .npy format version {version[0]}.{version[1]}; "
                              "save it with numpy.save")
    except FileRefused:
        raise
    except Exception:  # noqa: BLE001 - a malformed header
        raise FileRefused(f"{what} is not a valid .npy array") from None
    _check_dtype(dtype, what, text=text)
    if not isinstance(shape, tuple) or any(not isinstance(d, int) or d < 0 for d in shape):
        raise FileRefused(f"{what} has an invalid shape")
    if matrix:
        if len(shape) != 2:
            raise FileRefused(f"{what} has {len(shape)} dimensions; a matrix has 2")
        n = _check_size(shape[0], shape[1], what)
        if n * n > limits.MAX_DENSE_ENTRIES:
            raise FileRefused(f"{what} is a dense {n}x{n} matrix; dense matrices are limited "
                              f"to {limits.MAX_DENSE_ENTRIES} entries "
                              "(resonant.model.limits.MAX_DENSE_ENTRIES); save large "
                              "matrices sparse (scipy.sparse.save_npz or .mtx)")
    count = math.prod(shape)
    if max_entries is not None and count > max_entries:
        raise FileRefused(f"{what} holds {count} entries; at most {max_entries} here")
    nbytes = count * dtype.itemsize
    if nbytes > available:
        raise FileRefused(f"{what} claims {nbytes} bytes of data but the file holds fewer")
    array = np.frombuffer(_read_exact(handle, nbytes, what), dtype=dtype)
    return array.reshape(shape, order="F" if fortran else "C")


def _dense(array: np.ndarray, what: str = "the matrix") -> np.ndarray:
    out = np.array(array, dtype=float)  # a writable copy in native byte order
    if not np.all(np.isfinite(out)):
        raise FileRefused(f"{what} holds non-finite entries (inf or nan)")
    return out


def _check_archive_directory(handle: IO[bytes], size: int) -> None:
    """Refuse archives whose central directory is large before zipfile reads it."""
    tail_length = min(size, 22 + 65535)
    handle.seek(size - tail_length)
    tail = handle.read(tail_length)
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or len(tail) - at < 22:
        raise FileRefused("it is not a valid .npz (zip) archive")
    _, _, _, on_disk, total, directory_size, _, _ = struct.unpack("<4s4H2LH",
                                                                    tail[at:at + 22])
    if at >= 20 and tail[at - 20:at - 16] == b"PK\x06\x07":
        raise FileRefused("it is a ZIP64 archive; .npz files of matrices within the limits "
                          "are plain zip archives")
    most = limits.MAX_ARCHIVE_MEMBERS
    if max(on_disk, total) > most or directory_size > most * 1024:
        raise FileRefused(f"the archive has more than {most} members; numpy and scipy write "
                          "a few (resonant.model.limits.MAX_ARCHIVE_MEMBERS)")
    handle.seek(0)


def _read_npz(handle: IO[bytes], size: int, key: str) -> Any:
    _check_archive_directory(handle, size)
    try:
        archive = zipfile.ZipFile(handle)
    except Exception:  # noqa: BLE001
        raise FileRefused("it is not a valid .npz (zip) archive") from None
    with archive:
        infos = archive.infolist()
        if len(infos) > limits.MAX_ARCHIVE_MEMBERS:
            raise FileRefused(f"the archive has more than {limits.MAX_ARCHIVE_MEMBERS} members")
        members: dict[str, zipfile.ZipInfo] = {}
        total = 0
        for info in infos:
            if info.flag_bits & 0x1:
                raise FileRefused("the archive is encrypted")
            if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
                raise FileRefused("the archive uses a compression method numpy does not "
                                  "write; only stored and deflated members are read")
            if info.file_size > limits.MAX_COMPRESSION_RATIO * max(info.compress_size, 1):
                raise FileRefused("a member of the archive claims to expand more than "
                                  f"{limits.MAX_COMPRESSION_RATIO}-fold; not a numpy archive")
            total += info.file_size
            if info.filename.endswith(".npy"):
                name = info.filename[:-4]
                if name in members:
                    raise FileRefused("the archive holds two arrays of the same name")
                members[name] = info
        if total > limits.MAX_DECOMPRESSED_BYTES:
            raise FileRefused(f"the archive's arrays take {total} bytes decompressed; "
                              f"limited to {limits.MAX_DECOMPRESSED_BYTES} "
                              "(resonant.model.limits.MAX_DECOMPRESSED_BYTES)")
        if SPARSE_NPZ_KEYS <= set(members):  # written by scipy.sparse.save_npz
            return _read_sparse(archive, members)
        if key in members:
            chosen = members[key]
        elif len(members) == 1:
            chosen = next(iter(members.values()))
        else:
            raise FileRefused(f"the archive holds {len(members)} arrays but none named "
                              f"'{key}'; name the array like the matrix (numpy.savez(file, "
                              f"{key}=...)) or store only one")
        with archive.open(chosen) as member:
            return _dense(_read_npy(member, "the array", chosen.file_size, matrix=True))


def _member(archive: zipfile.ZipFile, members: dict[str, zipfile.ZipInfo], name: str,
            max_entries: int, text: bool = False) -> np.ndarray:
    info = members.get(name)
    if info is None:
        raise FileRefused(f"the sparse matrix has no '{name}' array")
    with archive.open(info) as member:
        return _read_npy(member, f"its '{name}' array", info.file_size, text=text,
                         max_entries=max_entries)


def _index(array: np.ndarray, name: str, length: int, upper: int) -> np.ndarray:
    """An integer index array of ``length`` entries, each in [0, upper)."""
    if array.ndim != 1 or array.dtype.kind not in "iu":
        raise FileRefused(f"its '{name}' array must be a 1-D array of integers")
    if array.shape[0] != length:
        raise FileRefused(f"its '{name}' array has {array.shape[0]} entries; expected {length}")
    if length and (array.min() < 0 or array.max() >= upper):
        raise FileRefused(f"its '{name}' array holds an index outside 0..{upper - 1}")
    return array.astype(np.int64)


def _read_sparse(archive: zipfile.ZipFile, members: dict[str, zipfile.ZipInfo]) -> Any:
    """A sparse matrix in scipy's save_npz layout, validated before scipy builds it."""
    import scipy.sparse

    fmt_array = _member(archive, members, "format", 1, text=True)
    fmt = fmt_array.item() if fmt_array.ndim == 0 else None
    if isinstance(fmt, bytes):
        fmt = fmt.decode("ascii", "replace")
    if fmt not in SPARSE_FORMATS:
        named = f"'{fmt}' " if fmt in ("bsr", "dia", "lil", "dok") else "an unknown format "
        raise FileRefused(f"the sparse matrix is stored in {named}; save it as csr, csc or coo")
    shape = _member(archive, members, "shape", 2)
    if shape.shape != (2,) or shape.dtype.kind not in "iu":
        raise FileRefused("its 'shape' array must hold two integers")
    n = _check_size(shape[0], shape[1], "the sparse matrix")
    data = _member(archive, members, "data", limits.MAX_MATRIX_NONZEROS)
    _check_dtype(data.dtype, "the sparse matrix")
    if data.ndim != 1:
        raise FileRefused("its 'data' array must be 1-D")
    nnz = data.shape[0]
    values = _dense(data, "the sparse matrix")
    if fmt == "coo":
        rows = _index(_member(archive, members, "row", nnz), "row", nnz, n)
        cols = _index(_member(archive, members, "col", nnz), "col", nnz, n)
    else:
        indptr = _index(_member(archive, members, "indptr", n + 1), "indptr", n + 1, nnz + 1)
        if indptr[0] != 0 or indptr[-1] != nnz or np.any(np.diff(indptr) < 0):
            raise FileRefused(f"its 'indptr' array must rise from 0 to {nnz} (the number of "
                              "stored entries) without decreasing")
        indices = _index(_member(archive, members, "indices", nnz), "indices", nnz, n)
        outer = np.repeat(np.arange(n, dtype=np.int64), np.diff(indptr))
        rows, cols = (outer, indices) if fmt == "csr" else (indices, outer)
    matrix = scipy.sparse.coo_matrix((values, (rows, cols)), shape=(n, n)).tocsr()
    matrix.sum_duplicates()
    return matrix


MTX_FIELDS = ("real", "integer", "complex", "pattern")


#: the banner: ``%%MatrixMarket matrix <layout> <field> <symmetry>``
_MTX_BANNER = re.compile(rb"%%MatrixMarket[ \t]+matrix[ \t]+([A-Za-z-]+)[ \t]+([A-Za-z-]+)"
                         rb"[ \t]+([A-Za-z-]+)[ \t]*\r?", re.IGNORECASE)
MTX_SYMMETRIES = ("general", "symmetric", "skew-symmetric")
_MTX_INVALID = "it is not a valid Matrix Market file"


def _mtx_size_line(text: bytes) -> tuple[list[bytes], int]:
    """The fields of the size line (the first line after the banner that is neither blank
    nor a comment) and the offset of the data after it."""
    start = text.find(b"\n") + 1
    while start and start < len(text):
        end = text.find(b"\n", start)
        end = len(text) if end < 0 else end
        line = text[start:end]
        if line.strip() and not line.startswith(b"%"):
            return line.split(), end + 1
        start = end + 1
    raise FileRefused(f"{_MTX_INVALID}: there is no size line after the banner")


def _mtx_numbers(data: bytes, rows: int, columns: int) -> np.ndarray:
    """The data lines as a ``rows x columns`` float array, or the message of what is wrong
    (numpy's C reader, correctly rounded; scipy's C++ Matrix Market reader crashed the
    process on hostile files: docs/fuzzing.md)."""
    if rows == 0:
        if data.strip(b" \t\r\n") and any(line.strip() and not line.startswith(b"%")
                                           for line in data.split(b"\n")):
            raise FileRefused(f"{_MTX_INVALID}: it holds more entries than its size line says")
        return np.empty((0, columns))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            values = np.loadtxt(io.BytesIO(data), dtype=np.float64, comments="%", ndmin=2,
                                encoding="latin-1")
        except (ValueError, UnicodeError):
            raise FileRefused(f"{_MTX_INVALID}: a data line holds something other than "
                              f"numbers (expected {columns} per line)") from None
    if values.shape[1] != columns:
        raise FileRefused(f"{_MTX_INVALID}: a data line holds {values.shape[1]} numbers; "
                          f"expected {columns}")
    if values.shape[0] != rows:
        raise FileRefused(f"{_MTX_INVALID}: its size line announces {rows} entries, the file "
                          f"holds {values.shape[0]}")
    return values


#: bytes of the data lines pyarrow's CSV reader parses per task (a line longer than this
#: fails the fast way and takes numpy's)
_MTX_ARROW_BLOCK = 4 * 2**20


def _mtx_with_arrow(text: bytes, offset: int, n: int, entries: int, coordinate: bool,
                    symmetry: str) -> Any | None:
    """The matrix from the data lines ``text[offset:]`` by pyarrow's CSV reader
    (multithreaded C++, correctly rounded doubles), when pyarrow is installed and the
    lines are plain and valid: exactly ``entries`` lines of numbers separated by single
    spaces, finite values, indices in 1..n.  None otherwise, and numpy's reader then
    reads them or names what is wrong, so every message comes from one place."""
    try:
        import pyarrow
        import pyarrow.csv as arrow_csv
    except ImportError:
        return None
    if entries == 0:
        return None
    # what pyarrow reads and numpy does not: hexadecimal integers (0x10), a carriage
    # return alone ending a line
    if coordinate and (text.find(b"x", offset) >= 0 or text.find(b"X", offset) >= 0):
        return None
    if text.find(b"\r", offset) >= 0 and \
            text.count(b"\r", offset) != text.count(b"\r\n", offset):
        return None
    names = ["i", "j", "v"] if coordinate else ["v"]
    index = pyarrow.int32() if _mtx_index_type(n) is np.int32 else pyarrow.int64()
    types = {"i": index, "j": index, "v": pyarrow.float64()}
    try:
        table = arrow_csv.read_csv(
            pyarrow.BufferReader(pyarrow.py_buffer(text)[offset:]),
            read_options=arrow_csv.ReadOptions(column_names=names,
                                               block_size=_MTX_ARROW_BLOCK),
            # single spaces, no quotes, no comment lines: what writers write; anything
            # else (runs of blanks, comments between data lines) fails here
            parse_options=arrow_csv.ParseOptions(delimiter=" ", quote_char=False,
                                                 escape_char=False,
                                                 newlines_in_values=False,
                                                 ignore_empty_lines=True),
            convert_options=arrow_csv.ConvertOptions(
                column_types={name: types[name] for name in names}, null_values=[],
                strings_can_be_null=False, quoted_strings_can_be_null=False),
            # malloc, not pyarrow's default mimalloc, which reserves 1 GiB of address
            # space at its first use: a process under RLIMIT_AS would then fail
            memory_pool=pyarrow.system_memory_pool())
    except (pyarrow.ArrowException, ValueError, TypeError, OverflowError, MemoryError):
        return None
    if table.num_rows != entries or any(column.null_count for column in table.columns):
        return None
    values = np.concatenate([_arrow_numbers(chunk, np.float64)
                             for chunk in table.column("v").chunks])
    if not np.all(np.isfinite(values)):  # also "nan(...)", which numpy does not read
        return None
    if not coordinate:
        return _mtx_dense(values, n, symmetry)
    rows_, cols_ = (_mtx_arrow_indices(table.column(name), n) for name in ("i", "j"))
    del table
    if rows_ is None or cols_ is None:
        return None
    if symmetry == "skew-symmetric" and np.any(rows_ == cols_):
        return None
    return _mtx_csr(rows_, cols_, values, n, symmetry)


def _mtx_banner(first_line: bytes) -> tuple[str, str, str]:
    """Layout, field and symmetry of a Matrix Market banner, each one resonant reads."""
    banner = _MTX_BANNER.fullmatch(first_line)
    if banner is None:
        raise FileRefused(f"{_MTX_INVALID} (it must start with '%%MatrixMarket matrix' and a "
                          "size line)")
    layout, field, symmetry = (g.decode("ascii").lower() for g in banner.groups())
    if field not in ("real", "integer"):
        named = f"{field} " if field in MTX_FIELDS else "non-numeric "
        raise FileRefused(f"it holds {named}entries; M, K and C must be real numbers")
    if layout not in ("coordinate", "array"):
        raise FileRefused("it is neither a coordinate nor an array Matrix Market file")
    if symmetry not in MTX_SYMMETRIES:
        raise FileRefused(f"{_MTX_INVALID}: the symmetry must be one of "
                          f"{', '.join(MTX_SYMMETRIES)}")
    return layout, field, symmetry


def _mtx_entries(fields: list[bytes], coordinate: bool, symmetry: str, size: int
                 ) -> tuple[int, int]:
    """The matrix size and the number of data lines from the size line, within the limits
    and what the file's bytes can hold."""
    try:
        numbers = [int(f) for f in fields]
    except ValueError:
        numbers = []
    if len(numbers) != (3 if coordinate else 2):
        raise FileRefused(f"{_MTX_INVALID}: the size line must hold "
                          f"{'rows, columns and entries' if coordinate else 'rows and columns'}"
                          " as integers")
    n = _check_size(numbers[0], numbers[1], "the matrix")
    if coordinate:
        entries = numbers[2]
        stored = entries * (1 if symmetry == "general" else 2)
        if entries < 0 or stored > limits.MAX_MATRIX_NONZEROS:
            raise FileRefused(f"the matrix has {entries} stored entries; sparse matrices are "
                              f"limited to {limits.MAX_MATRIX_NONZEROS} "
                              "(resonant.model.limits.MAX_MATRIX_NONZEROS)")
        least = entries * 6  # "1 1 1\n" is the shortest entry line
    else:
        if n * n > limits.MAX_DENSE_ENTRIES:
            raise FileRefused(f"the matrix is a dense {n}x{n} matrix; dense matrices are "
                              f"limited to {limits.MAX_DENSE_ENTRIES} entries "
                              "(resonant.model.limits.MAX_DENSE_ENTRIES)")
        entries = {"general": n * n, "symmetric": n * (n + 1) // 2,
                   "skew-symmetric": n * (n - 1) // 2}[symmetry]
        least = entries * 2  # "1\n"
    if least > size:
        raise FileRefused(f"its size line claims more entries than the file's {size} bytes "
                          "can hold")
    return n, entries


def _mtx_arrow_indices(column: pyarrow.ChunkedArray, n: int) -> np.ndarray | None:
    """A column of 1-based indices (a chunked pyarrow integer array) as 0-based indices of
    scipy's index type, in one pass over the chunks; None if one lies outside 1..n."""
    index = _mtx_index_type(n)
    out = np.empty(len(column), dtype=index)
    at = 0
    for chunk in column.chunks:
        part = _arrow_numbers(chunk, index)
        if part.size and (part.min() < 1 or part.max() > n):
            return None
        np.subtract(part, 1, out=out[at:at + part.size], casting="unsafe")
        at += part.size
    return out


def _arrow_numbers(chunk: pyarrow.Array, dtype: type[np.number]) -> np.ndarray:
    """A pyarrow array of ``dtype`` numbers without nulls as a read-only view of its data
    buffer: pyarrow's own ``to_numpy`` imports pandas, half a second in every process
    that reads a matrix file, and most of them never use pandas."""
    itemsize = np.dtype(dtype).itemsize
    return np.frombuffer(chunk.buffers()[1], dtype=dtype, count=len(chunk),
                         offset=chunk.offset * itemsize)


def _mtx_index_type(n: int) -> type[np.signedinteger]:
    """The index type scipy gives an n x n CSR matrix (converting to it once, not twice)."""
    return np.int32 if n <= np.iinfo(np.int32).max else np.int64


def _mtx_dense(values: np.ndarray, n: int, symmetry: str) -> np.ndarray:
    """An array file's column-major values (the lower triangle for a symmetric one)."""
    values = values.reshape(-1)
    if symmetry == "general":
        return np.array(values.reshape(n, n, order="F"))
    # the lower triangle column by column: (i, j), i >= j, ordered by j then i
    cols, rows = np.triu_indices(n, 0 if symmetry == "symmetric" else 1)
    dense = np.zeros((n, n))
    dense[rows, cols] = values
    dense[cols, rows] = values if symmetry == "symmetric" else -values
    return dense


def _mtx_sparse(values: np.ndarray, n: int, symmetry: str) -> Any:
    """A coordinate file's (i, j, value) lines as a CSR matrix, indices checked."""
    index = values[:, :2]
    if np.any(index != np.floor(index)):
        raise FileRefused(f"{_MTX_INVALID}: an entry's row and column must be integers")
    outside = np.flatnonzero(np.any((index < 1) | (index > n), axis=1))
    if outside.size:
        i, j = (int(v) for v in index[outside[0]])
        raise FileRefused(f"{_MTX_INVALID}: an entry at ({i}, {j}) lies outside the {n}x{n} "
                          "matrix")
    rows_, cols_ = (index[:, k].astype(_mtx_index_type(n)) - 1 for k in (0, 1))
    if symmetry == "skew-symmetric" and np.any(rows_ == cols_):
        raise FileRefused(f"{_MTX_INVALID}: a skew-symmetric matrix stores no diagonal "
                          "entries")
    return _mtx_csr(rows_, cols_, np.ascontiguousarray(values[:, 2]), n, symmetry)


def _mtx_csr(rows_: np.ndarray, cols_: np.ndarray, data: np.ndarray, n: int, symmetry: str
             ) -> Any:
    """The CSR matrix of checked 0-based entries, the other triangle of a symmetric or
    skew-symmetric file added, duplicates summed."""
    import scipy.sparse

    if symmetry != "general":
        # every stored entry mirrored; a diagonal entry's mirror is -0.0, which added to
        # any number gives that number bit for bit (cheaper than leaving it out)
        mirrored = np.negative(data) if symmetry == "skew-symmetric" else data.copy()
        np.copyto(mirrored, -0.0, where=rows_ == cols_)
        rows_, cols_, data = (np.concatenate([rows_, cols_]), np.concatenate([cols_, rows_]),
                              np.concatenate([data, mirrored]))
    out = scipy.sparse.coo_matrix((data, (rows_, cols_)), shape=(n, n)).tocsr()
    out.sum_duplicates()
    return out


def _read_mtx(handle: IO[bytes], size: int) -> Any:
    """A Matrix Market file (real or integer; general, symmetric or skew-symmetric; coordinate
    or array), read by resonant itself: banner and size line first, checked against the
    limits before the data are parsed."""
    text = handle.read(size + 1)
    end = text.find(b"\n")
    layout, _, symmetry = _mtx_banner(text if end < 0 else text[:end])
    fields, offset = _mtx_size_line(text)
    coordinate = layout == "coordinate"
    n, entries = _mtx_entries(fields, coordinate, symmetry, size)
    fast = _mtx_with_arrow(text, offset, n, entries, coordinate, symmetry)
    if fast is not None:
        return fast
    values = _mtx_numbers(text[offset:], entries, 3 if coordinate else 1)
    if not np.all(np.isfinite(values)):
        raise FileRefused("the matrix holds non-finite entries (inf or nan)")
    return _mtx_sparse(values, n, symmetry) if coordinate else _mtx_dense(values, n, symmetry)


def _damping_from_ratios(matrices: dict[str, Any], section: Mapping[str, object],
                         rayleigh: tuple[Expression, Expression] | None,
                         modal: np.ndarray | None, params: Sequence[str], source: str,
                         problems: list[Problem]) -> None:
    """C from Rayleigh coefficients or modal damping ratios, put in ``matrices``."""
    if rayleigh is not None and "M" in matrices and "K" in matrices:
        damping = _rayleigh_matrix(rayleigh, matrices["M"], matrices["K"], params, source,
                                   problems)
        if damping is not None:
            matrices["C"] = damping
    if modal is not None and ("C" in section):
        problems.append(Problem(f"give either C or {MODAL_KEY}, not both", source,
                                "matrices", MODAL_KEY))
    elif modal is not None and "M" in matrices and "K" in matrices:
        damping = _modal_matrix(modal, matrices["M"], matrices["K"], source, problems)
        if damping is not None:
            matrices["C"] = damping


def read_matrix_spec(section: object, harmonics: object, params: Sequence[str],
                     coordinates: Sequence[str], source: str, base_dir: Path | None,
                     allow_paths: Sequence[str | os.PathLike[str]] = (),
                     inline_arrays: Mapping[str, np.ndarray] | None = None) -> MatrixSpec:
    """Validate ``[matrices]`` and ``[[harmonic]]``; every problem in one ModelError.

    ``base_dir`` is the model file's folder (None for a model given as text:
    file references are then refused); ``allow_paths`` are further directories
    matrix files may be read from; ``inline_arrays`` the large number-only inline
    matrices already read (:func:`resonant.model.inline_matrices.extract_numeric_matrices`),
    by the placeholder that stands for them in ``section``.
    """
    inline_arrays = inline_arrays or {}
    problems: list[Problem] = []
    if not isinstance(section, dict):
        raise ModelError(Problem("[matrices] must be a table with M, K and optionally C",
                                 source, "matrices"))
    harmonics = _harmonics_given(section, harmonics, source, problems)
    matrices: dict[str, Any] = {}
    rayleigh = None
    modal = None
    dofs: list[str] | None = None
    uset: tuple[UsetMap, str | None] | None = None
    drop = False
    for key, value in section.items():
        if key == "harmonic":
            continue
        if key == MODAL_KEY:
            modal = _modal_ratios(value, source, problems)
            continue
        if key == SPEED_KEY:
            continue
        if key == DOFS_KEY:
            mapped = _dof_map(value, source, base_dir, allow_paths, problems)
            if isinstance(mapped, tuple):
                uset = mapped
            else:
                dofs = mapped
            continue
        if key == DROP_KEY:
            if not isinstance(value, bool):
                problems.append(Problem(f"{DROP_KEY} must be true or false", source,
                                        "matrices", key))
            drop = value is True
            continue
        if key not in MATRIX_KEYS:
            problems.append(Problem(f"unknown key '{key}'; [matrices] takes M, K, C, G, "
                                    f"{SPEED_KEY}, {MODAL_KEY}, {DOFS_KEY} and {DROP_KEY}",
                                    source, "matrices", key))
            continue
        if key == "C" and isinstance(value, str) and value not in inline_arrays and \
                not is_file_reference(value):
            rayleigh = _rayleigh_coefficients(value, params, source, problems)
            continue
        matrix = _matrix(key, value, params, source, base_dir, allow_paths, inline_arrays,
                         problems)
        if matrix is not None:
            matrices[key] = matrix
    if any(isinstance(m, AbaqusEntries) for m in matrices.values()):
        dofs = _abaqus_matrices(matrices, dofs, source, problems)
    _damping_from_ratios(matrices, section, rayleigh, modal, params, source, problems)
    speed = _speed_parameter(section, params, source, problems)
    n = _check_sizes(section, matrices, coordinates, source, problems)
    if uset is not None and n:
        dofs = _uset_dofs(uset, n, section, source, problems)
    dofs = _dofs_for(dofs, coordinates, n, source, problems)
    if drop and not problems:
        dofs = _drop_unconnected(matrices, dofs, coordinates, n, source, problems)
        n = matrices["M"].shape[0] if "M" in matrices else n
    names = list(coordinates) if coordinates else dofs or [f"q{i + 1}" for i in range(n)]
    loads = _LoadContext(names, base_dir, allow_paths)
    parsed = [_harmonic(entry, f"harmonic {i}", n, params, source, problems, loads)
              for i, entry in enumerate(harmonics if isinstance(harmonics, list)
                                        else [harmonics], start=1)]
    if problems:
        raise ModelError(problems)
    return MatrixSpec(M=matrices["M"], K=matrices["K"], C=matrices.get("C"),
                      harmonics=tuple(h for h in parsed if h is not None),
                      coordinates=tuple(dofs or ()), G=matrices.get("G"), speed=speed)


#: the keys of ``dofs = { uset = "run.f06", set = "a", table = 1 }``
USET_KEYS = ("uset", "set", "table")
#: Nastran's printed output, where a USET table is read from
PRINTOUT_SUFFIXES = (".f06", ".out")


def _uset_table(value: dict, base_dir: Path | None,
                allow_paths: Sequence[str | os.PathLike[str]]) -> tuple[UsetMap, str | None]:
    """``dofs = { uset = ..., set = ..., table = ... }``: the USET map and the set asked."""
    unknown = sorted(set(value) - set(USET_KEYS))
    reference, nasset, table = value.get("uset"), value.get("set"), value.get("table")
    if unknown or not isinstance(reference, str) or \
            not (nasset is None or isinstance(nasset, str)) or \
            not (table is None or (type(table) is int and table >= 1)):
        raise FileRefused('dofs as a table is { uset = "run.f06" or "model.op4:USET", '
                          'set = "a" (optional), table = 1 (optional, for a printout of '
                          "several superelements) }" +
                          (f"; unknown key(s) {', '.join(unknown)}" if unknown else ""))
    if reference.lower().endswith(PRINTOUT_SUFFIXES):
        path = resolve_matrix_path(reference, base_dir, allow_paths)
        return read_usetprt(path, table, reference), nasset
    if split_reference(reference) is None:
        raise FileRefused("uset names a Nastran printout (.f06, .out: its USET DEFINITION "
                          'TABLE) or an OP4 matrix of bit masks ("model.op4:USET")')
    path, name = split_reference(reference) or (reference, None)
    matrix = read_op4_matrix(resolve_matrix_path(path, base_dir, allow_paths), name,
                             DOFS_KEY, square=False)
    return uset_from_table(matrix, reference), nasset


def _uset_dofs(uset: tuple[UsetMap, str | None], n: int, section: dict, source: str,
               problems: list[Problem]) -> list[str] | None:
    """The names of the matrices' rows from a USET map (None: a problem is recorded)."""
    names = [ref[1] for key in MATRIX_KEYS if isinstance(section.get(key), str)
             and (ref := split_reference(section[key])) is not None and ref[1]]
    try:
        return uset_names(uset[0], n, uset[1], names)
    except FileRefused as exc:
        problems.append(Problem(str(exc), source, "matrices", DOFS_KEY))
        return None


def _dof_map(value: object, source: str, base_dir: Path | None,
             allow_paths: Sequence[str | os.PathLike[str]], problems: list[Problem]
             ) -> list[str] | tuple[UsetMap, str | None] | None:
    """The coordinate names of ``dofs``: inline [[node, component], ...], an n x 2 matrix
    of an OP4 file, or a USET map (an OP4 matrix of three or more columns, or a table
    naming one) with the set asked for (None: a problem is recorded)."""
    try:
        if isinstance(value, dict):
            return _uset_table(value, base_dir, allow_paths)
        if isinstance(value, str) and split_reference(value) is not None:
            path, name = split_reference(value) or (value, None)
            pairs = read_op4_matrix(resolve_matrix_path(path, base_dir, allow_paths), name,
                                    DOFS_KEY, square=False)
            pairs = pairs.toarray() if hasattr(pairs, "toarray") else pairs
            if pairs.ndim == 2 and pairs.shape[1] >= 3:
                return uset_from_table(pairs, value), None
        elif isinstance(value, str) and split_full(value) is not None:
            path = (split_full(value) or (value, None))[0]
            return full_dof_names(resolve_matrix_path(path, base_dir, allow_paths))
        elif isinstance(value, list) and all(
                isinstance(p, list) and len(p) == 2 and all(
                    type(v) is int for v in p) for p in value):
            pairs = np.array(value, dtype=np.int64).reshape(-1, 2)
        else:
            raise FileRefused("dofs must be a list of [node, component] pairs (dofs = "
                              '[[1042, 3], [1042, 4]]), an n x 2 matrix of an OP4 file '
                              '(dofs = "model.op4:DOFS"), an ANSYS .full file (dofs = '
                              '"model.full") or a Nastran USET table (dofs = { uset = '
                              '"run.f06", set = "a" })')
        return dof_names(np.asarray(pairs))
    except FileRefused as exc:
        shown = f"cannot read '{value}': " if isinstance(value, str) else ""
        problems.append(Problem(f"{shown}{exc}", source, "matrices", DOFS_KEY))
        return None


def _abaqus_matrices(matrices: dict[str, Any], dofs: list[str] | None, source: str,
                     problems: list[Problem]) -> list[str] | None:
    """Abaqus matrix files assembled on the union of their DOFs; their names."""
    entries = {k: m for k, m in matrices.items() if isinstance(m, AbaqusEntries)}
    if len(entries) != len(matrices):
        problems.append(Problem("Abaqus matrix output and DMIG entries, labelled by node, "
                                "cannot be combined with other matrix files or inline "
                                "matrices: give M, K (and C) all labelled", source,
                                "matrices"))
        for key in entries:
            del matrices[key]
        return dofs
    try:
        assembled, names = assemble_abaqus(entries)
    except FileRefused as exc:
        problems.append(Problem(f"cannot assemble the labelled matrices: {exc}", source,
                                "matrices"))
        for key in entries:
            del matrices[key]
        return dofs
    matrices.update(assembled)
    return dofs if dofs is not None else names


def _drop_unconnected(matrices: dict[str, Any], dofs: list[str] | None,
                      coordinates: Sequence[str], n: int, source: str,
                      problems: list[Problem]) -> list[str] | None:
    """Remove the rows and columns of M, K, C where all three are zero; the names that are
    left (the DOF map's, or q1 ... qn of the file's numbering)."""
    if coordinates or any(isinstance(m, list) for m in matrices.values()) or \
            not {"M", "K"} <= set(matrices):
        problems.append(Problem(f"{DROP_KEY} takes matrices from files (or plain numbers) "
                                "and no [coordinates]: the names come from dofs or the "
                                "file's numbering", source, "matrices", DROP_KEY))
        return dofs
    used = np.zeros(n, dtype=bool)
    for matrix in matrices.values():
        magnitude = abs(matrix)
        used |= np.asarray(magnitude.sum(axis=1)).ravel() > 0
        used |= np.asarray(magnitude.sum(axis=0)).ravel() > 0
    keep = np.flatnonzero(used)
    for key, matrix in matrices.items():
        matrices[key] = matrix[keep][:, keep]
    names = dofs or [f"q{i + 1}" for i in range(n)]
    return [names[i] for i in keep]


def _dofs_for(dofs: list[str] | None, coordinates: Sequence[str], n: int, source: str,
              problems: list[Problem]) -> list[str] | None:
    """The DOF map's names when they fit the matrices (n of them, no [coordinates])."""
    if dofs is None:
        return None
    if coordinates:
        problems.append(Problem(f"give the coordinates either in [coordinates] or by "
                                f"{DOFS_KEY}, not both", source, "matrices", DOFS_KEY))
        return None
    if n and len(dofs) != n:
        problems.append(Problem(f"the DOF map lists {len(dofs)} DOFs but the matrices have "
                                f"{n} rows: it does not belong to these matrices", source,
                                "matrices", DOFS_KEY))
        return None
    return dofs


def _speed_parameter(section: dict, params: Sequence[str], source: str,
                     problems: list[Problem]) -> str | None:
    """The parameter named by ``speed`` (the rotor's spin speed, rad/s), which G needs."""
    speed = section.get(SPEED_KEY)
    if speed is None:
        if "G" in section:
            problems.append(Problem(
                "the gyroscopic matrix G needs the speed it is multiplied by: add speed = "
                "\"NAME\" naming a parameter (the spin speed, e.g. Omega = \"3000 rpm\")",
                source, "matrices", SPEED_KEY))
        return None
    if not isinstance(speed, str) or speed not in params:
        known = ", ".join(params) or "none"
        problems.append(Problem(f"speed must name a parameter (the spin speed); got "
                                f"{speed!r}, parameters: {known}", source, "matrices",
                                SPEED_KEY))
        return None
    return speed


def _harmonics_given(section: dict, harmonics: object, source: str, problems: list[Problem]
                     ) -> object:
    """The harmonics: top-level ``[[harmonic]]`` or ``harmonic = [...]`` in [matrices]."""
    if "harmonic" not in section:
        return harmonics
    inner = section["harmonic"]
    if not isinstance(inner, list) or not all(isinstance(h, dict) for h in inner):
        problems.append(Problem(
            "harmonic inside [matrices] must be an array of tables (harmonic = [{ omega "
            "= ..., F_S = [...] }] or [[matrices.harmonic]]); or use top-level "
            "[[harmonic]] tables", source, "matrices", "harmonic"))
        return harmonics
    if harmonics and inner:
        problems.append(Problem("give the harmonics either as top-level [[harmonic]] "
                                "tables or inside [matrices], not both", source,
                                "matrices", "harmonic"))
        return harmonics
    return inner


def _matrix(key: str, value: object, params: Sequence[str], source: str, base_dir: Path | None,
            allow_paths: Sequence[str | os.PathLike[str]],
            inline_arrays: Mapping[str, np.ndarray], problems: list[Problem]) -> Any:
    """One of M, C, K: read from its file, inline numbers or expressions (None: a problem)."""
    if isinstance(value, str) and value in inline_arrays:
        return inline_arrays[value]
    if isinstance(value, str) and is_file_reference(value):
        try:
            return read_matrix_file(value, key, base_dir, allow_paths)
        except FileRefused as exc:
            problems.append(Problem(f"cannot read '{value}': {exc}", source, "matrices", key))
            return None
    if isinstance(value, list) and value and all(isinstance(r, list) for r in value):
        n = len(value)
        if any(len(row) != n for row in value):
            problems.append(Problem(f"{key} must be square: {n} rows of {n} entries",
                                    source, "matrices", key))
            return None
        numbers = _plain_numbers(value) if n > inline_matrices.INLINE_EXPRESSION_SIZE else None
        return numbers if numbers is not None else \
            _inline_entries(value, key, params, source, problems)
    problems.append(Problem(
        f"{key} must be an array of rows ([[1, 0], [0, 1]]) or a path to a "
        f"{'/'.join(FILE_SUFFIXES)} file or an OP4 matrix (\"model.op4:KAA\")", source,
        "matrices", key))
    return None


def _check_sizes(section: dict, matrices: Mapping[str, Any], coordinates: Sequence[str],
                 source: str, problems: list[Problem]) -> int:
    """M and K given, all of one size, one coordinate per row; the size."""
    for key in ("M", "K"):
        if key not in section:
            problems.append(Problem(f"{key} is missing", source, "matrices", key))
    sizes = {k: (m.shape[0] if hasattr(m, "shape") else len(m)) for k, m in matrices.items()}
    if len(set(sizes.values())) > 1:
        problems.append(Problem("M, K, C and G must have the same size; got " + ", ".join(
            f"{k}: {v}x{v}" for k, v in sizes.items()), source, "matrices"))
    n = sizes.get("M", 0)
    if coordinates and n and len(coordinates) != n:
        problems.append(Problem(f"{len(coordinates)} coordinates for {n}x{n} matrices",
                                source, "coordinates"))
    return n


@dataclass(frozen=True)
class _LoadContext:
    """What a load vector given by name or file needs: the coordinate names, where files
    may be read from."""

    names: list[str]
    base_dir: Path | None
    allow_paths: Sequence[str | os.PathLike[str]]


def _load_vector(vec: object, key: str, n: int, where: str, source: str,
                 loads: _LoadContext | None) -> list[Any]:
    """The n entries of F_S or F_C given as a list, a file or named entries."""
    if isinstance(vec, str) and loads is not None:
        if loads.base_dir is None:
            raise ModelError(Problem(
                f"{key} = '{vec}': a load vector file needs a model read from a file "
                "(its folder is where the file is looked for)", source, where, key))
        try:
            numbers = read_vector_file(vec, n, loads.base_dir, loads.allow_paths)
        except FileRefused as exc:
            raise ModelError(Problem(f"cannot read '{vec}': {exc}", source, where,
                                     key)) from None
        return [float(v) for v in numbers]
    if isinstance(vec, dict) and loads is not None:
        index = {name: i for i, name in enumerate(loads.names)}
        out: list[Any] = [0] * n
        for name, value in vec.items():
            if name not in index:
                shown = ", ".join(loads.names[:3]) + (", ..., " + loads.names[-1]
                                                      if n > 3 else "")
                raise ModelError(Problem(
                    f"{key} names '{name}', which is not a coordinate (the coordinates are "
                    f"{shown})", source, where, key))
            out[index[name]] = value
        return out
    if not isinstance(vec, list) or (n and len(vec) != n):
        raise ModelError(Problem(
            f"{key} must be a list of {n} entries, a table of entries by coordinate "
            f"({key} = {{ {loads.names[-1] if loads and loads.names else 'q1'} = \"F0\" }}) "
            f"or a .npy/.mtx file", source, where, key))
    return vec


def _rayleigh_coefficients(text: str, params: Sequence[str], source: str,
                           problems: list[Problem]) -> tuple[Expression, Expression] | None:
    """(alpha, beta) of ``C = "alpha*M + beta*K"`` (None: a problem is recorded)."""
    import sympy

    hint = ('C as text must be Rayleigh damping "alpha*M + beta*K" (alpha, beta numbers '
            "or expressions of the parameters), an array of rows or a matrix file")
    try:
        expression = parse(text, allowed=list(params) + ["M", "K"], file=source,
                           section="matrices", key="C")
    except ExpressionError as exc:
        problems.extend(exc.problems)
        return None
    if any(primes for _, primes in expression.names()):
        problems.append(Problem(hint, source, "matrices", "C"))
        return None
    if "M" in params or "K" in params:
        problems.append(Problem("Rayleigh damping names the matrices M and K: rename the "
                                "parameters called M or K", source, "matrices", "C"))
        return None
    symbols = {"M": sympy.Symbol("M"), "K": sympy.Symbol("K")}
    expr = sympy.expand(expression.to_sympy(lambda name, primes: sympy.Symbol(name)))
    alpha, beta = expr.coeff(symbols["M"], 1), expr.coeff(symbols["K"], 1)
    rest = sympy.expand(expr - alpha * symbols["M"] - beta * symbols["K"])
    if rest != 0 or any(c.has(symbols["M"]) or c.has(symbols["K"]) for c in (alpha, beta)):
        problems.append(Problem(f"{hint}; '{text}' is not of that form", source,
                                "matrices", "C"))
        return None
    # alpha is the expression at M = 1, K = 0, beta at M = 0, K = 1 (linear, checked above)
    parts = []
    for m, k in (("1", "0"), ("0", "1")):
        coefficient = re.sub(r"\bK\b", f"({k})", re.sub(r"\bM\b", f"({m})", text))
        try:
            parts.append(parse(coefficient, allowed=params, file=source, section="matrices",
                               key="C"))
        except ExpressionError as exc:
            problems.extend(exc.problems)
            return None
    return parts[0], parts[1]


def _modal_ratios(value: object, source: str, problems: list[Problem]) -> np.ndarray | None:
    """The damping ratios of ``modal_damping``: one number or a non-empty list of numbers,
    each finite and in [0, 1) (None: a problem is recorded)."""
    hint = (f"{MODAL_KEY} must be one damping ratio (modal_damping = 0.02) or a list of "
            "ratios, one per mode from the lowest (modal_damping = [0.02, 0.03])")
    items = value if isinstance(value, list) else [value]
    if not items or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                            for x in items):
        problems.append(Problem(hint, source, "matrices", MODAL_KEY))
        return None
    ratios = np.asarray(items, dtype=float)
    if not np.all(np.isfinite(ratios)) or np.any(ratios < 0) or np.any(ratios >= 1):
        problems.append(Problem(f"every ratio of {MODAL_KEY} must be a finite number in "
                                f"[0, 1) (0.02 is 2 % of critical damping); got {items}",
                                source, "matrices", MODAL_KEY))
        return None
    return ratios


def _modal_matrix(ratios: np.ndarray, M: Matrix | list[Any], K: Matrix | list[Any], source: str,
                  problems: list[Problem]) -> np.ndarray | None:
    """C = M Phi diag(2 zeta_r omega_r) Phi^T M with mass-normalized modes Phi of (K, M);
    modes beyond the list of ratios take its last ratio (None: a problem is recorded)."""
    def numbers(matrix: Matrix | list[Any]) -> np.ndarray | None:
        if not isinstance(matrix, list):
            return matrix.toarray() if hasattr(matrix, "toarray") else \
                np.asarray(matrix, dtype=float)
        entries = [e for row in matrix for e in row]
        if any(isinstance(e, Expression) and e.names() for e in entries):
            return None
        return np.array([[float(numeric_value(e, {})) if isinstance(e, Expression)
                          else float(e) for e in row] for row in matrix], dtype=float)

    Md, Kd = numbers(M), numbers(K)
    if Md is None or Kd is None:
        problems.append(Problem(f"{MODAL_KEY} needs M and K as numbers (files or plain "
                                "numbers), not expressions of parameters", source,
                                "matrices", MODAL_KEY))
        return None
    n = Md.shape[0]
    if Md.shape != Kd.shape:
        return None                 # the size check reports it
    if n > MODAL_DAMPING_MAX_DOF:
        problems.append(Problem(
            f"{MODAL_KEY} builds a dense C (n^2 numbers from the dense eigenproblem) and is "
            f"limited to {MODAL_DAMPING_MAX_DOF} coordinates; this model has {n}: give C "
            'explicitly (a file) or as Rayleigh damping C = "alpha*M + beta*K"',
            source, "matrices", MODAL_KEY))
        return None
    if len(ratios) > n:
        problems.append(Problem(f"{MODAL_KEY} lists {len(ratios)} ratios but the model has "
                                f"only {n} modes", source, "matrices", MODAL_KEY))
        return None
    try:
        lam, phi = mass_normalized_modes(Md, Kd)
    except (np.linalg.LinAlgError, ValueError):
        problems.append(Problem(f"{MODAL_KEY} needs a symmetric positive definite M and a "
                                "symmetric K (the modes are those of K phi = omega^2 M phi)",
                                source, "matrices", MODAL_KEY))
        return None
    zeta = np.full(n, ratios[-1])
    zeta[:len(ratios)] = ratios
    omega = np.sqrt(np.clip(lam, 0.0, None))
    B = Md @ phi
    C = (B * (2.0 * zeta * omega)) @ B.T
    return np.asarray(0.5 * (C + C.T), dtype=float)


def _rayleigh_matrix(coefficients: tuple[Expression, Expression], M: Matrix | list[Any],
                     K: Matrix | list[Any], params: Sequence[str], source: str,
                     problems: list[Problem]) -> Any:
    """C = alpha M + beta K: numbers for numeric M, K (file or plain numbers); entry
    expressions for inline expression matrices."""
    alpha, beta = coefficients
    if not isinstance(M, list) and not isinstance(K, list):  # numbers
        if alpha.names() or beta.names():
            problems.append(Problem(
                "Rayleigh damping of matrices read from files or given as numbers needs "
                f"numbers for alpha and beta, not expressions of parameters ('{alpha.text}',"
                f" '{beta.text}')", source, "matrices", "C"))
            return None
        a = float(numeric_value(alpha, {}))
        b = float(numeric_value(beta, {}))
        if not (np.isfinite(a) and np.isfinite(b)):
            problems.append(Problem("the Rayleigh coefficients must be finite", source,
                                    "matrices", "C"))
            return None
        C = a * M + b * K
        return C.tocsr() if hasattr(C, "tocsr") else np.asarray(C, dtype=float)

    def text(entry: Expression | float) -> str:
        return entry.text if isinstance(entry, Expression) else repr(float(entry))

    def rows(matrix: Matrix | list[Any]) -> list[list[Any]]:
        if isinstance(matrix, list):
            return matrix
        dense = matrix.toarray() if hasattr(matrix, "toarray") else np.asarray(matrix)
        return [list(row) for row in dense]

    out = []
    for i, (mrow, krow) in enumerate(zip(rows(M), rows(K))):
        out.append([parse(f"({alpha.text})*({text(m)}) + ({beta.text})*({text(k)})",
                          allowed=params, file=source, section="matrices",
                          key=f"C[{i + 1}][{j + 1}]")
                    for j, (m, k) in enumerate(zip(mrow, krow))])
    return out


def _harmonic(entry: object, where: str, n: int, params: Sequence[str], source: str,
              problems: list[Problem], loads: _LoadContext | None = None
              ) -> Harmonic | None:
    """One ``[[harmonic]]``: omega and the load vectors F_S, F_C of n entries (a list, a
    file, or a table of entries by coordinate name)."""
    if not isinstance(entry, dict) or "omega" not in entry:
        problems.append(Problem("a harmonic needs omega and F_S and/or F_C", source, where))
        return None
    unknown = set(entry) - {"omega", "F_S", "F_C"}
    if unknown:
        problems.append(Problem(f"unknown keys {sorted(unknown)}; a harmonic has omega, "
                                "F_S, F_C", source, where))
    try:
        omega = _entry(entry["omega"], params, source, "omega", where)
        vectors = []
        numbers: dict[tuple[type, Any], Expression] = {}  # each number literal parsed once
        for key in ("F_S", "F_C"):
            vec = _load_vector(entry.get(key, [0] * n), key, n, where, source, loads)
            parsed = []
            for j, v in enumerate(vec):
                literal = (type(v), v) if type(v) in (int, float) else None
                found = numbers.get(literal) if literal is not None else None
                if found is None:
                    found = _entry(v, params, source, f"{key}[{j + 1}]", where)
                    if literal is not None:
                        numbers[literal] = found
                parsed.append(found)
            vectors.append(tuple(parsed))
        return Harmonic(omega, vectors[0], vectors[1])
    except ModelError as exc:
        problems.extend(exc.problems)
        return None


def _plain_numbers(rows: list[list[Any]]) -> np.ndarray | None:
    """A large inline matrix of number literals as one float array, without the expression
    parser (8 bytes an entry instead of a syntax tree); None if an entry is anything else
    (an expression, a bool, a number beyond the limits), which then takes the parser's
    way and gets its message."""
    if not all(type(v) is int or type(v) is float for row in rows for v in row):
        return None
    try:
        array = np.array(rows, dtype=float)
    except OverflowError:
        return None
    if not inline_matrices.within_limits(array):
        return None
    array.flags.writeable = False
    return array


def _inline_entries(value: list[list[Any]], key: str, params: Sequence[str], source: str,
                    problems: list[Problem]) -> list[list[Expression]]:
    """Every entry of an inline matrix parsed as an expression of the parameters."""
    rows = []
    for i, row in enumerate(value):
        parsed = []
        for j, entry in enumerate(row):
            try:
                parsed.append(_entry(entry, params, source, f"{key}[{i + 1}][{j + 1}]"))
            except ModelError as exc:
                problems.extend(exc.problems)
        rows.append(parsed)
    return rows


def _entry(value: object, params: Sequence[str], source: str, key: str,
           section: str = "matrices") -> Expression:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ModelError(Problem(f"expected a number or an expression, got "
                                 f"{type(value).__name__}", source, section, key))
    try:
        return parse(value, allowed=params, file=source, section=section, key=key)
    except ExpressionError as exc:
        raise ModelError(list(exc.problems)) from None



__all__ = ["read_matrix_spec", "read_matrix_file", "is_file_reference", "DOFS_KEY", "DROP_KEY",
           "read_vector_file", "resolve_matrix_path",
           "open_regular_file",
           "read_bounded", "FileRefused", "MATRIX_KEYS", "FILE_SUFFIXES",
           "SPEED_KEY"]
