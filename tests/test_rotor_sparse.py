"""A large ``[rotor]``: sparse assembly (CSR above resonant.model.rotor.SPARSE_STATIONS),
the memory estimated first, and the complex modes near a branch's eigenvalue that the
root finder of a large rotor follows (docs/rotors.md)."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import scipy.sparse as sp

from conftest import EXAMPLES
from resonant.errors import AnalysisError, ModelError
from resonant.modal import gyroscopic_modes, gyroscopic_modes_near
from resonant.model import loads, rotor

sys.path.insert(0, str(EXAMPLES.parent / "benchmarks"))
from bench_rotor import rotor_toml  # noqa: E402


def test_sparse_assembly_equals_the_dense_one(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same 102-station rotor assembled sparse (the default above 100 stations) and
    dense: every matrix equal to 1e-15 of its largest entry."""
    sparse = loads(rotor_toml(101)).matrices
    monkeypatch.setattr(rotor, "SPARSE_STATIONS", 10_000)
    dense = loads(rotor_toml(101)).matrices
    assert sparse is not None and dense is not None
    for key in ("M", "K", "C", "G"):
        a, b = getattr(sparse, key), getattr(dense, key)
        assert sp.issparse(a) and isinstance(b, np.ndarray)
        assert np.max(np.abs(a.toarray() - b)) <= 1e-15 * max(np.max(np.abs(b)), 1.0)


def test_assembly_memory_is_estimated_first(monkeypatch: pytest.MonkeyPatch) -> None:
    """10^4 coordinates (2499 elements: some 17 MB of triplets) under a 1 MB budget."""
    monkeypatch.setenv("RESONANT_MEMORY", "1M")
    with pytest.raises(AnalysisError, match="the matrices of a \\[rotor\\] of 10000 coord"):
        loads(rotor_toml(2499))


def test_station_limit_is_said() -> None:
    text = rotor_toml(30).replace("count = 30", "count = 25000")
    with pytest.raises(ModelError, match="25001 stations: at most 25000"):
        loads(text, source="long.toml")


def test_modes_near_a_target_are_the_dense_kernels() -> None:
    """Complex shift-invert near a target: the nearest eigenvalues of the dense kernel,
    to 1e-10, and their shapes (MAC 1 - 1e-9), on a gyroscopic, circulatory model."""
    rng = np.random.default_rng(3)
    n = 50
    A = rng.standard_normal((n, n))
    K = A @ A.T + n * np.eye(n)
    K[0, 1] += 3.0   # circulatory (cross-coupled) part
    K[1, 0] -= 3.0
    G = rng.standard_normal((n, n))
    G = 0.2 * (G - G.T)
    M = np.diag(rng.uniform(1, 2, n))
    dense_s, dense_q = gyroscopic_modes(M, G, K)
    target = dense_s[20] * (1 + 2e-3j)
    s, q = gyroscopic_modes_near(sp.csr_matrix(M), sp.csr_matrix(G), sp.csr_matrix(K),
                                 target, 4)
    nearest = int(np.argmin(np.abs(s - dense_s[20])))
    assert abs(s[nearest] - dense_s[20]) < 1e-10 * abs(dense_s[20])
    a, b = q[:, nearest], dense_q[:, 20]
    assert abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real) > 1 - 1e-9
