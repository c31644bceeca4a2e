"""The study's per-chunk checks in their cheaper forms against the numpy expressions they
replace, bit for bit (two routes, one answer): the symmetry test against ``np.allclose``,
the largest entry against ``np.abs(a).max``, the 2 x 2 pencil with a constant M against
the same M broadcast to every sample."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from resonant.modal import largest_entry as _largest_entry
from resonant.modal import pencil_roots_2x2 as _pencil_roots_2x2
from resonant.modal import symmetric_stack as _symmetric

VALUES = [0.0, -0.0, 1.0, -1.0, 1 + 1e-13, 1 + 1e-11, 2.5, np.inf, -np.inf, np.nan, 1e-300,
          5e-324, 1e308]


@st.composite
def stacks(draw: st.DrawFn) -> np.ndarray:
    count, n = draw(st.integers(1, 3)), draw(st.integers(1, 3))
    entries = draw(st.lists(st.sampled_from(VALUES), min_size=count * n * n,
                            max_size=count * n * n))
    return np.array(entries).reshape(count, n, n)


@settings(max_examples=500, deadline=None)
@given(stacks())
def test_symmetric_is_allclose_with_the_transpose(a):
    with np.errstate(invalid="ignore"):
        expected = bool(np.allclose(a, a.swapaxes(1, 2), rtol=1e-12, atol=0.0))
    assert _symmetric(a) == expected


@settings(max_examples=300, deadline=None)
@given(stacks())
def test_largest_entry_is_the_max_of_abs(a):
    np.testing.assert_array_equal(_largest_entry(a), np.abs(a).max(axis=(1, 2)))


def test_pencil_of_a_constant_mass_is_that_of_the_broadcast_one():
    rng = np.random.default_rng(3)
    M = np.array([[[3.0, 0.5], [0.5, 1 / 3]]])
    K = np.zeros((50, 2, 2))
    K[:, 0, 0] = 80 + 40 * rng.random(50)
    K[:, 1, 1] = 9.81
    K[:, 0, 1] = K[:, 1, 0] = rng.normal(size=50)
    np.testing.assert_array_equal(_pencil_roots_2x2(M, K),
                                  _pencil_roots_2x2(*np.broadcast_arrays(M, K)))
