"""Numbers from a CSV file a model names: a load vector, a spectral density's table.

One row of numbers a line, separated by commas (or semicolons); a first line that is not
numbers is a header; ``#`` starts a comment; empty lines are skipped.  The file is
untrusted: read through the model's file policy (inside the model's folder or an allowed
one: :func:`~resonant.model.matrix_files.resolve_matrix_path`), a regular file of at most
:data:`MAX_BYTES`, at most ``max_rows`` rows, every problem named with its line.

Examples
--------
>>> import os, tempfile
>>> from pathlib import Path
>>> with tempfile.TemporaryDirectory() as folder:
...     _ = open(os.path.join(folder, "psd.csv"), "w").write("f,G\\n20,0.01\\n2000,0.01\\n")
...     table = read_csv_table("psd.csv", 2, Path(folder), max_rows=10)
>>> table.tolist()
[[20.0, 0.01], [2000.0, 0.01]]
"""

from __future__ import annotations

import math
import os
from array import array
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..errors import printable
from .files import FileRefused, open_regular_file, read_bounded
from .matrix_files import resolve_matrix_path

#: the largest CSV file read
MAX_BYTES = 200 * 2**20


def read_csv_table(value: str, columns: int, base_dir: Path | None,
                   allow_paths: Sequence[str | os.PathLike[str]] = (), *,
                   max_rows: int) -> np.ndarray:
    """The rows of ``columns`` finite numbers of the CSV file ``value`` (relative to the
    model's folder), as an array of shape (rows, columns).

    Parameters
    ----------
    value : str
        The file as the model names it.
    columns : int
        The numbers in each row.
    base_dir : Path or None
        The model's folder.
    allow_paths : sequence of paths
        Other folders files may be read from.
    max_rows : int
        The most rows read.

    Returns
    -------
    ndarray

    Raises
    ------
    FileRefused
        With a message safe to show (the line where a row is wrong), for a file outside
        the policy, unreadable, too large, with a row that is not ``columns`` finite
        numbers, or without rows.
    """
    path = resolve_matrix_path(value, base_dir, allow_paths)
    try:
        with open_regular_file(path, follow_symlinks=False, max_bytes=MAX_BYTES) as handle:
            data = read_bounded(handle, MAX_BYTES)
    except OSError as exc:
        raise FileRefused(f"cannot read it ({exc.strerror or 'error'})") from None
    numbers = array("d")
    header = True
    for number, raw in enumerate(data.removeprefix(b"\xef\xbb\xbf").split(b"\n"), start=1):
        line = raw.decode("utf-8", errors="replace").split("#", 1)[0].strip()
        if not line:
            continue
        parts = [p.strip() for p in line.replace(";", ",").split(",")]
        row = _numbers(parts) if len(parts) == columns else None
        if row is None and header and not _parsable(parts):
            header = False   # a first line of names
            continue
        header = False
        if row is None:
            wanted = "one number" if columns == 1 else f"{columns} numbers"
            raise FileRefused(f"line {number}: expected {wanted}, got "
                              f"'{printable(line, limit=60)}'")
        if len(numbers) >= max_rows * columns:
            raise FileRefused(f"line {number}: more than {max_rows} rows")
        numbers.extend(row)
    if not numbers:
        raise FileRefused("it holds no rows of numbers")
    return np.frombuffer(numbers, dtype=float).reshape(-1, columns).copy()


def _parsable(parts: list[str]) -> bool:
    """Whether every part reads as a number (finite or not): not a header."""
    try:
        [float(p) for p in parts]
    except ValueError:
        return False
    return True


def _numbers(parts: list[str]) -> list[float] | None:
    """The parts as finite numbers, or None."""
    try:
        row = [float(p) for p in parts]
    except ValueError:
        return None
    return row if all(math.isfinite(x) for x in row) else None


__all__ = ["MAX_BYTES", "read_csv_table"]
