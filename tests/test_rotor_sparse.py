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


def _free_rotor(bearings: bool, along: bool) -> str:
    """Friswell's Example 5.9.1 shaft (12 elements, two discs), on two bearings or on none,
    with free axial and torsional coordinates where ``along``: rigid-body motions s = 0."""
    text = rotor_toml(12).replace("Omega = 0\n", "Omega = 0\n", 1)
    if along:
        text = text.replace("G = 81.2e9\n", "G = 81.2e9\naxial = true\ntorsional = true\n")
    if not bearings:
        text = text[:text.index("[[rotor.bearing]]")]
    return text


@pytest.mark.parametrize("bearings, along", [(False, False), (True, True)])
def test_sparse_campbell_leaves_out_rigid_body_modes_as_the_dense_one(
        monkeypatch: pytest.MonkeyPatch, bearings: bool, along: bool) -> None:
    """A free-free rotor (no bearings) and one free axially and in torsion: the sparse
    eigen-solve (the rotor assembled sparse) leaves its rigid-body eigenvalues out of the
    branches as the dense one does, so both give the same Campbell diagram, critical speeds
    (1e-6 of the largest frequency: the shift-invert solve's backward error is some 1e-10
    beside a cluster of rigid-body pairs at s = 0, the dense one's 1e-16) and rigid-body
    warning."""
    from resonant.analyses.campbell import campbell
    from resonant.system import linear_system

    speeds = np.linspace(0.0, 400.0, 5)
    dense = campbell(linear_system(loads(_free_rotor(bearings, along))), speeds, modes=6)
    monkeypatch.setattr(rotor, "SPARSE_STATIONS", 5)
    model = loads(_free_rotor(bearings, along))
    assert model.matrices is not None and sp.issparse(model.matrices.K)
    sparse = campbell(linear_system(model), speeds, modes=6)
    top = float(np.max(np.abs(dense.eigenvalues)))
    assert np.min(np.abs(dense.eigenvalues)) > 10.0   # no s = 0 among the branches
    assert sparse.eigenvalues.shape == dense.eigenvalues.shape
    assert np.max(np.abs(sparse.eigenvalues - dense.eigenvalues)) <= 1e-6 * top
    assert len(sparse.critical_speeds) == len(dense.critical_speeds) > 0
    for a, b in zip(sparse.critical_speeds, dense.critical_speeds):
        assert (a.mode, a.order, a.whirl) == (b.mode, b.order, b.whirl)
        assert a.speed == pytest.approx(b.speed, abs=1e-6 * top)
    assert any("rigid-body" in w for w in sparse.warnings)
    assert any("rigid-body" in w for w in dense.warnings)
    # undamped, no cross coupling: marginal at every speed, so no threshold, whatever the
    # sparse solve's noise in Re s (the threshold is confirmed by the modes near a branch)
    assert sparse.threshold.verdict == dense.threshold.verdict == "stable in range"
