"""resonant's own OUTPUT4 reader (resonant.model.op4_records) against pyYeti's.

References:

* pyYeti's reader (``pyyeti.nastran.op4.read``) on the files pyYeti writes, in every
  layout (binary little- and big-endian, ASCII; dense, bigmat, non-bigmat): the same
  matrix bit for bit (hypothesis: random sparse matrices, empty columns, all-zero
  matrices);
* Nastran's own files of pyYeti's suite (tests/data/op4, also through pyYeti):
  tests/test_fe_import.py against the MATLAB ground truth;
* a file with 8-byte integers (Nastran's 64-bit OUTPUT4), written here record by
  record as the format says;
* damaged files (truncated anywhere, bytes changed): a FileRefused with a message, never
  another exception (hypothesis).
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from resonant.model.files import FileRefused
from resonant.model.op4_files import numpy_print_options_kept
from resonant.model.op4_records import op4_entries, op4_values

# pyYeti sets numpy's print options for the whole process when imported (legacy 1.13)
with numpy_print_options_kept():
    op4 = pytest.importorskip("pyyeti.nastran.op4")

DATA = Path(__file__).resolve().parent / "data" / "op4"
LAYOUTS = [(binary, endian, sparse) for binary, endian in ((True, "<"), (True, ">"),
                                                           (False, "="))
           for sparse in ("dense", "bigmat", "nonbigmat")]


def _ours(data: bytes) -> dict[str, np.ndarray]:
    matrices = {}
    for entry in op4_entries(data):
        if entry.kind in (1, 2):
            rows, columns, values = op4_values(data, entry)
            dense = np.zeros((entry.rows, entry.columns))
            dense[rows, columns] = values
            matrices[entry.name] = dense
    return matrices


@st.composite
def _matrices(draw: st.DrawFn) -> np.ndarray:
    rows = draw(st.integers(1, 12))
    columns = draw(st.integers(1, 12))
    mask = np.array(draw(st.lists(st.booleans(), min_size=rows * columns,
                                  max_size=rows * columns))).reshape(rows, columns)
    # two-digit exponents: a writer's E23.16 field overflows at |exponent| >= 100
    values = np.array(draw(st.lists(
        st.floats(-1e90, 1e90).filter(lambda x: x == 0 or abs(x) > 1e-90),
        min_size=rows * columns, max_size=rows * columns))).reshape(rows, columns)
    result: np.ndarray = np.where(mask, values, 0.0)
    return result


@settings(max_examples=20, deadline=None)
@given(matrix=_matrices(), layout=st.sampled_from(LAYOUTS))
def test_same_matrix_as_pyyeti_in_every_layout(tmp_path_factory: pytest.TempPathFactory,
                                               matrix: np.ndarray,
                                               layout: tuple[bool, str, str]) -> None:
    import scipy.sparse as sp

    binary, endian, sparse = layout
    path = tmp_path_factory.mktemp("op4") / "m.op4"
    written = matrix if sparse == "dense" else sp.csc_matrix(matrix)
    op4.write(str(path), {"kaa": written, "maa": 2 * written}, binary=binary,
              endian=endian, sparse=sparse)
    theirs = op4.read(str(path), sparse=False)
    ours = _ours(path.read_bytes())
    assert list(ours) == list(theirs)
    for name in theirs:  # binary: the stored bits; ASCII: both parse the same text
        assert np.array_equal(ours[name], theirs[name])


def test_nastran_suite_same_as_pyyeti() -> None:
    """Every real matrix of Nastran's files (all 18 layouts and inboard.op4)."""
    for path in sorted(DATA.glob("*.op4")):
        theirs = op4.read(str(path), sparse=False)
        ours = _ours(path.read_bytes())
        for name, matrix in ours.items():
            assert np.array_equal(matrix, theirs[name]), (path.name, name)


def _record(payload: bytes, endian: str = "<") -> bytes:
    return struct.pack(f"{endian}i", len(payload)) + payload + \
        struct.pack(f"{endian}i", len(payload))


def test_eight_byte_integers_bigmat() -> None:
    """A 64-bit OUTPUT4 file (8-byte integers, record lengths of 4 bytes), written as
    the format says: header (4 integers + a 16-byte name), one bigmat column of two
    strings, the trailer."""
    header = _record(struct.pack("<4q16s", 2, -3, 2, 2, b"KAA".ljust(16)))
    # column 1: string at row 1 (1 value), string at row 3 (1 value); L = values + 1
    strings = struct.pack("<qqd", 2, 1, 4.0) + struct.pack("<qqd", 2, 3, -1.5)
    column = _record(struct.pack("<3q", 1, 0, 6) + strings)
    trailer = _record(struct.pack("<3qd", 3, 1, 1, 1.0))
    data = header + column + trailer
    (entry,) = op4_entries(data)
    assert (entry.name, entry.rows, entry.columns, entry.bigmat) == ("kaa", 3, 2, True)
    rows, columns, values = op4_values(data, entry)
    assert rows.tolist() == [0, 2] and columns.tolist() == [0, 0]
    assert values.tolist() == [4.0, -1.5]


