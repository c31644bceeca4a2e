"""resonant's own Matrix Market reader agrees with scipy's on every layout it accepts.

The reader replaced ``scipy.io.mmread`` (whose C++ reader crashed the process on hostile
files in the fuzz campaigns, docs/fuzzing.md); scipy's writer and reader are the reference here,
exact agreement (the numbers are written with 17 significant digits and read back).
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import resonant.model.matrix_files as matrix_files
from resonant.model.files import FileRefused
from resonant.model.matrix_files import _read_mtx


def _read(text: bytes):
    return _read_mtx(io.BytesIO(text), len(text))


def _written(matrix, **kwargs) -> bytes:
    buffer = io.BytesIO()
    scipy.io.mmwrite(buffer, matrix, precision=17, **kwargs)
    return buffer.getvalue()


def _as_array(matrix) -> np.ndarray:
    return matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix)


@settings(max_examples=40, deadline=None)
@given(n=st.integers(1, 7), seed=st.integers(0, 2**32 - 1),
       symmetry=st.sampled_from(["general", "symmetric", "skew-symmetric"]),
       sparse=st.booleans())
def test_agrees_with_scipy(n, seed, symmetry, sparse):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n)) * (rng.random((n, n)) < 0.6)
    if symmetry == "symmetric":
        a = a + a.T
    elif symmetry == "skew-symmetric":
        a = a - a.T
    data = _written(sp.coo_matrix(a) if sparse else a, symmetry=symmetry)
    ours = _as_array(_read(data))
    theirs = _as_array(scipy.io.mmread(io.BytesIO(data)))
    np.testing.assert_array_equal(ours, theirs)
    np.testing.assert_array_equal(ours, a)


def test_integer_field_and_comments():
    text = (b"%%MatrixMarket matrix coordinate integer symmetric\n% a comment\n\n"
            b"2 2 2\n1 1 4\n% between\n2 1 -1\n")
    np.testing.assert_array_equal(_read(text).toarray(), [[4, -1], [-1, 0]])


@pytest.mark.parametrize("text, words", [
    (b"%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1\n", "holds 1"),
    (b"%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 1\n2 2 2\n", "holds 2"),
    (b"%%MatrixMarket matrix coordinate real general\n2 2 1\n1.5 1 1\n", "integers"),
    (b"%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1\n", "holds 2 numbers"),
    (b"%%MatrixMarket matrix coordinate real hermitian\n2 2 1\n1 1 1\n", "symmetry"),
    (b"%%MatrixMarket matrix coordinate pattern general\n2 2 1\n1 1\n", "pattern entries"),
    (b"%%MatrixMarket matrix coordinate real skew-symmetric\n2 2 1\n1 1 1\n", "diagonal"),
    (b"%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n", "holds 3"),
    (b"%%MatrixMarket matrix array real general\n2 x\n1\n", "size line"),
    (b"%%MatrixMarket matrix array real general\n% only a comment\n", "no size line"),
    (b"%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 \x00\n", "other than numbers"),
    (b"%%MatrixMarket matrix coordinate real general\n2 2 1\n0 1 1\n", "outside the 2x2"),
])
def test_refused(text, words):
    with pytest.raises(FileRefused) as info:
        _read(text)
    assert words in str(info.value)


# -- the fast way (pyarrow's CSV reader) and the safe way (numpy's reader) -------------------

def _bits(matrix) -> list[np.ndarray]:
    """Everything of a matrix, as bits: -0.0 and 0.0 differ, so do two roundings."""
    if sp.issparse(matrix):
        return [matrix.indptr, matrix.indices, matrix.data.view(np.int64)]
    return [np.ascontiguousarray(matrix).view(np.int64)]


def _slow(text: bytes):
    """The reader with the fast way turned off: numpy reads every data line."""
    with mock.patch.object(matrix_files, "_mtx_with_arrow", lambda *args: None):
        return _read(text)


def _fast_used(text: bytes) -> bool:
    """Whether pyarrow's reader took the file (did not hand it to numpy's)."""
    return matrix_files._mtx_with_arrow(text, matrix_files._mtx_size_line(text)[1],
                                        *_size(text)) is not None


def _size(text: bytes) -> tuple:
    banner = text.split(b"\n", 1)[0].split()
    fields, _ = matrix_files._mtx_size_line(text)
    coordinate = banner[2].lower() == b"coordinate"
    n, entries = matrix_files._mtx_entries(fields, coordinate, banner[4].lower().decode(),
                                           len(text))
    return n, entries, coordinate, banner[4].lower().decode()


_SUBNORMAL = 5e-324


def _number(draw, value: float) -> bytes:
    """``value`` written as a writer might: shortest repr, 17 significant digits, or with
    many more digits than a double holds (then not exactly ``value``)."""
    style = draw(st.sampled_from(["repr", "e17", "many", "g"]))
    if style == "repr":
        return repr(value).encode()
    if style == "e17":
        return b"%.16e" % value
    if style == "g":
        return b"%.6g" % value
    digits = draw(st.integers(18, 60))
    return b"%.*e" % (digits, value)


_VALUES = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False),
    st.floats(min_value=-1e-300, max_value=1e-300, allow_nan=False),  # subnormals
    st.sampled_from([0.0, -0.0, _SUBNORMAL, -_SUBNORMAL, 2.2250738585072014e-308,
                     1.7976931348623157e308, -1.7976931348623157e308, 1e-320, 1.0]),
)


@settings(max_examples=150, deadline=None)
@given(data=st.data(), n=st.integers(1, 8),
       symmetry=st.sampled_from(["general", "symmetric", "skew-symmetric"]),
       coordinate=st.booleans(), field=st.sampled_from(["real", "integer"]),
       crlf=st.booleans())
def test_arrow_and_numpy_read_bitwise_the_same(data, n, symmetry, coordinate, field, crlf):
    """Two routes to one answer: the data lines read by pyarrow's CSV reader (the fast
    way) and by numpy's reader (the safe way, used without pyarrow and for every file the
    fast way does not take) give bitwise the same matrix: extreme exponents, subnormals,
    negative zeros, more digits than a double holds, random sparsity, every symmetry,
    coordinate and array files."""
    if coordinate:
        cells = [(i, j) for j in range(1, n + 1) for i in range(1, n + 1)
                 if symmetry == "general" or i > j or (i == j and symmetry == "symmetric")]
        chosen = data.draw(st.lists(st.sampled_from(cells), max_size=3 * len(cells))
                           if cells else st.just([]))
    else:
        chosen = [(i, j) for j in range(1, n + 1) for i in range(1, n + 1)
                  if symmetry == "general" or i > j or (i == j and symmetry == "symmetric")]
    lines = []
    for i, j in chosen:
        value = data.draw(st.integers(-10**6, 10**6)) if field == "integer" \
            else data.draw(_VALUES)
        number = str(value).encode() if field == "integer" else _number(data.draw, value)
        lines.append(b"%d %d %s" % (i, j, number) if coordinate else number)
    end = b"\r\n" if crlf else b"\n"
    size = b"%d %d %d" % (n, n, len(lines)) if coordinate else b"%d %d" % (n, n)
    text = end.join([b"%%MatrixMarket matrix " + (b"coordinate " if coordinate else b"array ")
                     + field.encode() + b" " + symmetry.encode(), size, *lines]) + end
    fast = _read(text)
    slow = _slow(text)
    assert sp.issparse(fast) == sp.issparse(slow)
    for ours, theirs in zip(_bits(fast), _bits(slow), strict=True):
        assert ours.dtype == theirs.dtype
        np.testing.assert_array_equal(ours, theirs)
    if lines:
        assert _fast_used(text)  # the property is about both ways, not numpy twice


_HEAD = b"%%MatrixMarket matrix coordinate real general\n"
_GOOD = [b"1 1 1.5", b"2 1 -2.25", b"3 3 4", b"1 3 0.5"]


def _body(lines: list[bytes], entries: int | None = None, n: int = 3,
          head: bytes = _HEAD) -> bytes:
    count = len(lines) if entries is None else entries
    return head + b"%d %d %d\n" % (n, n, count) + b"\n".join(lines) + b"\n"


@pytest.mark.parametrize("text, words", [
    (_body(_GOOD, 5), "announces 5 entries, the file holds 4"),
    (_body(_GOOD, 3), "announces 3 entries, the file holds 4"),
    (_body([*_GOOD[:2], b"2 2 abc", *_GOOD[2:]]), "other than numbers"),
    (_body([*_GOOD[:2], b"2 2 1.0.0"]), "other than numbers"),
    (_body([*_GOOD[:2], b"0x2 2 1.0"]), "other than numbers"),
    (_body([*_GOOD[:2], b"2 2 nan(7)"]), "other than numbers"),
    (_body([*_GOOD[:2], b"2 2 1 7"]), "other than numbers (expected 3 per line)"),
    (_body([b"1 1", b"2 2"]), "holds 2 numbers"),
    (_body([*_GOOD[:2], b"4 1 1.0"]), "an entry at (4, 1) lies outside the 3x3"),
    (_body([*_GOOD[:2], b"1 0 1.0"]), "an entry at (1, 0) lies outside the 3x3"),
    (_body([*_GOOD[:2], b"-1 1 1.0"]), "an entry at (-1, 1) lies outside the 3x3"),
    (_body([*_GOOD[:2], b"99999999999999999999 1 1.0"]), "lies outside the 3x3"),
    (_body([*_GOOD[:2], b"2 1.5 1.0"]), "must be integers"),
    (_body([*_GOOD[:2], b"2 2 nan"]), "non-finite entries (inf or nan)"),
    (_body([*_GOOD[:2], b"2 2 -inf"]), "non-finite entries (inf or nan)"),
    (_body([*_GOOD[:2], b"2 2 1e400"]), "non-finite entries (inf or nan)"),
    (_body([*_GOOD[:2], b"2 2 " + b"1" * (9 * 2**20)]), "non-finite entries"),
    (_body([*_GOOD[:2], b"2 2 " + b"7" * (9 * 2**20) + b"x"]), "other than numbers"),
    (_body([*_GOOD[:2], b"2 2 \x00"]), "other than numbers"),
    (_body([b"1 1 1", b"2 2 1"], head=_HEAD.replace(b"general", b"skew-symmetric")),
     "stores no diagonal"),
    (_HEAD + b"3 3 1", "holds 1 numbers; expected 3"),  # the size line ends the file
], ids=lambda value: value[-40:].decode("latin-1") if isinstance(value, bytes) else None)
def test_refused_through_the_fast_way(text, words):
    """A malformed body is first offered to pyarrow's reader; the file is refused with
    numpy's specific message, exactly as without pyarrow."""
    assert not _fast_used(text)
    for read in (_read, _slow):
        with pytest.raises(FileRefused) as info:
            read(text)
        assert words in str(info.value)


