"""Result files of a study: Parquet or CSV, written chunk by chunk, resumable.

Rows arrive in chunk order and are appended at once, so memory holds one
chunk, whatever the study's size.  The file is written under a temporary
name (``FILE.part``) and renamed when the writer closes -- at the end, and
also when the study is interrupted, so that an interrupted study leaves a
valid file holding its first complete chunks.  The study's description
(model, request, chunk size) is stored with the rows (Parquet metadata, or a
``FILE.study.json`` beside a CSV file); ``resume`` checks it, keeps the
complete chunks and continues after them.

Examples
--------
>>> import tempfile, os, numpy as np
>>> path = os.path.join(tempfile.mkdtemp(), "r.csv")
>>> writer = ResultWriter(path, {"study": 1})
>>> writer.write({"sample": np.arange(2), "k": np.array([1.0, 2.0])})
>>> writer.close()
>>> open(path).read().splitlines()
['sample,k', '0,1.0', '1,2.0']
"""

from __future__ import annotations

import json
import math
import os
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError, Problem

if TYPE_CHECKING:
    import pyarrow

METADATA_KEY = b"resonant.study"
FORMATS = (".parquet", ".csv")


def check_output(path: str | os.PathLike[str]) -> Path:
    """The output path, checked once before any work: a .parquet or .csv file that can be
    written, whose temporary ``FILE.part`` and (CSV) ``FILE.study.json`` can be written too.

    Parameters
    ----------
    path : str or path

    Returns
    -------
    Path

    Raises
    ------
    ModelError
        Naming the file: a wrong ending, a missing or unwritable folder, or the file (or
        one of its companions) being a folder or not a regular file.

    Examples
    --------
    >>> check_output("/nope/r.csv")
    Traceback (most recent call last):
    resonant.errors.ModelError: /nope/r.csv: the folder '/nope' of the study's output does not exist
    """
    p = Path(path)
    name = str(path)
    if p.suffix.lower() not in FORMATS:
        raise ModelError(Problem("the study's output must end in .parquet or .csv", name))
    folder = p.parent if str(p.parent) else Path(".")
    if not folder.is_dir():
        raise ModelError(Problem(f"the folder '{folder}' of the study's output does not "
                                 "exist", name))
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ModelError(Problem(f"cannot write the study's output: the folder '{folder}' "
                                 "is not writable", name))
    companions = [p, p.with_name(p.name + ".part")]
    if p.suffix.lower() == ".csv":
        companions.append(_sidecar(p))
    for item in companions:
        if (item.exists() or item.is_symlink()) and not item.is_file():
            what = "a folder" if item.is_dir() else "not a regular file"
            raise ModelError(Problem(f"cannot write the study's output: '{item.name}' is "
                                     f"{what}; remove it or choose another name", name))
    return p


def _sidecar(path: Path) -> Path:
    return path.with_name(path.name + ".study.json")


def _damaged(path: Path, what: str) -> ModelError:
    return ModelError(Problem(f"cannot resume from this file: {what}; remove it (or write to "
                              "a new file) to start the study afresh", str(path)))