def test_all_zero_matrix_has_no_entries(tmp_path: Path) -> None:
    import scipy.sparse as sp

    op4.write(str(tmp_path / "z.op4"), {"kaa": sp.csc_matrix((4, 4))}, sparse="bigmat")
    (entry,) = op4_entries((tmp_path / "z.op4").read_bytes())
    assert len(op4_values((tmp_path / "z.op4").read_bytes(), entry)[2]) == 0


@pytest.fixture(scope="module")
def small_files(tmp_path_factory: pytest.TempPathFactory) -> list[bytes]:
    import scipy.sparse as sp

    folder = tmp_path_factory.mktemp("damaged")
    matrix = sp.random(9, 9, density=0.4, random_state=3, format="csc")
    files = []
    for binary, endian, sparse in LAYOUTS:
        path = folder / f"{binary}{endian}{sparse}.op4"
        op4.write(str(path), {"kaa": matrix if sparse != "dense" else matrix.toarray()},
                  binary=binary, endian=endian, sparse=sparse)
        files.append(path.read_bytes())
    return files


@settings(max_examples=40, deadline=None)
@given(which=st.integers(0, len(LAYOUTS) - 1), cut=st.floats(0.0, 1.0),
       flips=st.lists(st.tuples(st.floats(0.0, 1.0), st.integers(0, 255)), max_size=3))
def test_damaged_files_are_refused_with_a_message(small_files: list[bytes], which: int,
                                                  cut: float,
                                                  flips: list[tuple[float, int]]) -> None:
    data = bytearray(small_files[which])
    for where, value in flips:
        data[min(int(where * len(data)), len(data) - 1)] = value
    damaged = bytes(data[:max(1, int(cut * len(data)))]) if cut < 1 else bytes(data)
    try:
        for entry in op4_entries(damaged):
            if entry.kind in (1, 2):
                rows, columns, values = op4_values(damaged, entry)
                assert len(rows) == len(columns) == len(values)
                assert np.all((0 <= rows) & (rows < entry.rows))
                assert np.all((0 <= columns) & (columns < entry.columns))
    except FileRefused as refused:
        assert str(refused)


def test_truncated_binary_file_names_what_is_wrong() -> None:
    data = (DATA / "double_bigmat_le.op4").read_bytes()
    with pytest.raises(FileRefused, match="truncated"):
        op4_entries(data[:len(data) // 2])


@pytest.mark.parametrize("columns", [40, 5000])
def test_a_record_broken_inside_a_matrix_names_the_matrix(tmp_path: Path, columns: int) -> None:
    """Cut inside the column records of each matrix of a binary file (two sparse
    matrices, one record per column: 40 columns walked record by record, 5,000 past
    the 4,096 records walked one by one, by vectors; seven cuts in each matrix): the
    message names that matrix.
    (It named the file only: ``resonant import`` on a truncated file did not say which
    matrix was damaged.)"""
    import scipy.sparse as sp

    chain = sp.diags([np.ones(columns - 1), 2.0 * np.ones(columns), np.ones(columns - 1)],
                     [-1, 0, 1], format="csc")
    path = tmp_path / "two.op4"
    with numpy_print_options_kept():
        op4.write(str(path), {"ka": chain, "kb": 3.0 * chain}, binary=True,
                  sparse="bigmat")
    data = path.read_bytes()
    for entry in op4_entries(data):
        for cut in range(entry.start + 1, entry.stop, max(1, (entry.stop - entry.start) // 7)):
            # (a cut between two records: "matrix KA ends before its last column")
            with pytest.raises(FileRefused, match=f"truncated .*matrix {entry.name.upper()}[: ]"):
                op4_entries(data[:4 * cut])   # a whole word inside its records


def test_many_ascii_numbers_parse_as_python_does() -> None:
    """Above _ARROW_NUMBERS numbers the ASCII values go through pyarrow's parser (when
    installed): the same doubles as Python's float() (correctly rounded), D exponents
    included."""
    import resonant.model.op4_records as records
    from resonant.model.op4_records import _parse_numbers

    records._ARROW_NUMBERS, kept = 100_000, records._ARROW_NUMBERS

    values = np.random.default_rng(5).standard_normal(100_000) * \
        10.0 ** np.random.default_rng(6).integers(-60, 60, 100_000)
    text = "".join(f"{v:23.16E}" for v in values).replace("E", "D", 7)
    try:
        parsed = _parse_numbers(text.encode(), 23, len(values))
    finally:
        records._ARROW_NUMBERS = kept
    expected = np.array([float(text[i:i + 23].replace("D", "E"))
                         for i in range(0, len(text), 23)])
    assert np.array_equal(parsed, expected)