@pytest.mark.parametrize("lines", [
    [b"1 1 1.5", b"% a comment", b"2 1 2"],  # a comment between data lines
    [b"1  1 1.5", b"2\t1 2"],  # runs of blanks, tabs
    [b" 1 1 1.5", b"2 1 2 "],  # leading and trailing blanks
    [b"+1 1 1.5", b"2 1 2e0"],  # a plus sign, which pyarrow's integers refuse
    [b"1.0 1 1.5", b"2 1e0 2"],  # integral indices written as floats
])
def test_unusual_but_valid_lines_take_numpy_way(lines):
    text = _body(lines, sum(not line.startswith(b"%") for line in lines))
    assert not _fast_used(text)
    np.testing.assert_array_equal(_read(text).toarray(), [[1.5, 0, 0], [2, 0, 0], [0, 0, 0]])


def test_without_pyarrow():
    """pyarrow is optional (the study and test extras): without it numpy reads the lines."""
    text = _body(_GOOD)
    with mock.patch.dict(sys.modules, {"pyarrow": None, "pyarrow.csv": None}):
        assert not _fast_used(text)
        matrix = _read(text)
    assert _fast_used(text)
    for ours, theirs in zip(_bits(matrix), _bits(_read(text)), strict=True):
        np.testing.assert_array_equal(ours, theirs)


