"""The forward error of every harmonic solve (analyses/forward_error.py, through the
kernel), and the warning where fewer than three digits are left.

References:

* the exact solution of the 2-DOF models below from the same double-precision matrices,
  by mpmath's LU in 60 digits: the error of the kernel's answer against it is the true
  forward error the estimate must find (tolerance: the estimate within a factor 3 of it
  where it exceeds 1e-8, and never more than 3 times below it);
* two unit masses held by soft springs k = 1 and joined by a stiff one K (damping 0.01
  each): the soft mode's dynamic stiffness 1 - w^2 comes from differences of terms of
  order K, so about log10(K) digits go to rounding (K = 1.234e12: about 1e-4 left; K =
  1.7e15: 1e-1); a stiff spring K = 1e12 in *series* with a soft one has the same
  condition number but loses no digit (its solve is componentwise well conditioned);
* an Euler-Bernoulli cantilever of 2,000 Hermite elements (1 % stiffness-proportional
  damping) near its first resonance, 1.875104^2 sqrt(EI / (rho A L^4)) (Blevins, *Formulas
  for Natural Frequency and Mode Shape*, table 8-1): the banded and the sparse solves
  lose digits alike, and their estimates agree.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
import scipy.sparse as sp

from resonant.analyses.forward_error import ERROR_LIMIT, accuracy_warning
from resonant.analyses.kernel import solve_harmonic
from resonant.analyses.random_response import random_response
from resonant.analyses.stationary import stationary
from resonant.analyses.sweep import sweep
from resonant.model import loads
from resonant.system import NumericEOM, NumericHarmonic, linear_system

FREQUENCIES = np.array([0.3, 0.61, 0.7])


def parallel(stiff: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    K = np.array([[stiff + 1.0, -stiff], [-stiff, stiff + 1.0]])
    return K, np.eye(2), 0.01 * np.eye(2)


def exact(K: np.ndarray, M: np.ndarray, C: np.ndarray, w: float, F: np.ndarray) -> np.ndarray:
    with mpmath.workdps(60):
        n = len(F)
        A = mpmath.matrix(n, n)
        for i in range(n):
            for j in range(n):
                A[i, j] = (mpmath.mpf(K[i, j]) - mpmath.mpf(w) ** 2 * mpmath.mpf(M[i, j])
                           + 1j * mpmath.mpf(w) * mpmath.mpf(C[i, j]))
        x = mpmath.lu_solve(A, mpmath.matrix([mpmath.mpc(complex(f)) for f in F]))
        return np.array([complex(v) for v in x])


def kernel(K: np.ndarray, M: np.ndarray, C: np.ndarray, w: np.ndarray, method: str,
           F: np.ndarray | None = None, **options: bool):  # type: ignore[no-untyped-def]
    """The kernel's solve with F_S = F (default: a unit load at the first coordinate)."""
    n = K.shape[0]
    if F is None:
        F = np.zeros(n)
        F[0] = 1.0
    eom = NumericEOM(tuple(f"q{i}" for i in range(n)), M, C, K,
                     (NumericHarmonic(1.0, F, np.zeros(n)),))
    batch = eom.batch("omega", w)
    return solve_harmonic(batch, batch.harmonics[0], method, **options)


@pytest.mark.parametrize("method,options", [("dense", {}), ("dense", {"exact_condition": False}),
                                            ("banded", {}), ("sparse", {}), ("modal", {})])
@pytest.mark.parametrize("stiff", [1.234e12, 3.21e13, 1.7e15])
def test_the_estimate_finds_the_true_error(stiff: float, method: str, options: dict) -> None:
    K, M, C = parallel(stiff)
    result = kernel(K, M, C, FREQUENCIES, method, **options)
    assert result.forward_error is not None
    for i, w in enumerate(FREQUENCIES):
        reference = exact(K, M, C, float(w), np.array([-1j, 0.0]))
        true = np.abs(result.Z[i] - reference).max() / np.abs(reference).max()
        estimate = result.forward_error[i]
        assert estimate >= true / 3, (w, true, estimate)
        if true > 1e-8:
            assert estimate <= 3 * true, (w, true, estimate)


def test_a_stiff_spring_in_series_loses_nothing() -> None:
    K = np.array([[1.234e12 + 1.0, -1.0], [-1.0, 1.0]])
    result = kernel(K, np.eye(2), 0.01 * np.eye(2), FREQUENCIES, "dense")
    A = K - 0.49 * np.eye(2) + 0.007j * np.eye(2)
    assert np.linalg.cond(A) > 1e11          # the normwise condition number is large
    assert result.forward_error is not None and np.nanmax(result.forward_error) < 1e-14


