"""What reading a Universal File will cost, known before pyuff parses it (docs/testing.md).

pyuff reads the whole file into memory, splits each record into lines and parses the
numbers into Python lists before they become arrays: a file of B bytes costs several times
B.  A hostile file (millions of records, a record of nothing but line breaks, a header
announcing more points than the record holds) must be refused from its bytes, before pyuff
is called.  :func:`scan_uff` finds the records as pyuff does (a line ``    -1`` opens and
closes each), through a memory map in bounded chunks, and counts per record its bytes, its
lines and an upper bound of the numbers it holds; :func:`check_uff` refuses a file that
announces more points than its records can hold, or whose estimated peak memory
(:func:`peak_bytes`) is above the budget (``RESONANT_MEMORY``), with a
:class:`~resonant.errors.ModelError` that names the file and the limit.

The estimate, per record of B bytes, L lines and at most V numbers: pyuff's transient
copies (the record, its decoded text and its lines: 3 B + 64 L) and its Python floats
(48 bytes each, list, array and copies), plus 32 bytes per number kept (pyuff's arrays and
ours); the whole file once more (pyuff's first scan holds it).  V is the record's bytes over
the narrowest field pyuff parses (13 characters in ASCII datasets 55 and 58, 4 bytes in a
binary 58b), and the whitespace-separated words of the coordinate datasets 15 and 2411.

Examples
--------
>>> import os, tempfile
>>> text = "    -1\\n   164\\n         1SI\\n    -1\\n"
>>> with tempfile.TemporaryDirectory() as folder:
...     path = os.path.join(folder, "units.uff")
...     _ = open(path, "w").write(text)
...     scan = scan_uff(path)
>>> [(r.dataset, r.lines) for r in scan.records]
[(164, 3)]
>>> peak_bytes(scan) < 2**20
True
"""

from __future__ import annotations

import mmap
import os
import re
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError, Problem
from ..memory import CHUNK_BYTES, budget, size_text

#: the most records (datasets) a Universal File may hold
MAX_RECORDS = 200_000
#: the narrowest field of a number pyuff parses, per (dataset, binary)
FIELD_BYTES = {(58, False): 13, (58, True): 4, (55, False): 13}
#: bytes a number costs while pyuff parses it (a Python float in a list, its array, a copy)
PARSE_BYTES_PER_VALUE = 48
#: bytes a number costs once read (pyuff's array and resonant's)
KEPT_BYTES_PER_VALUE = 32
#: bytes a line costs while split (a Python bytes or str object and its list entry)
BYTES_PER_LINE = 64

_MARKER = b"    -1"
_HEADER_LINES = 13
_WHITESPACE = np.zeros(256, dtype=bool)
_WHITESPACE[[9, 10, 11, 12, 13, 32]] = True


@dataclass(frozen=True)
class UffRecord:
    """One record (dataset) of a Universal File, as its bytes tell it.

    Attributes
    ----------
    start, stop : int
        Its byte offsets (the opening ``    -1`` included, the closing one excluded).
    dataset : int
        Its dataset number (0 when the line after ``    -1`` is not a number).
    binary : bool
        A binary record (``58b``).
    lines : int
        Its line breaks.
    values : int
        An upper bound of the numbers pyuff parses from it.
    declared : int
        The numbers its header announces (dataset 58: points x values a point), else 0.
    """

    start: int
    stop: int
    dataset: int
    binary: bool
    lines: int
    values: int
    declared: int = 0

    @property
    def size(self) -> int:
        """Its bytes."""
        return self.stop - self.start


@dataclass(frozen=True)
class UffScan:
    """The records of a Universal File and its size.

    Attributes
    ----------
    name : str
        The file's name (no folder).
    size : int
        Its bytes.
    records : tuple of UffRecord
    """

    name: str
    size: int
    records: tuple[UffRecord, ...]


def _markers(view: mmap.mmap | bytes, name: str) -> list[int]:
    """The offsets of the ``    -1`` lines, by pyuff's rule (then a line break, the end of
    the file, or blanks up to column 80)."""
    found: list[int] = []
    end = len(view)
    at = view.find(_MARKER)
    while at >= 0:
        after = at + len(_MARKER)
        if after == end or view[after] in (10, 13) or (
                after + 74 <= end and view[after:after + 74] == b" " * 74):
            found.append(at)
            if len(found) > 2 * MAX_RECORDS + 1:
                raise ModelError(Problem(f"more than {MAX_RECORDS} records; at most "
                                         f"{MAX_RECORDS} are read (split the file)", name))
        at = view.find(_MARKER, at + 1)
    return found