_JUNK = st.lists(st.sampled_from([b"1", b"2", b"3", b"0", b"-", b"+", b".", b"e", b"5",
                                  b" ", b" ", b"\t", b"\n", b"\n", b"\r", b"%", b"x", b"n",
                                  b"a", b"i", b"f", b"\x00", b"1.5", b"nan", b"inf", b"0x1", b"E",
                                  b"X", b"\r\n", b"\v", b"\f", b"(", b")", b"00", b"1e5"]),
                 max_size=60).map(b"".join)


@settings(max_examples=300, deadline=None)
@given(body=_JUNK, n=st.integers(1, 3), entries=st.integers(0, 4), coordinate=st.booleans(),
       symmetry=st.sampled_from(["general", "symmetric", "skew-symmetric"]))
def test_any_body_same_outcome_both_ways(body, n, entries, coordinate, symmetry):
    """Whatever the data lines hold, the reader with the fast way gives what numpy's way
    alone gives: the same matrix bit for bit, or the same message."""
    head = b"%%MatrixMarket matrix " + (b"coordinate" if coordinate else b"array") + \
        b" real " + symmetry.encode() + b"\n"
    size = b"%d %d %d\n" % (n, n, entries) if coordinate else b"%d %d\n" % (n, n)
    text = head + size + body
    outcomes = []
    for read in (_read, _slow):
        try:
            outcomes.append(_bits(read(text)))
        except FileRefused as exc:
            outcomes.append(str(exc))
    if isinstance(outcomes[0], str) or isinstance(outcomes[1], str):
        assert outcomes[0] == outcomes[1]
    else:
        for ours, theirs in zip(*outcomes, strict=True):
            np.testing.assert_array_equal(ours, theirs)


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc (Linux)")
def test_the_fast_way_fits_under_an_address_space_limit():
    """pyarrow's default allocator (mimalloc) reserves 1 GiB of address space at its first
    use; the fast way allocates with malloc, so a process that read a file and then runs
    under RLIMIT_AS (the fuzzer's forked children, sandboxes) can still allocate."""
    code = """if True:
        import resource
        import pyarrow.csv
        from resonant.model import matrix_files
        def address_space():
            status = open("/proc/self/status").read()
            return int(status.split("VmSize:")[1].split()[0]) * 1024
        before = address_space()
        text = b"%%MatrixMarket matrix coordinate real general\\n2 2 1\\n1 1 1\\n"
        offset = text.index(b"1 1 1")
        assert matrix_files._mtx_with_arrow(text, offset, 2, 1, True, "general") is not None
        limit = before + 2**30
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        block = bytearray(600 * 2**20)
        print("read and allocated")
    """
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(Path(matrix_files.__file__)
                                                               .parents[2])}, timeout=120)
    assert done.stdout.strip() == "read and allocated", done.stderr[-2000:]


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 60),
       block=st.integers(64, 4096))
