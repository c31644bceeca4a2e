"""Nastran OUTPUT4 records read in bulk: resonant's own OP4 reader (no pyYeti needed).

An OP4 file is a sequence of matrices, each a header, one record per non-zero column and
a trailer record (column ``ncol + 1``). Binary files are Fortran unformatted records
(a 4-byte length before and after each record; integers of 4 or 8 bytes; either byte
order); ASCII files are fixed-width lines (``1P,5E16.9`` and the like). A column's
values are stored

* dense: ``icol, irow, nw`` then the values from row ``irow`` on;
* sparse, "bigmat" (more than 65535 rows, or the rows written negative): ``icol, 0, nw``
  then strings ``L, irow`` + ``L - 1`` words of values;
* sparse, "non-bigmat": strings ``IS = irow + 65536 (L + 1)`` + ``L`` words of values.

Why its own reader: a 300,000-row file has 300,000 column records and more strings; a
reader that appends value by value in Python (pyYeti's) spends seconds there. Here only
the record and string headers are walked in Python (a few integers each); the values are
gathered afterwards with one vectorized index into the file's bytes (binary) or one
fixed-width parse of the joined value lines (ASCII). Every header is checked (record
lengths before and after, strings inside their record, rows and columns inside the
matrix); anything else is a :class:`~resonant.model.files.FileRefused` saying what is
wrong, never an exception of the parser.

Examples
--------
>>> import struct
>>> head = struct.pack("<i4i8si", 24, 1, 1, 1, 2, b"KAA     ", 24)
>>> column = struct.pack("<i3idi", 20, 1, 1, 2, 4.0, 20)
>>> trailer = struct.pack("<i3idi", 20, 2, 1, 1, 1.0, 20)
>>> [entry.name for entry in op4_entries(head + column + trailer)]
['kaa']
>>> rows, columns, values = op4_values(head + column + trailer, op4_entries(head + column
...                                    + trailer)[0])
>>> rows.tolist(), columns.tolist(), values.tolist()
([0], [0], [4.0])
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass

import numpy as np

from .files import FileRefused

#: rows from which Nastran writes the sparse "bigmat" string headers
BIGMAT_ROWS = 65536
_TRUNCATED = "it is truncated or not a valid OUTPUT4 file"


@dataclass(frozen=True)
class Op4Entry:
    """One matrix of an OP4 file, from its header.

    Attributes
    ----------
    name : str
        The matrix name, lower case, blanks removed.
    rows, columns : int
        Its size.
    form, kind : int
        Nastran's form (1 square, 2 rectangular, 6 symmetric, ...) and type (1 real
        single, 2 real double, 3 complex single, 4 complex double).
    start : int
        Where its first column record starts: a word index (binary: 4-byte words) or a
        line index (ASCII).
    bigmat : bool
        Whether sparse strings have the bigmat header ``L, irow``.
    stop : int
        Binary: the word index of its trailer record (-1 for ASCII).
    """

    name: str
    rows: int
    columns: int
    form: int
    kind: int
    start: int
    bigmat: bool
    stop: int = -1


@dataclass(frozen=True)
class _Binary:
    """The layout of a binary file: byte order and integer size."""

    endian: str
    int_bytes: int

    def ints(self, count: int) -> struct.Struct:
        return struct.Struct(f"{self.endian}{count}{'i' if self.int_bytes == 4 else 'q'}")


def _layout(data: bytes) -> _Binary | None:
    """The binary layout, or None for an ASCII file (decided by the first record length:
    24 bytes for 4-byte integers, 48 for 8-byte ones)."""
    if len(data) < 16:
        raise FileRefused(f"it is empty or nearly empty ({len(data)} bytes), not an "
                          "OUTPUT4 file")
    if min(data[:4]) != 0:
        return None
    for endian in "<>":
        length = struct.unpack_from(f"{endian}i", data, 0)[0]
        if length in (24, 48):
            return _Binary(endian, 4 if length == 24 else 8)
    raise FileRefused("it is not an OUTPUT4 file (its first record is no matrix header)")


def op4_entries(data: bytes) -> list[Op4Entry]:
    """The matrices of an OP4 file's bytes, from their headers (values not read).

    Parameters
    ----------
    data : bytes
        The whole file.

    Returns
    -------
    list of Op4Entry

    Raises
    ------
    FileRefused
        For a file that is no OP4 file or ends inside a record.
    """
    layout = _layout(data)
    if layout is None:
        return _ascii_entries(_ascii_text(data))
    return _binary_entries(data, layout)


@dataclass(frozen=True)
class Op4Runs:
    """The stored values of one matrix as runs of consecutive rows in one column.

    Attributes
    ----------
    rows, columns : tuple of int
        The matrix size.
    first_rows, counts, at_columns : ndarray
        Each run's first row and column (zero-based) and its number of values.
    values : ndarray
        All values (float64), run after run.
    """

    rows: int
    columns: int
    first_rows: np.ndarray
    counts: np.ndarray
    at_columns: np.ndarray
    values: np.ndarray

    def coo(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rows, columns and values of every stored entry."""
        total = int(self.counts.sum())
        within = np.arange(total) - np.repeat(np.cumsum(self.counts) - self.counts,
                                              self.counts)
        return (np.repeat(self.first_rows, self.counts) + within,
                np.repeat(self.at_columns, self.counts), self.values)

    def dense(self) -> np.ndarray:
        """The matrix as a float64 array (few runs: copied run by run, into Fortran order
        where a column is contiguous, as the file stores it)."""
        matrix = np.zeros((self.rows, self.columns), order="F")
        if len(self.counts) > _WALKED_RECORDS:
            rows, columns, values = self.coo()
            matrix[rows, columns] = values
            return matrix
        taken = 0
        for row, count, column in zip(self.first_rows.tolist(), self.counts.tolist(),
                                      self.at_columns.tolist()):
            matrix[row:row + count, column] = self.values[taken:taken + count]
            taken += count
        return matrix


