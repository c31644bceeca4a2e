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
import os
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ModelError

METADATA_KEY = b"resonant.study"
FORMATS = (".parquet", ".csv")


def check_output(path: str | os.PathLike[str]) -> Path:
    """The output path, checked: a .parquet or .csv file in an existing directory.

    Parameters
    ----------
    path : str or path

    Returns
    -------
    Path
    """
    p = Path(path)
    if p.suffix.lower() not in FORMATS:
        raise ModelError(f"the study's output '{p}' must end in .parquet or .csv")
    if not p.parent.is_dir():
        raise ModelError(f"the directory of the study's output '{p}' does not exist")
    if p.exists() and not p.is_file():
        raise ModelError(f"the study's output '{p}' exists and is not a file")
    return p


def _sidecar(path: Path) -> Path:
    return path.with_name(path.name + ".study.json")


def read_description(path: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The study description stored with a result file (None if it has none).

    Parameters
    ----------
    path : str or path

    Returns
    -------
    dict or None
    """
    p = Path(path)
    try:
        if p.suffix.lower() == ".parquet":
            import pyarrow.parquet as pq

            meta = pq.read_schema(p).metadata or {}
            raw = meta.get(METADATA_KEY)
            return None if raw is None else json.loads(raw)
        return json.loads(_sidecar(p).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


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
        import pyarrow.parquet as pq

        return int(pq.ParquetFile(p).metadata.num_rows)
    with p.open("rb") as handle:
        return max(0, sum(1 for _ in handle) - 1)


class ResultWriter:
    """Appends chunks of rows to a Parquet or CSV file (see the module docstring).

    Parameters
    ----------
    path : str or path
    description : dict
        The study's description, stored with the rows.
    keep_rows : int
        Rows of an existing file to keep (``resume``); 0 starts afresh.
    """

    def __init__(self, path: str | os.PathLike[str], description: dict[str, Any],
                 keep_rows: int = 0) -> None:
        self.path = Path(path)
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

    def _write_table(self, table: Any) -> None:
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
        self._writer.write_table(table.cast(self._schema))
        self.rows += table.num_rows

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

    def close(self) -> None:
        """Finish the file (also after an interruption: it then holds the rows so far)."""
        try:
            self._wait()
        finally:
            self._thread.shutdown(wait=True)
            self._finish()

    def _finish(self) -> None:
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


__all__ = ["ResultWriter", "check_output", "completed_rows", "read_columns",
           "read_description"]