def test_many_arrow_blocks_read_as_one(seed, n, block):
    """A file that pyarrow reads in many blocks (many chunks per column) gives bitwise the
    matrix numpy's reader gives: the chunks are joined in order, none lost or repeated."""
    rng = np.random.default_rng(seed)
    text = _written(sp.random(n, n, density=0.3, random_state=rng, format="coo"))
    with mock.patch.object(matrix_files, "_MTX_ARROW_BLOCK", block):
        assert _fast_used(text)
        fast = _read(text)
    slow = _slow(text)
    for ours, theirs in zip(_bits(fast), _bits(slow), strict=True):
        np.testing.assert_array_equal(ours, theirs)


@pytest.mark.parametrize("dtype", [np.float64, np.int32, np.int64])
def test_arrow_numbers_of_a_slice(dtype):
    """A pyarrow array that starts inside its buffer (a slice) is read from its offset."""
    pyarrow = pytest.importorskip("pyarrow")
    whole = pyarrow.array(np.arange(10, dtype=dtype))
    np.testing.assert_array_equal(matrix_files._arrow_numbers(whole.slice(3, 4), dtype),
                                  np.arange(3, 7, dtype=dtype))


def test_reading_a_matrix_file_does_not_import_pandas(tmp_path):
    """pyarrow's to_numpy imports pandas (half a second); a process that only reads a
    matrix model, such as a study's worker, does not pay for it."""
    pytest.importorskip("pyarrow")
    path = tmp_path / "K.mtx"
    scipy.io.mmwrite(path, sp.eye(50, format="coo") * 2.0)
    code = ("import sys\nfrom pathlib import Path\n"
            "from resonant.model import matrix_files\n"
            f"m = matrix_files.read_matrix_file('K.mtx', 'K', Path({str(tmp_path)!r}), ())\n"
            "assert m.shape == (50, 50)\nprint('pandas' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(Path(matrix_files.__file__)
                                                               .parents[2])}, timeout=120)
    assert done.stdout.strip() == "False", done.stderr[-2000:]
