"""Every large-model linear path on every corpus structure (benchmarks/corpus.py) at a small
size, against references this test computes independently.

The reference responses are SuperLU solves (partial pivoting) refined with residuals
in double-double arithmetic (benchmarks/corpus.py ``reference``): accurate to about
the rounding of the solution itself even where cond(A) reaches 1e14 (Higham,
*Accuracy and Stability of Numerical Algorithms*, 2nd ed., Sect. 12.1); a dense
LAPACK solve checks them where the conditioning allows.  Tolerances:

* the exact methods (sparse, banded, dense) are backward stable, so their relative
  error is within 10 eps cond_2(A(w)) (+1e-13) of the reference (the forward error
  bound, Higham Sect. 7.1), cond_2 computed densely here; ``modal`` (superposition of
  all modes, checked by the kernel against a direct solve to MODAL_TOLERANCE) gets
  10 MODAL_TOLERANCE more;
* ``reduced`` declares no point singular on these (damped) structures and its
  per-frequency estimate is at least the true error at every frequency (reported side
  by side in the assertion message).
"""

from __future__ import annotations

import functools
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("skfem")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import corpus  # noqa: E402

from resonant.analyses import kernel  # noqa: E402
from resonant.analyses.reduced import reduced_response  # noqa: E402
from resonant.errors import AnalysisError  # noqa: E402
from resonant.system import NumericEOM, NumericHarmonic  # noqa: E402

#: the size of each structure in these tests (a few hundred coordinates at most)
SIZES = {"plate": 150, "solid": 150, "timoshenko_beam": 120}
POINTS = 16
NAMES = sorted(corpus.BUILDERS)
PROPORTIONAL = {"eb_beam", "timoshenko_beam", "plate", "chain", "grid", "beam_spring",
                "clustered", "free_beam"}


@functools.cache
def case(name: str):
    s = corpus.build(name, SIZES.get(name, 120))
    w = np.linspace(*s.band, POINTS)
    ref = corpus.reference(s, w)
    cond = np.array([np.linalg.cond(s.matrix(wi).toarray()) for wi in w])
    return s, w, ref, cond


def batch_of(s, w):
    eom = NumericEOM(tuple(f"q{i + 1}" for i in range(s.n)), s.M, s.C, s.K,
                     (NumericHarmonic(1.0, np.zeros(s.n), s.b.real.copy()),))
    return eom.batch("omega", w)


def relative(Z, ref):
    return np.linalg.norm(Z - ref, axis=1) / np.linalg.norm(ref, axis=1)


@pytest.mark.parametrize("name", NAMES)
def test_reference_agrees_with_dense_lapack(name):
    s, w, ref, cond = case(name)
    eps = np.finfo(float).eps
    dense = np.array([np.linalg.solve(s.matrix(wi).toarray(), s.b) for wi in w])
    assert np.all(relative(dense, ref) <= 10 * eps * cond + 1e-13)


@pytest.mark.parametrize("method", ["sparse", "banded", "dense", "modal"])
@pytest.mark.parametrize("name", NAMES)
def test_exact_methods(name, method):
    s, w, ref, cond = case(name)
    batch = batch_of(s, w)
    if method == "modal" and name not in PROPORTIONAL:
        with pytest.raises(AnalysisError, match="proportional damping"):
            kernel.solve_harmonic(batch, batch.harmonics[0], method)
        return
    result = kernel.solve_harmonic(batch, batch.harmonics[0], method)
    assert not result.singular.any(), f"{name}: a damped structure called singular"
    err = relative(result.Z, ref)
    bound = 10 * np.finfo(float).eps * cond + 1e-13
    if method == "modal":  # superposition of modes: checked against a direct solve to
        bound += 10 * kernel.MODAL_TOLERANCE  # MODAL_TOLERANCE at three points
    assert np.all(err <= bound), f"{name} {method}: errors {err.max():.2g}, bound {bound.min():.2g}"


@pytest.mark.parametrize("name", NAMES)
def test_reduced_estimate_bounds_the_true_error(name):
    s, w, ref, _ = case(name)
    red = reduced_response(s.M, s.C, s.K, s.b, w, tol=1e-6)
    assert not red.singular.any(), f"{name}: a damped structure called undamped"
    true = relative(red.Z, ref)
    table = "\n".join(f"  w = {wi:10.4g}  true {t:9.2e}  estimated {e:9.2e}"
                      for wi, t, e in zip(w, true, red.error))
    assert np.all(red.error >= true), f"{name}: the estimate misses the true error\n{table}"
    assert red.estimated_error >= true.max()
    if red.converged:
        assert true.max() <= 1e-6


@pytest.mark.parametrize("name", NAMES)
def test_reduced_through_the_kernel(name):
    """``reduced`` and ``auto`` through the kernel: no damped point skipped; auto's answer
    within the tolerance (reduced) or exact."""
    s, w, ref, cond = case(name)
    batch = batch_of(s, w)
    red = kernel.solve_harmonic(batch, batch.harmonics[0], "reduced", tol=1e-6)
    assert not red.singular.any()
    auto = kernel.solve_harmonic(batch, batch.harmonics[0], "auto", tol=1e-6)
    assert not auto.singular.any()
    err = relative(auto.Z, ref)
    allowed = 1e-6 if auto.method == "reduced" else 0.0
    assert np.all(err <= allowed + 10 * np.finfo(float).eps * cond + 1e-13)


#: the one-dimensional structures: a narrow band in some numbering of their coordinates
LINEAR = ["eb_beam", "timoshenko_beam", "chain", "beam_spring", "clustered", "free_beam",
          "stiff_chain"]


@pytest.mark.parametrize("name", LINEAR)
def test_band_found_in_any_numbering(name):
    """Coordinates numbered at random (as an assembler may): the band solve finds the
    narrow band again (reverse Cuthill-McKee) and its answers are the reference's,
    put back in the given order."""
    s, w, ref, cond = case(name)
    order = np.random.default_rng(7).permutation(s.n)
    M, C, K = (a.tocsr()[order][:, order] for a in (s.M, s.C, s.K))
    natural = kernel.band_ordering(s.M, s.C, s.K)
    band = kernel.band_ordering(M, C, K)
    assert band.order is not None
    assert band.lower + band.upper <= 2 * (natural.lower + natural.upper) + 2
    eom = NumericEOM(tuple(f"q{i + 1}" for i in range(s.n)), M, C, K,
                     (NumericHarmonic(1.0, np.zeros(s.n), s.b.real[order].copy()),))
    batch = eom.batch("omega", w)
    assert kernel.choose_direct(batch, w) != "dense"
    result = kernel.solve_harmonic(batch, batch.harmonics[0], "banded")
    err = relative(result.Z, ref[:, order])
    assert np.all(err <= 10 * np.finfo(float).eps * cond + 1e-13), err.max()
