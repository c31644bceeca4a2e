"""The closed-form 1 x 1 and 2 x 2 solves of the dense kernel against LAPACK.

Two routes, one answer: ``closed_form_solve`` (Cramer's rule on scaled entries) and
``numpy.linalg.solve`` (LU with partial pivoting).  Both are normwise forward stable
(Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., sec. 1.10.1 for
Cramer's rule with n = 2; sec. 9.3 for LU), so they agree to c cond(A) u with u the unit
roundoff (plus an absolute error at the underflow threshold for subnormal numbers); c = 64
leaves room for the complex arithmetic and the norms' constants.  Both are also held to
the exact solution (80-digit arithmetic), the reference where LAPACK's own overflows.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import resonant
from resonant.analyses.kernel import closed_form_solve, solve_harmonic
from resonant.system.base import sample_parameters

U = np.finfo(float).eps / 2
TINY = np.finfo(float).tiny
TOLERANCE = 64

mantissa = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False)
exponent = st.integers(min_value=-120, max_value=120)


@st.composite
def systems(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """A 2 x 2 complex matrix and load: random, badly scaled (rows and columns by up to
    10^+-120, entries by up to 10^+-8), or nearly singular (a rank-one matrix plus
    10^-k of another)."""
    def complex_matrix(shape: tuple[int, ...]) -> np.ndarray:
        re = np.array(draw(st.lists(mantissa, min_size=int(np.prod(shape)),
                                    max_size=int(np.prod(shape))))).reshape(shape)
        im = np.array(draw(st.lists(mantissa, min_size=int(np.prod(shape)),
                                    max_size=int(np.prod(shape))))).reshape(shape)
        return re + 1j * im

    kind = draw(st.sampled_from(["random", "scaled", "nearly singular"]))
    A = complex_matrix((2, 2))
    if kind == "scaled":
        rows = 10.0 ** np.array([draw(exponent), draw(exponent)])
        cols = 10.0 ** np.array([draw(exponent), draw(exponent)])
        entries = 10.0 ** np.array(draw(st.lists(st.integers(-8, 8), min_size=4,
                                                 max_size=4))).reshape(2, 2)
        A = rows[:, None] * A * entries * cols[None, :]
    elif kind == "nearly singular":
        u, v = complex_matrix((2,)), complex_matrix((2,))
        A = np.outer(u, v) + 10.0 ** -draw(st.integers(0, 17)) * A
    b = complex_matrix((2,)) * 10.0 ** draw(exponent)
    return A, b


def exact_solution(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cramer's rule in 80-digit arithmetic without overflow or underflow (mpmath), rounded
    to doubles: the reference that LAPACK cannot always be (its pivoting overflows on
    entries near 1e200)."""
    with mpmath.workdps(80):
        a = [[mpmath.mpc(complex(v)) for v in row] for row in A]
        f = [mpmath.mpc(complex(v)) for v in b]
        det = a[0][0] * a[1][1] - a[0][1] * a[1][0]
        return np.array([complex((a[1][1] * f[0] - a[0][1] * f[1]) / det),
                         complex((a[0][0] * f[1] - a[1][0] * f[0]) / det)])


def assert_within_bound(x: np.ndarray, y: np.ndarray, cond: float, case: object) -> None:
    """|x - y| <= c cond(A) (u |y| + TINY), relative to |y| so that no bound overflows
    (cond up to 1e307); below the smallest normal number rounding errors are absolute
    (gradual underflow, Higham sec. 2.1): TINY for them."""
    scale = np.abs(y).max()
    if scale > 0:
        assert np.abs(x - y).max() / scale <= cond * (TOLERANCE * (U + TINY / scale)), case
    else:
        assert np.abs(x).max() <= cond * (TOLERANCE * TINY), case


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(systems(), min_size=1, max_size=8), st.booleans())
@example([(np.array([[1j, 1j], [0.25, 0.0]]), np.array([2.22507386e-311j, 0.0]))], False)
@example([(np.array([[1e90j, 1e82j], [5e-129j, 0.0]]), np.array([0.0, 1e90j]))], False)
@example([(np.array([[0.1, 2.78806550e-130], [1.52592589e-196, 0.0]]), np.zeros(2))], True)
@example([(np.array([[0.0, 1.56676907e-201j], [5e-206j, 0.0]]), np.array([0.0, 1e103j]))],
         False)
