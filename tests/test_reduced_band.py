"""Reduced models of a narrow-band model (docs/sweeps.md, "How the reduced model is
built"; docs/performance-large.md, "Reduced sweeps of large FE models").

* A narrow band (the five-diagonal chain of benchmarks/bench_op4.py, as numbered and
  numbered at random) is factorized by LAPACK's band LU
  (``resonant.analyses.bands.BandLU``), a 2-D grid by SuperLU; both
  solve A(s) x = b to the same digits (1e-12 relative against SciPy's ``spsolve``).
* An expansion point on a sharp resonance: the chain of 2,000 rows, C = 1e-3 K (damping
  ratios about 1e-5), 101 frequencies centred on its third natural frequency (the
  middle initial expansion point falls on that peak).  The reduced sweep returns the
  exact solve it made there, so it converges with its three first points (the reduced
  response at the peak was 6e-8 off the exact one, 1e-6 estimated: not converged after
  seven points, "the residual stopped decreasing"); every frequency agrees with
  ``spsolve`` to 1e-6 relative (the tolerance).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from resonant.analyses.bands import BandLU
from resonant.analyses.reduced import ScaledLU, _Operators, reduced_response


def chain(n: int) -> sp.csr_matrix:
    main, first, second = np.full(n, 3.0), np.full(n - 1, -1.0), np.full(n - 2, -0.5)
    return sp.diags([second, first, main, first, second], [-2, -1, 0, 1, 2], format="csr")


def grid(side: int) -> sp.csr_matrix:
    line = sp.diags([-np.ones(side - 1), 2 * np.ones(side), -np.ones(side - 1)], [-1, 0, 1])
    eye = sp.identity(side)
    return (sp.kron(line, eye) + sp.kron(eye, line)).tocsr()


def test_a_narrow_band_is_factorized_by_the_band_lu_a_wide_one_by_superlu():
    rng = np.random.default_rng(3)
    order = rng.permutation(3000)   # numbered at random: the band is found again (RCM)
    scrambled = chain(3000)[order][:, order]
    for K, kind in ((chain(3000), BandLU), (scrambled, BandLU), (grid(60), ScaledLU)):
        n = K.shape[0]
        M, C = sp.identity(n, format="csr"), 1e-3 * K + 0.01 * sp.identity(n)
        ops = _Operators(M, C, K)
        s = 0.7
        lu = ops.factor(s)
        assert isinstance(lu, kind)
        b = rng.standard_normal(n) + 1j * rng.standard_normal(n)
        exact = sla.spsolve((K - s * s * M + 1j * s * C).tocsc(), b)
        x = lu.solve(b)
        assert np.linalg.norm(x - exact) <= 1e-12 * np.linalg.norm(exact)
        X = lu.solve(np.column_stack([b, 2 * b]))   # several right-hand sides at once
        assert np.allclose(X[:, 1], 2 * x, rtol=1e-13, atol=0)


def test_an_expansion_point_on_a_sharp_peak_returns_its_exact_solve():
    n = 2000
    K = chain(n)
    M, C = sp.identity(n, format="csr"), 1e-3 * K
    natural = np.sqrt(np.sort(sla.eigsh(K.tocsc(), k=5, sigma=0, which="LM")[0]))
    half = 1.5 * (natural[2] - natural[0])
    w = np.linspace(natural[2] - half, natural[2] + half, 101)
    assert abs(w[50] / natural[2] - 1) < 1e-14
    b = np.zeros(n, dtype=complex)
    b[0] = 1.0
    red = reduced_response(M, C, K, b, w, tol=1e-6)
    assert red.converged and red.estimated_error <= 1e-6
    assert w[50] in red.expansion and len(red.expansion) == 3
    exact = np.array([sla.spsolve((K - s * s * M + 1j * s * C).tocsc(), b) for s in w])
    error = np.linalg.norm(red.Z - exact, axis=1) / np.linalg.norm(exact, axis=1)
    assert error.max() <= 1e-6
