"""The band a band solve takes (resonant.analyses.kernel.band_ordering): its bandwidths
from dense arrays (first and last nonzero of each row) against those from the sparse
entries, two routes to one pair of numbers; and the reverse Cuthill-McKee order never
wider than the given one."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from resonant.analyses.kernel import band_ordering


@st.composite
def patterns(draw: st.DrawFn, n: int) -> np.ndarray:
    """An n x n matrix: full, banded with holes, a few scattered entries, or zero."""
    rng = np.random.default_rng(draw(st.integers(0, 2**31 - 1)))
    kind = draw(st.sampled_from(["full", "band", "scattered", "zero"]))
    a = np.zeros((n, n))
    if kind == "full":
        a = rng.standard_normal((n, n))
    elif kind == "band":
        lower, upper = rng.integers(0, n, 2)
        i, j = np.indices((n, n))
        inside = (i - j <= lower) & (j - i <= upper) & (rng.random((n, n)) < 0.7)
        a[inside] = 1.0
    elif kind == "scattered":
        a[rng.integers(0, n, 3), rng.integers(0, n, 3)] = 1.0
    return a


@settings(max_examples=150, deadline=None)
@given(st.integers(1, 30).flatmap(lambda n: st.lists(patterns(n), min_size=3, max_size=3)))
def test_dense_and_sparse_bandwidths_agree(matrices):
    dense = band_ordering(*matrices)
    sparse = band_ordering(*(sp.csr_matrix(a) for a in matrices))
    assert (dense.lower, dense.upper) == (sparse.lower, sparse.upper)
    assert (dense.order is None) == (sparse.order is None)
    rows, cols = np.nonzero(sum(np.abs(a) for a in matrices))
    natural = (max(0, int((rows - cols).max(initial=0))),
               max(0, int((cols - rows).max(initial=0))))
    assert dense.lower + dense.upper <= sum(natural)
    if dense.order is None:
        assert (dense.lower, dense.upper) == natural
