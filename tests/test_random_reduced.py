"""The random response of a sparse model through one reduced model of the band.

The model: a 30 x 30 grid of masses (900 coordinates; random masses 1-1.3 and springs
1-1.2 to the four neighbours, edges grounded; the stiffness scaled to a lowest natural
frequency of 400 Hz), Rayleigh damping of 2 % at 400 Hz and 2000 Hz, under a base
acceleration of every mass (``base``, the load -M 1 a) whose density has the shape of
the GEVS qualification table (NASA GSFC-STD-7000B, Table 2.4-3), 20-2000 Hz: about 40
natural frequencies in the band.

References, both hand-written with scipy:

* a direct solve (SuperLU, ``scipy.sparse.linalg.splu``) at every 16th frequency of the
  result's grid and at the densities' peaks: the reduced model's densities agree to
  1e-6 of the largest;
* the exact mean square: the modal superposition of all 900 modes (``scipy.linalg.eigh``;
  Rayleigh damping decouples them exactly), |H|^2 G integrated by the trapezoidal rule
  on 40,000 log-spaced frequencies and the table's breakpoints (steps of 1.2e-4 f, 170
  per half-power bandwidth: its own error below 1e-6).  The reported relative error of
  every mean square bounds its true error, and is below 2x the quadrature's tolerance
  1e-4.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from resonant.analyses.random_response import random_response
from resonant.model import loads
from resonant.system import linear_system

NX = 30
LOWEST, ZETA = 400.0, 0.02
GEVS = [(20, 0.026), (50, 0.16), (800, 0.16), (2000, 0.026)]
ROWS = [NX * (NX // 2) + NX // 2, NX * (NX // 3) + NX // 4, NX + NX // 2, NX * NX - NX - 3]


def grid() -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
    n = NX * NX
    idx = np.arange(n).reshape(NX, NX)
    rows = np.concatenate([idx[:, :-1].ravel(), idx[:-1, :].ravel()])
    cols = np.concatenate([idx[:, 1:].ravel(), idx[1:, :].ravel()])
    rng = np.random.default_rng(3)
    springs = sp.coo_matrix((1 + 0.2 * rng.random(len(rows)), (rows, cols)), shape=(n, n))
    springs = springs + springs.T
    edge = np.zeros((NX, NX), dtype=bool)
    edge[0, :] = edge[-1, :] = edge[:, 0] = edge[:, -1] = True
    K = sp.diags(np.asarray(springs.sum(axis=1)).ravel() + edge.ravel()) - springs
    M = sp.diags(1 + 0.3 * rng.random(n))
    lam = scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True, subset_by_index=[0, 0])
    K = K * ((2 * np.pi * LOWEST) ** 2 / lam[0])
    w1, w2 = 2 * np.pi * LOWEST, 2 * np.pi * 2000
    C = 2 * ZETA * w1 * w2 / (w1 + w2) * M + 2 * ZETA / (w1 + w2) * K
    return M.tocsr(), C.tocsr(), K.tocsr()


@pytest.fixture(scope="module")
def case(tmp_path_factory):  # type: ignore[no-untyped-def]
    tmp = tmp_path_factory.mktemp("grid")
    M, C, K = grid()
    for key, a in (("M", M), ("C", C), ("K", K)):
        sp.save_npz(tmp / f"{key}.npz", a)
    text = ('[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
            '[random]\nband = [20, 2000]\ntolerance = 1e-4\n[random.psd.a]\n'
            f'unit = "g^2/Hz"\nbase = [{", ".join(["1"] * NX * NX)}]\n'
            f'values = {[list(p) for p in GEVS]}\n')
    system = linear_system(loads(text, source=str(tmp / "grid.toml"), base_dir=tmp))
    names = [system.coordinates[i] for i in ROWS]
    return system, names, (M, C, K), exact_mean_squares(M, C, K)


def density(f: np.ndarray) -> np.ndarray:
    bf, bv = np.log([p[0] for p in GEVS]), np.log([p[1] for p in GEVS])
    return np.exp(np.interp(np.log(f), bf, bv)) * 9.80665 ** 2


def exact_mean_squares(M: sp.csr_matrix, C: sp.csr_matrix, K: sp.csr_matrix) -> np.ndarray:
    lam, phi = scipy.linalg.eigh(K.toarray(), M.toarray())
    c = np.einsum("ij,ij->j", phi, C @ phi)
    p = phi.T @ -(M @ np.ones(M.shape[0]))
    f = np.unique(np.r_[np.geomspace(20, 2000, 40_000), [g for g, _ in GEVS]])
    parts = []
    for start in range(0, len(f), 5000):
        w = 2 * np.pi * f[start:start + 5000, None]
        parts.append(np.abs((p / (lam - w**2 + 1j * w * c)) @ phi[ROWS].T) ** 2)
    return np.asarray(np.trapezoid(np.concatenate(parts) * density(f)[:, None], f, axis=0))


@pytest.mark.parametrize("method", ["auto", "reduced"])
def test_one_reduced_model_against_direct_solves_and_exact_mean_squares(case, method):  # type: ignore[no-untyped-def]
    system, names, (M, C, K), exact = case
    result = random_response(system, names=names, method=method)
    assert result.method == "reduced"
    f = result.frequency
    S = np.column_stack([result.psd[q] for q in names])
    # the direct solve at every 16th frequency of the grid (and its densities' peaks)
    load = -(M @ np.ones(M.shape[0])).astype(complex)
    some = np.unique(np.r_[np.arange(0, len(f), 16), np.argmax(S, axis=0)])
    Z = np.array([sla.splu((K - w * w * M + 1j * w * C).tocsc()).solve(load)[ROWS]
                  for w in 2 * np.pi * f[some]])
    direct = np.abs(Z) ** 2 * density(f[some])[:, None]
    assert np.abs(S[some] - direct).max() <= 1e-6 * direct.max()
    for r, name in enumerate(names):
        error = result.error[name]
        true = abs(result.rms[name] ** 2 / exact[r] - 1)
        assert true <= error, (name, true, error)
        assert error <= 2e-4, (name, error)
