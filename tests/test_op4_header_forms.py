"""ASCII OP4 header forms the corpus run found (benchmarks/bench_op4_corpus.py,
docs/performance-large.md "OP4 corpus"), each in a small hand-made file:

* a matrix header without its number format (``       6       5       2       1R1``, as
  in pyYeti's test file ``nastran_op4_data/rs.op4``, which the corpus run reads bit for
  bit as pyYeti does): the default ``5E16.9`` applies;
* pyYeti's wide header (``...1P,3E23.16|I16``: columns and rows in 16-character fields,
  form and type in 8, then the name), which it writes above 9,999,999 rows, and the I8
  fields of a string header that touch there (``       310000001``);
* Fortran's own form of an exponent beyond 99 (``E16.9`` drops the ``E``:
  `` 1.500000000-300``), read; and a field that overflows its width (as pyYeti's writer
  makes it for such exponents), refused.

Expected values: the numbers written in the files (exact).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from resonant.model.files import FileRefused
from resonant.model.op4_files import op4_directory, read_op4_matrix
from resonant.model.op4_records import op4_entries, op4_runs

BARE = """\
       2       3       2       1R1
       1       1       3
 1.233140833E+00 2.305579698E-01-7.900736796E-02
       2       2       1
 5.555555500E+00
       3       1       1
 1.000000000E+00
"""
#: written by pyYeti 1.4.7 (op4.write, ASCII bigmat) for a 10,000,001 x 2 matrix with
#: 1.5 at row 2 of column 1 and -2.5 at row 10,000,001 of column 2; the second string
#: header's I8 fields touch: L = 3, irow = 10000001
WIDE = """\
               2       -10000001       2       2WIDE    1P,3E23.16|I16
       1       0       4
       3       2
 1.5000000000000000E+00
       2       0       4
       310000001
-2.5000000000000000E+00
       3       1       1
 1.4142135623730951E+00
"""
FORTRAN_EXPONENT = """\
       1       1       2       2KAA     1P,5E16.9
       1       1       1
 1.500000000-300
       2       1       1
 1.000000000E+00
"""
#: as pyYeti's writer makes it: -3.25e-301 takes 17 characters in a field of 16
OVERFLOWING = """\
       1       2       2       2KAA     1P,5E16.9
       1       1       2
1.500000000E-300-3.250000000E-301
       2       1       1
 1.000000000E+00
"""


def _file(folder: Path, text: str) -> str:
    path = folder / "m.op4"
    path.write_text(text, encoding="ascii")
    return str(path)


def test_header_without_a_number_format(tmp_path: Path) -> None:
    path = _file(tmp_path, BARE)
    assert op4_directory(path) == [("r1", (3, 2), 1)]
    matrix = read_op4_matrix(path, "R1", "M", square=False)
    assert matrix.tolist() == [[1.233140833, 0.0], [0.2305579698, 5.5555555],
                               [-0.07900736796, 0.0]]


def test_wide_header_and_touching_fields(tmp_path: Path) -> None:
    data = Path(_file(tmp_path, WIDE)).read_bytes()
    (entry,) = op4_entries(data)
    assert (entry.name, entry.rows, entry.columns, entry.bigmat) == ("wide", 10_000_001, 2,
                                                                     True)
    rows, columns, values = op4_runs(data, entry).coo()
    assert rows.tolist() == [1, 10_000_000] and columns.tolist() == [0, 1]
    assert values.tolist() == [1.5, -2.5]


def test_exponents_beyond_99(tmp_path: Path) -> None:
    assert read_op4_matrix(_file(tmp_path, FORTRAN_EXPONENT), "KAA", "K").tolist() == \
        [[1.5e-300]]
    with pytest.raises(FileRefused, match="more numbers than its header says"):
        read_op4_matrix(_file(tmp_path, OVERFLOWING), "KAA", "K", square=False)