def test_closed_form_agrees_with_lapack_to_cond_times_u(cases, real):
    """Complex matrices, or their real parts (a system without damping: real arithmetic),
    against the exact solution, and against LAPACK where LAPACK's is finite."""
    A = np.array([a.real if real else a for a, _ in cases])
    b = np.array([v for _, v in cases])
    x, hard = closed_form_solve(A, b)
    for i in np.flatnonzero(~hard):
        assert np.isfinite(x[i]).all()
        cond = np.linalg.cond(A[i])
        assert_within_bound(x[i], exact_solution(A[i], b[i]), cond, (A[i], b[i]))
        with np.errstate(all="ignore"):
            try:
                y = np.linalg.solve(A[i], b[i])
            except np.linalg.LinAlgError:  # a pivot underflowed to an exact zero in LU
                continue
        if np.isfinite(y).all():
            assert_within_bound(x[i], y, cond, (A[i], b[i]))
    for i in range(len(cases)):  # r = |det| / (|a11 a22| + |a12 a21|) >= 1 / (2 cond)
        if np.linalg.cond(A[i]) < 1e5 and np.abs(b[i]).max() > 0 and np.isfinite(
                exact_solution(A[i], b[i])).all():   # (a solution beyond 1.8e308 is hard)
            assert not hard[i], A[i]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(mantissa, mantissa, mantissa, mantissa), min_size=1, max_size=8),
       exponent, exponent)
def test_one_by_one_is_the_quotient(values, ea, eb):
    a = np.array([complex(p, q) for p, q, _, _ in values]) * 10.0 ** ea
    b = np.array([complex(r, s) for _, _, r, s in values]) * 10.0 ** eb
    x, hard = closed_form_solve(a[:, None, None], b[:, None])
    with np.errstate(all="ignore"):
        overflow = ~np.isfinite(b / np.where(a == 0, 1, a))
    assert hard.tolist() == ((a == 0) | overflow).tolist()
    ok = ~hard
    np.testing.assert_allclose(x[ok, 0], b[ok] / a[ok], rtol=4 * U, atol=0)


def test_singular_and_non_finite_points_go_to_lapack():
    A = np.array([[[1, 2], [2, 4]], [[np.inf, 0], [0, 1]], [[np.nan, 0], [0, 1]],
                  [[0, 0], [0, 0]], [[1e-300, 0], [0, 1e-300]], [[1e300, 1e300], [0, 1e300]]],
                 dtype=complex)
    b = np.array([[1, 1], [1, 1], [1, 1], [1, 1], [1e300, 1e300], [1, 1]], dtype=complex)
    x, hard = closed_form_solve(A, b)
    # overflowing solutions (x = 1e600) and singular or non-finite matrices are LAPACK's
    assert hard.tolist() == [True, True, True, True, True, False]
    np.testing.assert_allclose(x[5], [0, 1e-300], rtol=4 * U, atol=0)


#: k of an undamped resonance at the excitation (20 rad/s): det(K - w^2 M) = 0 with
#: M = [[3, 1/2], [1/2, 1/3]], K = diag(k, 9.81)
RESONANT_K = 3 * 400 + (400 / 2) ** 2 / (9.81 - 400 / 3)


@pytest.mark.parametrize("k", [[80.0, 100.0, 120.0], [100.0, RESONANT_K, RESONANT_K * 1.001]])
def test_study_route_agrees_with_the_exact_condition_route(k):
    """The study's solve (closed form, condition bound) against the sweep's (LAPACK,
    equilibrated, exact condition numbers) on the reference exercise; the second case
    includes an undamped resonance at the excitation and a point near one."""
    model = resonant.load("examples/cart_pendulum.toml")
    system = model.linearize()
    values, _, _ = sample_parameters(model, {"k": np.array(k)}, len(k))
    batch = system.evaluate(values, len(k))
    h = batch.harmonics[0]
    fast = solve_harmonic(batch, h, "dense", exact_condition=False)
    exact = solve_harmonic(batch, h, "dense")
    assert fast.singular.tolist() == exact.singular.tolist()
    ok = ~fast.singular
    np.testing.assert_allclose(fast.Z[ok], exact.Z[ok], rtol=1e-12,
                               atol=1e-12 * np.abs(exact.Z[ok]).max())