def chain(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    return K, np.eye(n), 0.05 * np.eye(n) + 0.01 * K


@pytest.mark.parametrize("method", ["dense", "banded", "sparse"])
def test_a_sweep_that_keeps_its_digits_is_estimated_at_every_sixteenth_point(
        method: str) -> None:
    K, M, C = chain(5)
    w = np.linspace(0.1, 2.0, 40)
    result = kernel(K, M, C, w, method)
    assert result.forward_error is not None
    assert np.flatnonzero(np.isfinite(result.forward_error)).tolist() == [0, 16, 32, 39]
    assert np.nanmax(result.forward_error) < 1e-13


@pytest.mark.parametrize("method", ["dense", "banded", "sparse"])
def test_a_loss_the_screen_cannot_see_gets_every_point_estimated(method: str) -> None:
    # the load [1, -1] excites only the stiff mode: ||A|| ||x|| / ||b|| is about 1, yet
    # the rounding of the soft mode's dynamic stiffness costs about four digits; the
    # estimate at the 16th point exceeds the alert level, so every point is estimated,
    # the skipped ones again (each within a factor 3 of the 60-digit reference)
    K, M, C = parallel(1.234e12)
    w = np.linspace(0.3, 0.7, 40)
    load = np.array([1.0, -1.0])
    result = kernel(K, M, C, w, method, F=load)
    assert result.forward_error is not None and np.isfinite(result.forward_error).all()
    assert result.condition.max() < 10 or method == "dense"   # (dense: exact numbers)
    for i in range(0, 40, 3):
        reference = exact(K, M, C, float(w[i]), -1j * load)
        true = np.abs(result.Z[i] - reference).max() / np.abs(reference).max()
        assert true > 1e-6 and true / 3 <= result.forward_error[i] <= 3 * true, (i, true)


def test_not_estimated_when_not_asked() -> None:
    assert kernel(*parallel(10.0), FREQUENCIES, "dense", forward_error=False
                  ).forward_error is None


MODEL = """
[parameters]
omega = 0.61
[matrices]
M = [[1, 0], [0, 1]]
K = [[{a}, {b}], [{b}, {a}]]
C = [[0.01, 0], [0, 0.01]]
[[harmonic]]
omega = "omega"
F_S = [1, 0]
"""


def model(stiff: float, extra: str = ""):  # type: ignore[no-untyped-def]
    K = parallel(stiff)[0]
    text = MODEL.format(a=repr(float(K[0, 0])), b=repr(float(K[0, 1])))
    return linear_system(loads(text + extra))


def said(warnings: tuple[str, ...] | list[str]) -> list[str]:
    return [w for w in warnings if "correct digits" in w]


def test_the_sweep_names_the_points_and_the_cause() -> None:
    (text,) = said(sweep(model(1.7e15), "omega", list(FREQUENCIES)).warnings)
    assert "at 3 of 3 points" in text and "omega = 0.3 to omega = 0.7" in text
    assert "conditioning" in text and "not a resonance" in text and "undamped" not in text


@pytest.mark.parametrize("stiff", [1.234e12, 3.0])
def test_four_digits_left_or_more_say_nothing(stiff: float) -> None:
    result = sweep(model(stiff), "omega", list(FREQUENCIES))
    assert not said(result.warnings)
    assert not any("ill-conditioned" in w for w in result.warnings)


def test_the_stationary_solution_warns_only_where_digits_are_gone() -> None:
    (text,) = [w for w in stationary(model(1.7e15)).warnings if "ill-conditioned" in w]
    assert "fewer than 3 correct digits" in text and "not a resonance" in text
    assert not any("ill-conditioned" in w for w in stationary(model(1.234e12)).warnings)


RANDOM = """
[random]
band = [0.05, 0.15]
lines = 20
[random.psd.F]
unit = "N^2/Hz"
load = [1, 0]
values = 1.0
"""


def test_the_random_response_names_its_frequency_lines() -> None:
    system = model(1.7e15, RANDOM)
    (text,) = said(random_response(system, method="direct").warnings)
    assert "frequency lines" in text and "Hz" in text and "conditioning" in text
    assert not said(random_response(model(3.0, RANDOM), method="direct").warnings)


def cantilever(elements: int) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix, float]:
    h = 1.0 / elements
    ke = np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                   [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h**3
    me = h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                             [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    n = 2 * (elements + 1)
    index = 2 * np.arange(elements)[:, None] + np.arange(4)[None, :]
    rows = np.repeat(index, 4, axis=1).ravel()
    cols = np.tile(index, (1, 4)).ravel()

    def assemble(e: np.ndarray) -> sp.csr_matrix:
        return sp.csr_matrix(sp.coo_matrix((np.tile(e.ravel(), elements), (rows, cols)),
                                           shape=(n, n)).tocsr()[2:, 2:])
    K, M = assemble(ke), assemble(me)
    first = 1.875104**2
    return K, M, sp.csr_matrix((2 * 0.01 / first) * K), first


def test_a_fine_beam_near_its_resonance_loses_its_digits_by_either_route() -> None:
    K, M, C, first = cantilever(2000)
    w = first * np.array([0.5, 1.0])
    banded = kernel(K, M, C, w, "banded")
    sparse = kernel(K, M, C, w, "sparse")
    assert banded.forward_error is not None and sparse.forward_error is not None
    assert banded.forward_error[1] > 10 * ERROR_LIMIT and banded.forward_error[0] > 1e-4
    ratio = banded.forward_error / sparse.forward_error
    assert np.all((ratio > 0.2) & (ratio < 5)), ratio


def test_the_warning_counts_only_points_with_an_answer() -> None:
    errors = np.array([0.5, np.nan, 1e-9])
    assert accuracy_warning(errors, np.arange(3.0), "x = {:.6g}",
                            skipped=np.array([True, False, False])) is None
    assert "no digit left" in str(accuracy_warning(np.array([np.inf]), np.array([1.0]),
                                                   "x = {:.6g}"))