def _count(view: np.ndarray, start: int, stop: int, words: bool) -> int:
    """Line breaks (or whitespace-separated words) in ``view[start:stop]``, in chunks."""
    total = 0
    previous_space = True
    for a in range(start, stop, CHUNK_BYTES):
        chunk = view[a:min(stop, a + CHUNK_BYTES)]
        if not words:
            total += int(np.count_nonzero(chunk == 10))
            continue
        space = _WHITESPACE[chunk]
        starts = ~space & np.concatenate(([previous_space], space[:-1]))
        total += int(np.count_nonzero(starts))
        previous_space = bool(space[-1])
    return total


_TYPE_LINE = re.compile(rb"\s*(\d{1,6})([bB]?)")


def _header(view: mmap.mmap | bytes, start: int, stop: int) -> tuple[int, bool, list[bytes]]:
    """The dataset number, binary flag and first header lines of a record."""
    head = bytes(view[start:min(stop, start + 13 * 82 * 2)]).splitlines()[:_HEADER_LINES]
    match = _TYPE_LINE.match(head[1]) if len(head) > 1 else None
    if match is None:
        return 0, False, head
    return int(match.group(1)), bool(match.group(2)), head


def _declared58(head: list[bytes]) -> int:
    """The numbers a dataset 58 header announces (record 7: type, points, spacing)."""
    try:                            # three I10 fields, as pyuff reads them
        line = head[8]
        kind, points, spacing = (int(line[k:k + 10]) for k in (0, 10, 20))
    except (IndexError, ValueError):
        return 0                    # pyuff refuses the header itself, with its reason
    per_point = (2 if kind in (5, 6) else 1) + (1 if spacing == 0 else 0)
    return max(points, 0) * per_point


def scan_uff(path: str | os.PathLike[str]) -> UffScan:
    """The records of a Universal File, found from its bytes without parsing them.

    Parameters
    ----------
    path : str or PathLike
        A regular file (the caller has bounded its size).

    Returns
    -------
    UffScan

    Raises
    ------
    ModelError
        For more than :data:`MAX_RECORDS` records.
    """
    name = os.path.basename(os.fspath(path))
    with open(path, "rb") as handle:
        size = os.fstat(handle.fileno()).st_size
        if size == 0:
            return UffScan(name, 0, ())
        with mmap.mmap(handle.fileno(), 0, access=mmap.ACCESS_READ) as view:
            records = _records(view, name)
    return UffScan(name, size, tuple(records))


def _records(view: mmap.mmap, name: str) -> list[UffRecord]:
    markers = _markers(view, name)
    array = np.frombuffer(view, dtype=np.uint8)
    try:
        records = []
        for start, stop in zip(markers[:-1:2], markers[1::2], strict=True):
            dataset, binary, head = _header(view, start, stop)
            lines = _count(array, start, stop, words=False)
            if dataset in (15, 2411):
                values = _count(array, start, stop, words=True)
            else:
                values = (stop - start) // FIELD_BYTES.get((dataset, binary), 2)
            declared = _declared58(head) if dataset == 58 else 0
            records.append(UffRecord(start, stop, dataset, binary, lines, values, declared))
    finally:
        del array                   # the map closes only once no array views it
    return records


def peak_bytes(scan: UffScan) -> float:
    """The estimated peak memory of reading the file through pyuff (the module's model).

    Parameters
    ----------
    scan : UffScan

    Returns
    -------
    float
        Bytes.
    """
    if not scan.records:
        return float(scan.size)
    transient = max(3.0 * r.size + BYTES_PER_LINE * r.lines + PARSE_BYTES_PER_VALUE * r.values
                    for r in scan.records)
    kept = KEPT_BYTES_PER_VALUE * sum(r.values for r in scan.records)
    return float(scan.size) + transient + kept


def check_uff(path: str | os.PathLike[str]) -> UffScan:
    """Refuse a Universal File before pyuff parses it: a dataset 58 announcing more points
    than its record holds, or an estimated peak memory above the budget.

    Parameters
    ----------
    path : str or PathLike

    Returns
    -------
    UffScan
        The records found.

    Raises
    ------
    ModelError
        Naming the file, the record and the size, or the estimate and the budget.
    """
    scan = scan_uff(path)
    for number, record in enumerate(scan.records, start=1):
        width = FIELD_BYTES.get((record.dataset, record.binary), 0)
        if record.declared and record.declared * width > record.size:
            raise ModelError(Problem(
                f"record {number} (dataset 58) announces {record.declared} numbers "
                f"({size_text(record.declared * width)} at least) but holds "
                f"{size_text(record.size)}: truncated, or a wrong header", scan.name))
    peak = peak_bytes(scan)
    limit = budget()
    if peak > limit:
        raise ModelError(Problem(
            f"reading it ({size_text(scan.size)}, {len(scan.records)} records) would take "
            f"about {size_text(peak)} of memory, above the budget of {size_text(limit)} "
            "(RESONANT_MEMORY): split the file, or raise the budget", scan.name))
    return scan


__all__ = ["UffRecord", "UffScan", "scan_uff", "peak_bytes", "check_uff", "MAX_RECORDS"]
