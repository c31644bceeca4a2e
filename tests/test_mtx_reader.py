"""resonant's own Matrix Market reader agrees with scipy's on every layout it accepts.

The reader replaced ``scipy.io.mmread`` (whose C++ reader crashed the process on hostile
files in the fuzz campaigns, docs/fuzzing.md); scipy's writer and reader are the reference here,
exact agreement (the numbers are written with 17 significant digits and read back).
"""

from __future__ import annotations

import io

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

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


@settings(max_examples=30, deadline=None)
@given(n=st.integers(1, 9), seed=st.integers(0, 2**32 - 1), sparse=st.booleans(),
       spacing=st.sampled_from([b" ", b"  ", b"\t"]))
def test_pandas_and_numpy_read_the_same_numbers(n, seed, sparse, spacing):
    """Two routes to one answer: the data lines read by pandas' C reader and by numpy's
    reader give bitwise the same matrix (other blanks than one space take numpy's way)."""
    from unittest import mock

    import resonant.model.matrix_files as matrix_files

    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n)) * 10.0 ** rng.integers(-30, 30, (n, n))
    a *= rng.random((n, n)) < 0.6
    data = _written(sp.coo_matrix(a) if sparse else a)
    head, body = data.split(b"\n", 2)[:2], data.split(b"\n", 2)[2]
    data = b"\n".join([*head, body.replace(b" ", spacing)])
    fast = _as_array(_read(data))
    with mock.patch.object(matrix_files, "_mtx_numbers_with_pandas", lambda *args: None):
        plain = _as_array(_read(data))
    np.testing.assert_array_equal(fast, plain)
    np.testing.assert_array_equal(fast, a)