def op4_runs(data: bytes, entry: Op4Entry) -> Op4Runs:
    """The stored values of one real matrix, run by run, in the file's (column) order.

    Parameters
    ----------
    data : bytes
        The whole file.
    entry : Op4Entry
        One of :func:`op4_entries` (of type 1 or 2).

    Returns
    -------
    Op4Runs

    Raises
    ------
    FileRefused
        For a record or string that does not fit (the matrix is named by the caller).
    """
    if entry.kind not in (1, 2):
        raise FileRefused(f"it is of Nastran type {entry.kind}, not real")
    layout = _layout(data)
    if layout is None:
        runs = _ascii_values(_ascii_text(data), entry)
    else:
        runs = _binary_values(data, layout, entry)
    first_rows, counts, columns = runs.first_rows, runs.counts, runs.at_columns
    if len(counts) and (first_rows.min() < 0 or (first_rows + counts).max() > entry.rows
                        or columns.min() < 0 or columns.max() >= entry.columns):
        raise FileRefused(f"a column holds rows outside its {entry.rows} x "
                          f"{entry.columns} size")
    return runs


def op4_values(data: bytes, entry: Op4Entry) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The stored entries of one real matrix: zero-based rows, columns and float64 values
    (:func:`op4_runs` expanded).

    Parameters
    ----------
    data : bytes
        The whole file.
    entry : Op4Entry
        One of :func:`op4_entries`.

    Returns
    -------
    rows, columns, values : ndarray
    """
    return op4_runs(data, entry).coo()


# -- binary ----------------------------------------------------------------------------------

def _words(data: bytes, layout: _Binary) -> np.ndarray:
    """The file as native int32 words (every record length, integer and value of a binary
    OP4 file starts on a 4-byte boundary)."""
    if len(data) % 4:
        raise FileRefused(f"{_TRUNCATED} (its length is no whole number of words)")
    return np.frombuffer(data, dtype=f"{layout.endian}i4").astype(np.int32, copy=False)


def _integers_at(words: np.ndarray, at: np.ndarray, layout: _Binary) -> np.ndarray:
    """The integers (4 or 8 bytes) that start at word indices ``at``, as int64."""
    if layout.int_bytes == 4:
        return words[at].astype(np.int64)
    high, low = (at + 1, at) if layout.endian == "<" else (at, at + 1)
    return (words[high].astype(np.int64) << 32) | (words[low].astype(np.int64) & 0xFFFFFFFF)


#: records walked one by one before the rest is walked by vector steps
_WALKED_RECORDS = 4096


class _Broken(FileRefused):
    """A record chain that breaks: ``good`` holds the word indices of the records before
    the break (to name the matrix it breaks in)."""

    def __init__(self, message: str, good: np.ndarray) -> None:
        super().__init__(message)
        self.good = good


_BROKEN = (f"{_TRUNCATED} (a record ends before its length says, or its closing length "
           "differs from its opening one)")


def _chain(words: np.ndarray, first: int, stop: int) -> np.ndarray:
    """The word indices of the records from word ``first`` to word ``stop``, which the last
    record must end at: each record is its length, the payload, the length again.

    The first records are walked one by one (a file of few long records, a dense matrix,
    is done there); the rest by :func:`_chain_by_vectors`.
    """
    view = memoryview(words.data)  # Python ints, fast one by one
    found: list[int] = []
    at = first
    while at < stop and len(found) < _WALKED_RECORDS:
        length = view[at]
        closing = at + 1 + length // 4
        if length <= 0 or length % 4 or closing >= stop or view[closing] != length:
            raise _Broken(_BROKEN, np.array(found, dtype=np.int64))
        found.append(at)
        at = closing + 1
    walked = np.array(found, dtype=np.int64)
    if at == stop:
        return walked
    try:
        return np.concatenate([walked, _chain_by_vectors(words, at, stop)])
    except _Broken as broken:
        raise _Broken(str(broken), np.concatenate([walked, broken.good])) from None


def _chain_by_vectors(words: np.ndarray, first: int, stop: int) -> np.ndarray:
    """:func:`_chain` without a Python loop: every word that could open a record (a length
    whose closing copy is where it says) is a candidate; the successor of each candidate
    is the word after its record; the records are the candidates reached from ``first``,
    found by pointer doubling (log2 of the number of records vector steps)."""
    lengths = words[first:stop]
    candidates = np.flatnonzero((lengths > 0) & (lengths % 4 == 0)) + first
    closing = candidates + 1 + words[candidates] // 4
    inside = closing < stop
    candidates, closing = candidates[inside], closing[inside]
    candidates = candidates[words[closing] == words[candidates]]
    if not len(candidates) or candidates[0] != first:
        raise _Broken(f"{_TRUNCATED} (a record's closing length is not where its opening "
                      "one says)", np.zeros(0, dtype=np.int64))
    following = candidates + 2 + words[candidates] // 4
    found = np.minimum(np.searchsorted(candidates, following), len(candidates) - 1)
    ended, broken = len(candidates), len(candidates) + 1
    jump = np.where(candidates[found] == following, found,
                    np.where(following == stop, ended, broken))
    jump = np.concatenate([jump, [ended, broken]])
    step = jump.copy()   # one record ahead (jump becomes 2**k records ahead)
    reached = np.zeros(len(jump), dtype=bool)
    reached[0] = True
    count = 1
    while True:  # reached holds the records 0 .. 2**k - 1 steps from the first
        reached[jump[np.flatnonzero(reached)]] = True
        jump = jump[jump]
        if int(reached.sum()) == count:
            break
        count = int(reached.sum())
    if reached[broken] or not reached[ended]:
        # the records before the break: those reached up to the one whose next is broken
        good = np.flatnonzero(reached[:ended])
        last = good[step[good] == broken]
        good = good[good <= last[0]] if len(last) else good
        raise _Broken(_BROKEN, candidates[good])
    return candidates[reached[:ended]]


def _binary_entries(data: bytes, layout: _Binary) -> list[Op4Entry]:
    words = _words(data, layout)
    try:
        records = _chain(words, 0, len(words))
    except _Broken as broken:   # named by the matrix whose records it breaks in
        raise FileRefused(str(broken).replace(
            f"{_TRUNCATED} (", f"{_TRUNCATED} ({_broken_in(data, words, broken.good, layout)}",
            1)) from None
    column_field = _integers_at(words, records + 1, layout)
    entries = []
    at = 0
    while at < len(records):
        entry = _binary_header(data, int(records[at]), layout)
        after = column_field[at + 1:] > entry.columns
        if not after.any():
            raise FileRefused(f"{_TRUNCATED} (matrix {entry.name.upper()} ends before its "
                              "last column)")
        trailer = at + 1 + int(np.argmax(after))
        entries.append(Op4Entry(entry.name, entry.rows, entry.columns, entry.form,
                                entry.kind, int(records[at + 1]), entry.bigmat,
                                int(records[trailer])))
        at = trailer + 1
    return entries


def _broken_in(data: bytes, words: np.ndarray, good: np.ndarray, layout: _Binary) -> str:
    """Where a broken record chain breaks: "in matrix NAME: " for the matrix whose header
    is the last before the break (the records ``good``), "" before the first header or
    where the headers cannot be told."""
    if not len(good):   # (in the first record)
        return ""
    column_field = _integers_at(words, good + 1, layout)
    name, at = "", 0
    try:
        while at < len(good):
            entry = _binary_header(data, int(good[at]), layout)
            name = entry.name.upper()
            after = column_field[at + 1:] > entry.columns
            if not after.any():   # its trailer is not among the good records: broken in it
                break
            at += 2 + int(np.argmax(after))
            name = ""   # (complete: the break comes after it, in the next header)
    except FileRefused:
        return ""
    return f"in matrix {name}: " if name else "after the last complete matrix: "


def _binary_header(data: bytes, at: int, layout: _Binary) -> Op4Entry:
    """The matrix header record at word ``at``."""
    size = layout.int_bytes
    length = struct.unpack_from(f"{layout.endian}i", data, 4 * at)[0]
    if length != 6 * size:
        raise FileRefused(f"{_TRUNCATED} (a matrix header of {length} bytes)")
    columns, rows, form, kind = layout.ints(4).unpack_from(data, 4 * at + 4)
    name = data[4 * at + 4 + 4 * size:4 * at + 4 + length].decode("ascii", "replace")
    name = name.replace(" ", "").replace("\x00", "").lower()
    if columns < 0 or kind not in (1, 2, 3, 4):
        raise FileRefused(f"{_TRUNCATED} (matrix {name.upper()}: {columns} columns, "
                          f"type {kind})")
    return Op4Entry(name, abs(rows), columns, form, kind, -1, rows < 0 or rows >= BIGMAT_ROWS)


def _value_format(layout: _Binary, kind: int) -> tuple[int, int]:
    """(integers per value, bytes per value): single precision takes one 4-byte word; a
    double takes two 4-byte words or one 8-byte word."""
    if layout.int_bytes == 8:
        return 1, 8
    return (1, 4) if kind == 1 else (2, 8)


@dataclass
class _Runs:
    """Runs of consecutive values: word index of the first value, count, first row
    (zero-based), column (zero-based)."""

    at: list[np.ndarray]
    counts: list[np.ndarray]
    rows: list[np.ndarray]
    columns: list[np.ndarray]

    def add(self, at: np.ndarray, counts: np.ndarray, rows: np.ndarray,
            columns: np.ndarray) -> None:
        self.at.append(at)
        self.counts.append(counts)
        self.rows.append(rows)
        self.columns.append(columns)

    def joined(self) -> tuple[np.ndarray, ...]:
        return tuple(np.concatenate(part) if part else np.zeros(0, dtype=np.int64)
                     for part in (self.at, self.counts, self.rows, self.columns))


def _binary_runs(words: np.ndarray, layout: _Binary, entry: Op4Entry) -> _Runs:
    """The runs of one matrix: its column records (vectorized) and their strings (one
    vector step per string index: the i-th string of every sparse column at once)."""
    unit = layout.int_bytes // 4
    per_value = _value_format(layout, entry.kind)[0]
    try:
        records = _chain(words, entry.start, entry.stop) if entry.stop > entry.start else \
            np.zeros(0, dtype=np.int64)
    except _Broken as broken:
        raise FileRefused(str(broken).replace(
            f"{_TRUNCATED} (", f"{_TRUNCATED} (in matrix {entry.name.upper()}: ", 1)) from None
    payload = words[records].astype(np.int64) // 4
    if np.any(payload < 3 * unit):
        raise FileRefused("a column record too short for its header")
    column, row, count = (_integers_at(words, records + 1 + k * unit, layout)
                          for k in range(3))
    if np.any((column < 1) | (column > entry.columns) | (count < 0)) or \
            np.any(payload != 3 * unit + count * unit):
        raise FileRefused("a column record does not fit the matrix or its record length")
    runs = _Runs([], [], [], [])
    dense = row > 0
    if np.any(count[dense] % per_value):
        raise FileRefused("a dense column record holds part of a value")
    runs.add(records[dense] + 1 + 3 * unit, count[dense] // per_value, row[dense] - 1,
             column[dense] - 1)
    sparse = np.flatnonzero(~dense)
    position = records[sparse] + 1 + 3 * unit
    end = records[sparse] + 1 + payload[sparse]
    string_column = column[sparse] - 1
    head = 2 * unit if entry.bigmat else unit
    while len(position):
        if np.any(position + head > end):
            raise FileRefused("a string header runs past its column record")
        if entry.bigmat:
            length = _integers_at(words, position, layout)
            first = _integers_at(words, position + unit, layout)
            stored = length - 1
        else:
            packed = _integers_at(words, position, layout)
            stored = (packed >> 16) - 1
            first = packed - ((stored + 1) << 16)
        values_at = position + head
        if np.any(stored < 0) or np.any(values_at + stored * unit > end):
            raise FileRefused("a string runs past its column record")
        runs.add(values_at, stored // per_value, first - 1, string_column)
        position = values_at + stored * unit
        going = position < end
        position, end, string_column = position[going], end[going], string_column[going]
    return runs


def _gather(data: bytes, endian: str, value_bytes: int, offsets: np.ndarray,
            counts: np.ndarray) -> np.ndarray:
    """The values of all runs, read at once: a view of the file as floats at each of the
    (at most two) alignments the runs start at, indexed by a vector of positions."""
    total = int(counts.sum())
    dtype = np.dtype(f"{endian}f{value_bytes}")
    values = np.empty(total, dtype=np.float64)
    if total == 0:
        return values
    if len(counts) <= _WALKED_RECORDS:  # few long runs (dense columns): copy slices
        taken = 0
        for offset, count in zip(offsets.tolist(), counts.tolist()):
            values[taken:taken + count] = np.frombuffer(data, dtype=dtype, count=count,
                                                        offset=offset)
            taken += count
        return values
    skew = offsets % value_bytes
    run_of = np.repeat(np.arange(len(counts)), counts)
    within = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    for shift in np.unique(skew):
        view = np.frombuffer(data, dtype=dtype, count=(len(data) - shift) // value_bytes,
                             offset=int(shift))
        chosen = skew[run_of] == shift
        positions = (offsets - shift)[run_of[chosen]] // value_bytes + within[chosen]
        values[chosen] = view[positions]
    return values


def _binary_values(data: bytes, layout: _Binary, entry: Op4Entry) -> Op4Runs:
    at, counts, first_rows, columns = _binary_runs(_words(data, layout), layout,
                                                   entry).joined()
    value_bytes = _value_format(layout, entry.kind)[1]
    values = _gather(data, layout.endian, value_bytes, 4 * at, counts)
    return Op4Runs(entry.rows, entry.columns, first_rows, counts, columns, values)


# -- ASCII -----------------------------------------------------------------------------------

def _bare_header(line: bytes) -> bool:
    """Whether a line without a ``.`` is a matrix header without its number format
    (``       6       5       2       1R1``: four I8 integers, then the name)."""
    head, name = line[:32], line[32:].strip()
    try:
        return len(head) == 32 and bool(name) and all(
            int(head[i:i + 8]) is not None for i in range(0, 32, 8))
    except ValueError:
        return False


class _AsciiText:
    """An ASCII OP4 file as lines, and its integer lines (no ``.``: column and string
    headers) parsed at once: their field counts and first three fields."""

    def __init__(self, data: bytes) -> None:
        if b"\r" in data:
            data = data.replace(b"\r\n", b"\n")
        self.data = data
        self.buffer = np.frombuffer(data, dtype=np.uint8)
        newlines = np.flatnonzero(self.buffer == 10)
        self.starts = np.concatenate([[0], newlines + 1])
        self.ends = np.concatenate([newlines, [len(data)]])
        dotted = np.zeros(len(self.starts), dtype=bool)
        dotted[np.searchsorted(newlines, np.flatnonzero(self.buffer == 46))] = True
        self.dotted = dotted
        headers = np.zeros(len(self.starts), dtype=bool)  # matrix headers without a format
        lower = self.buffer | 32
        lettered = np.unique(np.searchsorted(newlines, np.flatnonzero((lower >= 97)
                                                                      & (lower <= 122))))
        for at in lettered[~dotted[lettered]].tolist():
            headers[at] = _bare_header(self.line(at))
        self.integer_lines = np.flatnonzero(~dotted & ~headers & (self.ends > self.starts))
        self.counts, self.fields = self._parse_integer_lines()

    def line(self, at: int) -> bytes:
        return self.data[int(self.starts[at]):int(self.ends[at])]

    def _parse_integer_lines(self) -> tuple[np.ndarray, np.ndarray]:
        """Each integer line's number of fields and its first three fields (0 where it
        has fewer): the lines' bytes taken at once and parsed by numpy."""
        chosen = self.integer_lines
        keep = np.zeros(len(self.starts), dtype=bool)
        keep[chosen] = True
        spans = self.ends - self.starts + 1  # with the newline (the last line has none)
        text = self.buffer[np.repeat(keep, spans)[:len(self.buffer)]]
        blank = (text == 32) | (text == 10)
        opening = ~blank
        opening[1:] &= blank[:-1]
        line_of_field = np.searchsorted(np.cumsum(spans[chosen]), np.flatnonzero(opening),
                                        side="right")
        counts = np.bincount(line_of_field, minlength=len(chosen))
        allowed = np.zeros(256, dtype=bool)
        allowed[list(b"0123456789+- \n")] = True
        values = np.zeros(0, dtype=np.int64)
        if allowed[text].all() and len(text):
            values = np.fromstring(text.tobytes(), dtype=np.int64, sep=" ")
        if len(values) != len(line_of_field):
            raise FileRefused(f"{_TRUNCATED} (a line that is neither numbers nor a header "
                              "of integers)")
        fields = np.zeros((len(chosen), 3), dtype=np.int64)
        offsets = np.cumsum(counts) - counts
        for k in range(3):
            has = counts > k
            fields[has, k] = values[offsets[has] + k]
        # I8 fields that touch (``       310000001``: 3 and 10000001) read as one number:
        # a line of whole I8 fields, more than its numbers, is read again field by field
        # (a non-bigmat string header is one wider field, ``     196609``: left as it is)
        lengths = (self.ends - self.starts)[chosen]
        for i in np.flatnonzero(lengths > 8 * counts).tolist():
            line = self.line(int(chosen[i])).rstrip()
            if len(line) > 8 * counts[i] and len(line) % 8 == 0:
                numbers = _integers(line, -(-len(line) // 8))
                counts[i] = len(numbers)
                fields[i] = (numbers + [0, 0, 0])[:3]
        return counts, fields

    def integer_range(self, first: int, stop: int) -> slice:
        """The integer lines among lines first .. stop - 1."""
        return slice(int(np.searchsorted(self.integer_lines, first)),
                     int(np.searchsorted(self.integer_lines, stop)))


#: the last file parsed: (its bytes, the parse), so that the directory and the values of
#: one read parse the lines once
_LAST_TEXT: list[tuple[bytes, _AsciiText]] = []


def _ascii_text(data: bytes) -> _AsciiText:
    if _LAST_TEXT and _LAST_TEXT[0][0] is data:
        return _LAST_TEXT[0][1]
    text = _AsciiText(data)
    _LAST_TEXT[:] = [(data, text)]
    return text


def forget_parsed_text() -> None:
    """Drop the parse kept for the last ASCII file (its memory)."""
    _LAST_TEXT.clear()


@dataclass(frozen=True)
class _AsciiHeader:
    entry: Op4Entry
    per_line: int
    width: int


def _integers(line: bytes, count: int, width: int = 8) -> list[int]:
    """``count`` integers of a header line: fixed-width fields (Fortran I8, which may
    touch)."""
    try:
        return [int(line[i * width:(i + 1) * width]) for i in range(count)]
    except ValueError:
        raise FileRefused(f"{_TRUNCATED} (a line that should hold {count} integers: "
                          f"{line[:40].decode('ascii', 'replace')!r})") from None


def _ascii_header(text: _AsciiText, at: int) -> _AsciiHeader:
    line = text.line(at).rstrip()
    wide = line.endswith(b"|I16")  # pyYeti's mark: columns and rows in I16, the rest I8
    if wide:
        line = line[:-4]
        columns, rows = _integers(line, 2, 16)
        form, kind = _integers(line[32:], 2)
        name_at = 48
    else:
        columns, rows, form, kind = _integers(line, 4)
        name_at = 32
    name = line[name_at:name_at + 8].decode("ascii", "replace")
    name = name.replace(" ", "").replace("\x00", "").lower()
    number = line[name_at + 8:].strip().upper().decode("ascii", "replace")
    number = number[3:] if number.startswith("1P,") else number
    per_line, length = 5, 16
    split = number.replace("D", "E").find("E")
    if split > 0:
        try:
            per_line, length = int(number[:split]), int(number[split + 1:].split(".")[0])
        except ValueError:
            raise FileRefused(f"matrix {name.upper()}: a number format {number!r} that is "
                              "not Fortran's nEw.d") from None
    if columns < 0 or kind not in (1, 2, 3, 4) or per_line < 1 or length < 1:
        raise FileRefused(f"{_TRUNCATED} (matrix {name.upper()}: {columns} columns, "
                          f"type {kind})")
    entry = Op4Entry(name, abs(rows), columns, form, kind, at + 1,
                     rows < 0 or rows >= BIGMAT_ROWS)
    return _AsciiHeader(entry, per_line, length)


def _ascii_entries(text: _AsciiText) -> list[Op4Entry]:
    """Each matrix from its header line to its trailer (the first column header after
    it with a column beyond the matrix) and the trailer's value line."""
    entries = []
    at = 0
    lines = len(text.starts)
    while at < lines and text.line(at).strip():
        header = _ascii_header(text, at)
        entry = header.entry
        part = text.integer_range(at + 1, lines)
        after = (text.counts[part] == 3) & (text.fields[part, 0] > entry.columns)
        if not after.any():
            raise FileRefused(f"{_TRUNCATED} (matrix {entry.name.upper()} ends before its "
                              "last column)")
        trailer = part.start + int(np.argmax(after))
        stop = int(text.integer_lines[trailer])
        words = int(text.fields[trailer, 2])
        entries.append(Op4Entry(entry.name, entry.rows, entry.columns, entry.form,
                                entry.kind, entry.start, entry.bigmat, stop))
        at = stop + 1 + math.ceil(max(words, 1) / header.per_line)
    return entries


def _ascii_runs(text: _AsciiText, header: _AsciiHeader, stop: int
                ) -> tuple[np.ndarray, ...]:
    """The runs of one matrix's lines ``entry.start .. stop - 1``: for each, its first
    value line, the number of its value lines, its count, first row and column; checked
    against the headers (strings only in sparse columns, their words adding up to the
    column's, the value lines each run needs)."""
    entry, per_line = header.entry, header.per_line
    per_value = 1 if entry.kind & 1 else 2
    part = text.integer_range(entry.start, stop)
    where = text.integer_lines[part]
    counts, fields = text.counts[part], text.fields[part]
    string_fields = 2 if entry.bigmat else 1
    if np.any((counts != 3) & (counts != string_fields)) or \
            (len(where) and where[0] != entry.start):
        raise FileRefused("a line that is neither a column header nor a string header "
                          "where one is due")
    following = np.concatenate([where[1:], [stop]]) - where - 1
    column_header = counts == 3
    owner = np.maximum.accumulate(np.where(column_header, np.arange(len(where)), 0))
    column = fields[owner, 0]
    dense = column_header & (fields[:, 1] > 0)
    string = ~column_header
    if np.any((column < 1) | (column > entry.columns)) or np.any(string & dense[owner]):
        raise FileRefused("a column header outside the matrix, or strings in a dense column")
    if entry.bigmat:
        length, first, used = fields[:, 0] - 1, fields[:, 1], fields[:, 0] + 1
    else:
        length = (fields[:, 0] >> 16) - 1
        first, used = fields[:, 0] - ((length + 1) << 16), fields[:, 0] >> 16
    numbers = np.where(dense, fields[:, 2], np.where(string, length // per_value, 0))
    first = np.where(dense, fields[:, 1], first)
    sparse_header = column_header & ~dense
    words = np.bincount(owner[string], weights=used[string], minlength=len(where))
    if np.any(string & (length < 0)) or \
            np.any(words[sparse_header] != fields[sparse_header, 2]) or \
            np.any(following != -(-numbers // per_line)):
        raise FileRefused("a column's strings or value lines do not add up to its header")
    run = dense | string
    return (where[run] + 1, following[run], numbers[run], first[run] - 1, column[run] - 1)


def _ascii_values(text: _AsciiText, entry: Op4Entry) -> Op4Runs:
    header = _ascii_header(text, entry.start - 1)
    first_line, line_counts, counts, first_rows, columns = _ascii_runs(text, header,
                                                                       entry.stop)
    value_lines = np.zeros(len(text.starts), dtype=bool)
    value_lines[entry.start:entry.stop] = True
    value_lines[text.integer_lines[text.integer_range(entry.start, entry.stop)]] = False
    lengths = text.ends - text.starts
    some = line_counts > 0
    per_run = np.add.reduceat(lengths[value_lines] // header.width,
                              (np.cumsum(line_counts) - line_counts)[some]) \
        if some.any() else np.zeros(0, dtype=np.int64)
    if np.any(lengths[value_lines] % header.width) or np.any(per_run != counts[some]):
        blob = b"".join(_fitted(text.line(i), header, n)
                        for i, n in zip(*_numbers_per_line(first_line, line_counts, counts,
                                                           header.per_line)))
    else:
        mask = np.repeat(value_lines, lengths + 1)[:len(text.buffer)]
        mask &= text.buffer != 10
        blob = text.buffer[mask].tobytes()
    return Op4Runs(entry.rows, entry.columns, first_rows, counts, columns,
                   _parse_numbers(blob, header.width, int(counts.sum())))


def _numbers_per_line(first_line: np.ndarray, line_counts: np.ndarray, counts: np.ndarray,
                      per_line: int) -> tuple[list[int], list[int]]:
    """Each value line of the runs and how many numbers it holds (the slow path, for
    lines with trailing blanks)."""
    lines, numbers = [], []
    for start, n_lines, count in zip(first_line.tolist(), line_counts.tolist(),
                                     counts.tolist()):
        for k in range(n_lines):
            lines.append(start + k)
            numbers.append(min(per_line, count - k * per_line))
    return lines, numbers


def _fitted(line: bytes, header: _AsciiHeader, numbers: int) -> bytes:
    wanted = numbers * header.width
    if len(line.rstrip()) > wanted:
        raise FileRefused("a line holds more numbers than its header says")
    return line[:wanted].ljust(wanted)


#: numbers from which pyarrow's CSV parser (when installed) is worth its import
_ARROW_NUMBERS = 1_000_000


def _parse_numbers(blob: bytes, width: int, count: int) -> np.ndarray:
    """Fixed-width Fortran numbers (``E`` or ``D`` exponents; ``1.0+100``, the three-digit
    exponent Fortran writes without its letter) as float64, correctly rounded: one
    number per line parsed by pyarrow's CSV reader (C++) when installed and there are
    many, else by numpy, else (three-digit exponents) one by one."""
    if len(blob) != count * width:
        raise FileRefused(f"{_TRUNCATED} (fewer numbers than its headers say)")
    blob = blob.replace(b"D", b"E").replace(b"d", b"E")
    if count >= _ARROW_NUMBERS:
        lines = np.empty((count, width + 1), dtype=np.uint8)
        lines[:, :width] = np.frombuffer(blob, dtype=np.uint8).reshape(count, width)
        lines[:, width] = 10
        parsed = _arrow_numbers(lines.tobytes(), count)
        if parsed is not None:
            return parsed
    fields = np.frombuffer(blob, dtype=f"S{width}")
    try:
        return fields.astype(np.float64)
    except ValueError:
        pass
    values = np.empty(count)
    for i, field in enumerate(fields):
        text = field.decode("ascii", "replace").strip()
        mantissa = text.rstrip("0123456789")
        if mantissa and mantissa[-1] in "+-" and "E" not in text.upper() and \
                len(mantissa) > 1:
            text = f"{mantissa[:-1]}E{text[len(mantissa) - 1:]}"
        try:
            values[i] = float(text)
        except ValueError:
            raise FileRefused(f"a value {text!r} that is not a number") from None
    return values


def _arrow_numbers(lines: bytes, count: int) -> np.ndarray | None:
    """One number per line by pyarrow's CSV reader; None when pyarrow is missing or a line
    is no plain number (numpy then reads them or says what is wrong)."""
    try:
        import pyarrow
        import pyarrow.csv as arrow_csv
    except ImportError:
        return None
    try:
        table = arrow_csv.read_csv(
            pyarrow.BufferReader(pyarrow.py_buffer(lines)),
            read_options=arrow_csv.ReadOptions(column_names=["v"], block_size=4 * 2**20),
            parse_options=arrow_csv.ParseOptions(quote_char=False, escape_char=False,
                                                 newlines_in_values=False),
            convert_options=arrow_csv.ConvertOptions(
                column_types={"v": pyarrow.float64()}, null_values=[],
                strings_can_be_null=False, quoted_strings_can_be_null=False),
            # malloc, not pyarrow's default mimalloc (1 GiB of address space reserved)
            memory_pool=pyarrow.system_memory_pool())
    except (pyarrow.ArrowException, ValueError, TypeError, OverflowError, MemoryError):
        return None
    column = table.column("v")
    if table.num_rows != count or column.null_count:
        return None
    return np.concatenate([np.frombuffer(chunk.buffers()[1], dtype=np.float64,
                                         count=len(chunk), offset=chunk.offset * 8)
                           for chunk in column.chunks])


__all__ = ["Op4Entry", "Op4Runs", "op4_entries", "op4_runs", "op4_values", "BIGMAT_ROWS",
           "forget_parsed_text"]