def read_description(path: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The study description stored with a result file (None if there is no file).

    The file is untrusted input: what cannot be read is an error naming it.

    Parameters
    ----------
    path : str or path

    Returns
    -------
    dict or None

    Raises
    ------
    ModelError
        For a file that is damaged, truncated or has no study description.
    """
    p = Path(path)
    if not p.is_file():
        return None
    if p.suffix.lower() == ".parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        try:
            meta = pq.read_schema(p).metadata or {}
        except (OSError, ValueError, pa.ArrowException):
            raise _damaged(p, "it is not a readable Parquet file (damaged or truncated)"
                           ) from None
        raw = meta.get(METADATA_KEY)
        if raw is None:
            raise _damaged(p, "it was not written by a study (no study description)")
    else:
        side = _sidecar(p)
        if not side.is_file():
            raise _damaged(p, f"its study description '{side.name}' is missing")
        try:
            raw = read_bounded_text(side)
        except (OSError, ValueError):
            raise _damaged(p, f"its study description '{side.name}' cannot be read"
                           ) from None
    try:
        found = json.loads(raw)
    except (ValueError, RecursionError):
        found = None
    if not isinstance(found, dict):
        raise _damaged(p, "its study description is damaged")
    return found


def read_bounded_text(path: Path, limit: int = 2**24) -> str:
    """A small text file (a study description), refused above ``limit`` bytes."""
    with path.open("rb") as handle:
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise ValueError("too large")
    return data.decode("utf-8")


def completed_rows(path: str | os.PathLike[str]) -> int:
    """The number of rows already in a result file (0 if there is none).

    Parameters
    ----------
    path : str or path

    Returns
    -------
    int
    """
    p = Path(path)
    if not p.is_file():
        return 0
    if p.suffix.lower() == ".parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        try:
            return int(pq.ParquetFile(p).metadata.num_rows)
        except (OSError, ValueError, pa.ArrowException):
            raise _damaged(p, "it is not a readable Parquet file (damaged or truncated)"
                           ) from None
    with p.open("rb") as handle:  # complete lines only: a cut last line is no row
        return max(0, sum(1 for line in handle if line.endswith(b"\n")) - 1)


def _number(value: object) -> bool:
    """A cell that reads as a floating-point number (NaN, infinities and blanks
    included; not digits beyond the range of floats, which read as infinite)."""
    try:
        x = float(value)  # type: ignore[arg-type]  # any cell: float() is the test
    except (TypeError, ValueError, OverflowError):
        return False
    return not math.isinf(x) or str(value).strip().lstrip("+-").lower() in ("inf", "infinity")


def check_rows(path: str | os.PathLike[str], columns: list[str], text: tuple[str, ...],
               rows: int) -> None:
    """Check the first ``rows`` rows of a result file before a resume keeps them: the
    columns (names and order) are ``columns``, those not in ``text`` hold numbers, and the
    samples are numbered 0, 1, ... in order.

    Parameters
    ----------
    path : str or path
    columns : list of str
    text : tuple of str
        The columns of text (status, reason).
    rows : int

    Raises
    ------
    ModelError
        Naming the file and what is wrong in it.
    """
    p = Path(path)
    if rows <= 0:
        return
    import pandas as pd

    try:
        if p.suffix.lower() == ".parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            try:
                source = pq.ParquetFile(p)
                names = list(source.schema_arrow.names)
                groups: list[int] = []
                count = 0
                while count < rows and len(groups) < source.num_row_groups:
                    count += source.metadata.row_group(len(groups)).num_rows
                    groups.append(len(groups))
                frame = source.read_row_groups(groups).to_pandas()
            except (OSError, ValueError, pa.ArrowException):
                raise _damaged(p, "its rows cannot be read (damaged or truncated)") from None
        else:
            with p.open("r", encoding="utf-8", newline="") as handle:
                names = handle.readline().rstrip("\r\n").split(",")
            if names != columns:
                raise _damaged(p, f"its header is '{','.join(names)}', not the study's "
                               f"'{','.join(columns)}'")
            try:
                frame = pd.read_csv(p, nrows=rows, keep_default_na=False,
                                    na_values={c: ["", "NaN", "nan"] for c in columns
                                               if c not in text},
                                    dtype={c: str for c in text})
            except (OSError, ValueError, UnicodeDecodeError) as exc:
                raise _damaged(p, f"its rows cannot be read ({exc})") from None
    except MemoryError:
        raise _damaged(p, "its rows do not fit in memory") from None
    if names != columns:
        raise _damaged(p, f"its columns are {', '.join(names)}, not the study's "
                       f"{', '.join(columns)}")
    frame = frame.iloc[:rows]
    if len(frame) < rows:
        raise _damaged(p, f"it holds {len(frame)} readable rows, not {rows}")
    for column in columns:
        if column in text:
            continue
        values = frame[column]
        if not (pd.api.types.is_numeric_dtype(values) or pd.api.types.is_bool_dtype(values)):
            bad = next((i for i, v in enumerate(values) if not _number(v)), 0)
            raise _damaged(p, f"column '{column}' holds '{str(values.iloc[bad])[:40]}' in row "
                           f"{bad + 1}, not a number")
    if not np.array_equal(frame["sample"].to_numpy(), np.arange(rows)):
        raise _damaged(p, "its samples are not numbered 0, 1, 2, ... in order")


class ResultWriter:
    """Appends chunks of rows to a Parquet or CSV file (see the module docstring).

    Parameters
    ----------
    path : str or path
    description : dict
        The study's description, stored with the rows.
    keep_rows : int
        Rows of an existing file to keep (``resume``); 0 starts afresh.
    empty : dict, optional
        The columns with no rows (names and types): written when a stopped study closes
        the writer before any row was, so that it leaves a file to resume.
    keep : list of str, optional
        Columns whose rows a Parquet writer also keeps as written (the kept rows of a
        resume among them), for :meth:`kept_rows`: the rows as reading the file back
        would give them, without reading it.
    """

    def __init__(self, path: str | os.PathLike[str], description: dict[str, Any],
                 keep_rows: int = 0, empty: dict[str, np.ndarray] | None = None,
                 keep: list[str] | None = None) -> None:
        self.path = Path(path)
        self.empty = empty
        self._keep = keep
        self._kept: list[pyarrow.Table] = []
        self.part = self.path.with_name(self.path.name + ".part")
        self.description = description
        self.parquet = self.path.suffix.lower() == ".parquet"
        self._writer: Any = None
        self.rows = 0
        # one chunk is written on a thread while the next is computed (pyarrow and the
        # file system release the GIL); at most one write is pending
        self._thread = ThreadPoolExecutor(max_workers=1, thread_name_prefix="resonant-writer")
        self._pending: Future[None] | None = None
        if self.part.exists():
            self.part.unlink()
        if keep_rows:
            self._copy(keep_rows)

    def _copy(self, keep_rows: int) -> None:
        """Copy the first ``keep_rows`` rows of the existing file (whole chunks)."""
        if self.parquet:
            import pyarrow.parquet as pq

            old = pq.ParquetFile(self.path)
            for i in range(old.num_row_groups):
                table = old.read_row_group(i)
                if self.rows + table.num_rows > keep_rows:
                    break
                self._write_table(table)
            return
        with self.path.open("rb") as src, self.part.open("wb") as dst:
            for i, line in enumerate(src):
                if i > keep_rows:
                    break
                dst.write(line)
        self.rows = keep_rows

    def _write_table(self, table: pyarrow.Table) -> None:
        import pyarrow.parquet as pq

        if self._writer is None:
            meta = dict(table.schema.metadata or {})
            meta[METADATA_KEY] = json.dumps(self.description, sort_keys=True).encode()
            self._schema = table.schema.with_metadata(meta)
            # dictionary pages for the text columns (status, reason) only: numbers are
            # nearly all distinct, and a dictionary of them costs time and space
            text = [f.name for f in self._schema
                    if str(f.type).startswith(("dictionary", "string"))]
            self._writer = pq.ParquetWriter(self.part, self._schema,
                                            use_dictionary=text or False)
        table = table.cast(self._schema)
        self._writer.write_table(table)
        if self._keep is not None:
            self._kept.append(table.select(self._keep))
        self.rows += table.num_rows

    def kept_rows(self) -> Any:
        """The kept columns of every row written, as a DataFrame: what ``pandas.read_parquet``
        of those columns gives (the same types, categories for the text columns), or None
        (a CSV file, no ``keep``, no rows).

        Returns
        -------
        pandas.DataFrame or None
        """
        if not self._kept:
            return None
        import pyarrow as pa

        return pa.concat_tables(self._kept).to_pandas()

    def write(self, columns: dict[str, np.ndarray]) -> None:
        """Append one chunk.

        Parameters
        ----------
        columns : dict
            column -> array, all of one length.
        """
        self._wait()
        self._pending = self._thread.submit(self._append, columns)

    def _wait(self) -> None:
        """Finish the pending write (raising what it raised)."""
        pending, self._pending = self._pending, None
        if pending is not None:
            pending.result()

    def _append(self, columns: dict[str, np.ndarray]) -> None:
        if self.parquet:
            import pyarrow as pa

            self._write_table(pa.table({k: _text_column(v) if v.dtype.kind in "OU" else v
                                        for k, v in columns.items()}))
            return
        import pandas as pd

        frame = pd.DataFrame(columns)
        header = self.rows == 0 and not self.part.exists()
        with self.part.open("a", encoding="utf-8", newline="") as handle:
            frame.to_csv(handle, index=False, header=header)
        self.rows += len(frame)

    def close(self, stopped: bool = False) -> None:
        """Finish the file (also after an interruption: it then holds the rows so far).

        Parameters
        ----------
        stopped : bool
            The study was stopped (an interrupt, the time limit): the file is written even
            with no rows, for a resume.
        """
        try:
            self._wait()
        finally:
            self._thread.shutdown(wait=True)
            self._finish(stopped)

    def _finish(self, stopped: bool) -> None:
        if (stopped and self.empty is not None and self._writer is None
                and not self.part.exists()):
            self._append(self.empty)
        if self.parquet and self._writer is not None:
            self._writer.close()
            self._writer = None
        if not self.part.exists():
            return
        if not self.parquet:
            _sidecar(self.path).write_text(json.dumps(self.description, sort_keys=True),
                                           encoding="utf-8")
        os.replace(self.part, self.path)


def _text_column(values: np.ndarray) -> Any:
    """A column of strings, dictionary-encoded; one repeated value (a chunk whose samples
    are all ok) without a conversion per row."""
    import pyarrow as pa

    if len(values) and (values == values[0]).all():
        return pa.DictionaryArray.from_arrays(pa.array(np.zeros(len(values), np.int32)),
                                              pa.array([str(values[0])]))
    return pa.array(values).dictionary_encode()


def read_columns(path: str | os.PathLike[str], columns: list[str]) -> dict[str, np.ndarray]:
    """Some columns of a result file as arrays (strings as an array of str).

    Parameters
    ----------
    path : str or path
    columns : list of str

    Returns
    -------
    dict
    """
    p = Path(path)
    if p.suffix.lower() == ".parquet":
        import pyarrow.parquet as pq

        table = pq.read_table(p, columns=columns)
        return {c: np.asarray(table.column(c).to_numpy()) if not str(
            table.column(c).type).startswith(("dictionary", "string"))
            else np.asarray(table.column(c).cast("string").to_numpy(zero_copy_only=False),
                            dtype=str) for c in columns}
    import pandas as pd

    frame = pd.read_csv(p, usecols=columns, keep_default_na=False,
                        na_values={c: ["", "NaN", "nan"] for c in columns
                                   if c not in ("status", "reason")})
    return {c: frame[c].to_numpy() for c in columns}


__all__ = ["ResultWriter", "check_output", "check_rows", "completed_rows", "read_columns",
           "read_description"]
