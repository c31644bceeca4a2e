"""Complex modes of large non-proportionally damped models by sparse
shift-invert, without dense 2n x 2n matrices (it used to raise above 1,500 DOF).

Reference: the dense eigenvalues of the state matrix [[0, I], [-M^-1 K, -M^-1 C]]
(numpy), on a 500-DOF chain with Rayleigh damping plus one extra damper between DOF 1
and 2 (not proportional).  Tolerance: relative 1e-8 on the 20 eigenvalues nearest 0.
"""

from __future__ import annotations

import numpy as np
import scipy.io
import scipy.sparse as sp

from resonant.api import load
from resonant.modal import lowest_state_eigenvalues


def nonproportional_chain(n: int, k: float = 1e4, m: float = 1.0):
    main = np.full(n, 2 * k)
    main[-1] = k
    K = sp.diags([main, -k * np.ones(n - 1), -k * np.ones(n - 1)], [0, 1, -1], format="lil")
    M = sp.identity(n, format="lil") * m
    C = (0.1 * M + 1e-4 * K).tolil()
    C[0, 0] += 10
    C[1, 1] += 10
    C[0, 1] -= 10
    C[1, 0] -= 10
    return M.tocsc(), C.tocsc(), K.tocsc()


def test_complex_modes_match_the_dense_state_matrix():
    M, C, K = nonproportional_chain(500)
    s = lowest_state_eigenvalues(M, C, K, 10)
    n = 500
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K.toarray(), -C.toarray()]])
    dense = np.linalg.eigvals(A)
    dense = dense[np.argsort(np.abs(dense))][:20]
    for value in dense:
        assert np.min(np.abs(s - value)) <= 1e-8 * abs(value)


def test_modes_of_a_large_non_proportional_matrix_model(tmp_path):
    n = 2000
    M, C, K = nonproportional_chain(n)
    for name, a in (("M", M), ("C", C), ("K", K)):
        scipy.io.mmwrite(str(tmp_path / f"{name}.mtx"), a)
    (tmp_path / "m.toml").write_text('[matrices]\nM = "M.mtx"\nK = "K.mtx"\nC = "C.mtx"\n')
    result = load(tmp_path / "m.toml").linearize().modes(count=5)
    assert not result.proportional_damping and "complex modes" in result.method
    assert result.eigenvalues.size == 10 and result.damping_ratios.size >= 5
    assert result.stability == "asymptotically stable"
