"""Reduced-order frequency response: ``method="reduced"`` and ``auto`` (docs/performance.md).

Every reduced response is checked against an exact direct solve (numpy dense or SuperLU)
of the same complex system (K - w^2 M + i w C) z = F_C - i F_S, per frequency and
normwise: err(w) = ||z_red - z|| / ||z||.

* random sparse mass-spring systems (hypothesis, n = 8 ... 60; Rayleigh or discrete,
  non-proportional dampers): the largest true error is at most the tolerance and at
  most the reported estimate (the estimate is a safety factor times the validated
  ratio of error to residual: observed 3-1000x above the true error);
* a 30 x 30 mass-spring grid (900 DOF, band 30) with Rayleigh damping and with
  non-proportional dampers, through ``sweep`` on a ``[matrices]`` model file;
* ``auto`` keeps the reduced model only when its estimate meets ``tol``, otherwise
  it solves directly; the cost-based direct choice picks sparse LU for the grid
  and the band for a chain;
* method, estimated error and tolerance are reported (fields, ``to_dict``, summary,
  CLI ``--method reduced --tol``).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import run_cli
from resonant.analyses import kernel
from resonant.analyses.reduced import reduced_model, reduced_response
from resonant.analyses.sweep import sweep, sweep_text
from resonant.api import load
from resonant.errors import AnalysisError


def grid(nx: int, ny: int | None = None, k: float = 1e4, alpha: float = 0.1,
         beta: float = 1e-3, dampers: int = 0, seed: int = 0):
    """(M, C, K, f) of an nx x ny mass-spring grid, edges grounded, irregular springs and
    masses, Rayleigh damping alpha M + beta K plus ``dampers`` random discrete dampers
    between neighbours (non-proportional), a unit force at one interior node."""
    ny = ny or nx
    n = nx * ny
    idx = np.arange(n).reshape(ny, nx)
    rows = np.concatenate([idx[:, :-1].ravel(), idx[:-1, :].ravel()])
    cols = np.concatenate([idx[:, 1:].ravel(), idx[1:, :].ravel()])
    rng = np.random.default_rng(seed)
    springs = sp.coo_matrix((k * (1 + 0.2 * rng.random(len(rows))), (rows, cols)),
                            shape=(n, n))
    springs = springs + springs.T
    edge = np.zeros((ny, nx), dtype=bool)
    edge[0, :] = edge[-1, :] = edge[:, 0] = edge[:, -1] = True
    K = (sp.diags(np.asarray(springs.sum(axis=1)).ravel() + k * edge.ravel())
         - springs).tocsr()
    M = sp.diags(1 + 0.3 * rng.random(n)).tocsr()
    C = alpha * M + beta * K
    if dampers:
        pick = rng.choice(len(rows), dampers, replace=False)
        c = 5.0 * (1 + rng.random(dampers))
        i, j = rows[pick], cols[pick]
        D = sp.coo_matrix((np.concatenate([c, c, -c, -c]),
                           (np.concatenate([i, j, i, j]), np.concatenate([i, j, j, i]))),
                          shape=(n, n))
        C = C + D
    f = np.zeros(n)
    f[idx[ny // 3, nx // 4]] = 1.0
    return M.tocsr(), sp.csr_matrix(C), K, f


def lowest_frequencies(M, K, count):
    return np.sqrt(np.sort(sla.eigsh(K, k=count, M=M, sigma=0, return_eigenvectors=False)))


def exact(M, C, K, b, w):
    return np.array([sla.splu((K - x * x * M + 1j * x * C).tocsc()).solve(b) for x in w])


def relative_errors(Z, ref):
    return np.linalg.norm(Z - ref, axis=1) / np.linalg.norm(ref, axis=1)


def write_model(directory, M, C, K, f):
    for key, a in (("M", M), ("C", C), ("K", K)):
        scipy.io.mmwrite(str(directory / f"{key}.mtx"), sp.csr_matrix(a))
    force = ", ".join(repr(float(v)) for v in f)
    path = directory / "model.toml"
    path.write_text('title = "grid"\n[parameters]\nw = 1\n[matrices]\nM = "M.mtx"\n'
                    'C = "C.mtx"\nK = "K.mtx"\n[[harmonic]]\nomega = "w"\n'
                    f"F_C = [{force}]\n", encoding="utf-8")
    return path


def response_matrix(result):
    """z = L - i N of every coordinate, rebuilt from amplitude and phase, (N, n)."""
    X = np.stack([np.asarray(result.amplitudes[q]) for q in result.coordinates], axis=1)
    d = np.nan_to_num(np.stack([np.asarray(result.phases[q]) for q in result.coordinates],
                               axis=1))
    return X * np.sin(d) - 1j * X * np.cos(d)


# -- random sparse mass-spring systems --------------------------------------------------------

@st.composite
def mass_spring(draw):
    n = draw(st.integers(8, 60))
    seed = draw(st.integers(0, 2**31 - 1))
    proportional = draw(st.booleans())
    rng = np.random.default_rng(seed)
    extra = rng.integers(0, n, size=(n, 2))            # random extra springs
    pairs = np.vstack([np.c_[np.arange(n - 1), np.arange(1, n)], extra])
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    k = 10.0 ** rng.uniform(2, 4, len(pairs))
    i, j = pairs[:, 0], pairs[:, 1]
    K = sp.coo_matrix((np.concatenate([k, k, -k, -k]),
                       (np.concatenate([i, j, i, j]), np.concatenate([i, j, j, i]))),
                      shape=(n, n)).tocsr()
    K = K + sp.diags(np.where(rng.random(n) < 0.2, 1e3, 0.0) + np.r_[1e3, np.zeros(n - 1)])
    M = sp.diags(10.0 ** rng.uniform(-0.5, 0.5, n)).tocsr()
    if proportional:
        C = 0.05 * M + 1e-4 * K
    else:
        d = rng.choice(n, size=3)
        C = sp.diags(np.bincount(d, minlength=n) * 2.0) + 1e-5 * K
    b = np.zeros(n, dtype=complex)
    b[rng.integers(n)] = 1.0
    b[rng.integers(n)] -= 0.5j
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(M.toarray(), K.toarray())).real)
    top = np.sqrt(lam[min(n - 1, draw(st.integers(1, 6)))])
    w = np.linspace(0.2 * np.sqrt(lam[0]), 1.1 * top, 120)
    return M, sp.csr_matrix(C), K.tocsr(), b, w


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mass_spring(), st.sampled_from([1e-6, 1e-9]))
def test_reduced_matches_direct_on_random_systems(system, tol):
    M, C, K, b, w = system
    red = reduced_response(M, C, K, b, w, tol=tol)
    A = (K.toarray()[None] - w[:, None, None] ** 2 * M.toarray()[None]
         + 1j * w[:, None, None] * C.toarray()[None])
    ref = np.linalg.solve(A, b[None, :, None])[..., 0]
    err = relative_errors(red.Z, ref)
    if not red.converged:
        # an honest stop at the rounding floor, only for the tight tolerance (some drawn
        # systems are too ill-conditioned for 1e-9): its answer is as good as it says
        assert "rounding floor" in red.reason and tol < 1e-6, (red.reason, tol)
        assert err.max() <= max(10 * red.estimated_error, 1e-8)
        return
    assert err.max() <= tol
    # the reference is a double precision solve too: its own error is up to about
    # eps * cond(A) (1e-11 near a lightly damped resonance), below which both are rounding
    rounding = 10 * np.finfo(float).eps * np.linalg.cond(A)
    assert np.all(err <= np.maximum(red.estimated_error, np.maximum(rounding, 1e-11)))
    assert np.all(red.error >= 0) and red.estimated_error == np.nanmax(red.error)
    assert not red.Z.flags.writeable


# -- the 30 x 30 grid -------------------------------------------------------------------------

@pytest.fixture(scope="module")
def grid_cases():
    out = {}
    for name, dampers in (("rayleigh", 0), ("nonprop", 12)):
        M, C, K, f = grid(30, dampers=dampers)
        om = lowest_frequencies(M, K, 25)
        w = np.linspace(0.5 * om[0], om[19], 300)
        out[name] = (M, C, K, f, w)
    return out


@pytest.mark.parametrize("name", ["rayleigh", "nonprop"])
def test_grid_reduced_within_tolerance(grid_cases, name):
    """20 resonances in the band, 300 frequencies: error <= 1e-6 at 15 sampled ones,
    below the estimate; the estimate is honest to within a factor 1e4."""
    M, C, K, f, w = grid_cases[name]
    red = reduced_response(M, C, K, f.astype(complex), w, tol=1e-6)
    assert red.converged and red.estimated_error <= 1e-6
    assert red.basis_size < 200 and len(red.expansion) <= 12
    sample = np.linspace(0, len(w) - 1, 15).astype(int)
    err = relative_errors(red.Z[sample], exact(M, C, K, f.astype(complex), w[sample]))
    assert err.max() <= 1e-6
    assert err.max() <= red.estimated_error <= 1e4 * max(err.max(), 1e-15)
    # the validation solves are true errors of the basis of their moment
    assert all(e >= 0 for _, e in red.checks)


def test_grid_sweep_methods_agree(grid_cases, tmp_path):
    """Through sweep() on a [matrices] model: reduced and sparse LU agree to the tolerance;
    the result says which method and how accurate."""
    M, C, K, f, w = grid_cases["nonprop"]
    model = load(write_model(tmp_path, M, C, K, f)).linearize()
    names = list(model.coordinates)
    red = sweep(model, "w", w[::2], method="reduced", tol=1e-7, names=names)
    direct = sweep(model, "w", w[::20], method="direct", names=names)
    assert red.method == "reduced" and direct.method in ("banded", "sparse")
    assert red.estimated_error is not None and red.estimated_error <= 1e-7
    assert red.tolerance == 1e-7 and direct.estimated_error is None
    za, zb = response_matrix(red)[::10], response_matrix(direct)
    assert relative_errors(za, zb).max() <= 1e-7
    data = red.to_dict()
    assert data["method"] == "reduced" and data["estimated_error"] == red.estimated_error
    assert data["tolerance"] == 1e-7
    assert "method reduced (estimated error" in sweep_text(red)
    assert direct.to_dict()["estimated_error"] is None


def test_auto_picks_reduced_when_it_pays(grid_cases, tmp_path, monkeypatch):
    M, C, K, f, w = grid_cases["rayleigh"]
    model = load(write_model(tmp_path, M, C, K, f)).linearize()
    monkeypatch.setattr(kernel, "REDUCED_WORTH", 0.0)  # the 900-DOF sweep is short anyway
    monkeypatch.setattr(kernel, "REDUCED_MIN_BUDGET", 60.0)  # a loaded test machine
    auto = sweep(model, "w", w)
    assert auto.method == "reduced" and auto.estimated_error <= 1e-6
    assert not auto.warnings


def test_auto_solves_directly_when_the_tolerance_cannot_be_met(grid_cases, tmp_path,
                                                               monkeypatch):
    """A band over every resonance of the grid with a cap of 4 expansion points: the
    reduced model cannot meet 1e-6, auto falls back to an exact direct solve."""
    M, C, K, f, _ = grid_cases["rayleigh"]
    model = load(write_model(tmp_path, M, C, K, f)).linearize()
    top = np.sqrt(sla.eigsh(K, k=1, M=M, which="LM", return_eigenvectors=False)[0])
    w = np.linspace(1.0, 1.5 * top, 60)
    monkeypatch.setattr(kernel, "REDUCED_WORTH", 0.0)
    monkeypatch.setattr(kernel, "REDUCED_MIN_BUDGET", 0.0)  # the fewest points (4)
    monkeypatch.setattr(kernel, "REDUCED_BUDGET", 0.0)
    auto = sweep(model, "w", w, names=["q1", "q300"])
    assert auto.method in ("banded", "sparse") and auto.estimated_error is None
    # asked for explicitly, the reduced model says how far off it is
    monkeypatch.setattr("resonant.analyses.reduced.MAX_POINTS", 4)
    red = sweep(model, "w", w, method="reduced", names=["q1", "q300"])
    assert red.method == "reduced" and red.estimated_error > 1e-6
    assert any("exceeds the tolerance" in m for m in red.warnings)


def test_direct_choice_from_costs():
    """A 2-D grid (100 x 100, band 100): sparse LU, whose fill with the minimum degree
    ordering (~0.37 M) is far below the band's n x 2 x 100 storage; a chain: the band,
    without a probe factorization."""
    from resonant.system import NumericEOM, NumericHarmonic

    def batch_of(M, C, K):
        n = M.shape[0]
        load = NumericHarmonic(1.0, np.zeros(n), np.r_[np.zeros(n - 1), 1.0])
        eom = NumericEOM(tuple(f"q{i}" for i in range(n)), M, C, K, (load,))
        return eom.batch("omega", np.array([1.0, 2.0]))

    M, C, K, _ = grid(100)
    batch = batch_of(M, C, K)
    costs = kernel.direct_costs(batch)
    assert costs["sparse"] < costs["banded"] and costs["sparse_fill"] < 100 * 10_000
    assert kernel.choose_direct(batch) == "sparse"
    n = 3000
    chain = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1],
                     format="csr")
    batch = batch_of(sp.identity(n, format="csr"), 1e-3 * chain, 1e4 * chain)
    assert "sparse" not in kernel.direct_costs(batch)
    assert kernel.choose_direct(batch) == "banded"


def test_cli_method_and_tol(grid_cases, tmp_path):
    M, C, K, f, w = grid_cases["rayleigh"]
    path = write_model(tmp_path, M, C, K, f)
    code, out, err = run_cli(["sweep", path, "--param", "w", "--from", str(w[0]), "--to",
                              str(w[-1]), "--points", "200", "--method", "reduced",
                              "--tol", "1e-8", "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["method"] == "reduced" and data["estimated_error"] <= 1e-8
    assert data["tolerance"] == 1e-8
    code, out, err = run_cli(["sweep", path, "--param", "w", "--from", str(w[0]), "--to",
                              str(w[-1]), "--points", "20", "--method", "direct"])
    assert code == 0, err
    assert "method banded" in out or "method sparse" in out
    code, out, err = run_cli(["sweep", path, "--param", "w", "--from", "1", "--to", "2",
                              "--tol", "-1"])
    # an invalid option value is invalid input (exit 2), named by its option
    assert code == 2 and "--tol" in err


def test_reduced_refuses_a_changing_system():
    from resonant.system import NumericEOM, NumericHarmonic

    eom = NumericEOM(("x",), np.eye(1), np.zeros((1, 1)), 4 * np.eye(1),
                     (NumericHarmonic(1.0, np.array([3.0]), np.array([0.0])),))
    with pytest.raises(AnalysisError):
        reduced_response(np.eye(1), np.zeros((1, 1)), np.eye(1), np.ones(1), [1.0], tol=0.0)
    result = sweep(eom, "omega", np.linspace(0.5, 3, 5), method="reduced")
    np.testing.assert_allclose(result.amplitudes["x"], 3 / np.abs(4 - np.linspace(0.5, 3, 5)
                                                                    ** 2), rtol=1e-9)


def test_stacked_solves_when_the_reduced_poles_are_ill_conditioned(grid_cases, monkeypatch):
    """Without the diagonalization (defective or ill-conditioned reduced eigenvectors) the
    reduced system is solved point by point (stacked), with the same accuracy."""
    from resonant.analyses import reduced

    M, C, K, f, w = grid_cases["nonprop"]
    monkeypatch.setattr(reduced._Reduced, "_diagonalize", lambda self: None)
    red = reduced_response(M, C, K, f.astype(complex), w[::3], tol=1e-6)
    sample = np.arange(0, len(w[::3]), 10)
    err = relative_errors(red.Z[sample], exact(M, C, K, f.astype(complex), w[::3][sample]))
    assert red.converged and err.max() <= 1e-6


def test_undamped_system():
    """C = 0: real poles of the reduced model on the frequency axis; still within tol.
    A frequency exactly at a natural frequency is singular (NaN), not an error."""
    M, _, K, f = grid(12)
    C = sp.csr_matrix(K.shape)
    om = lowest_frequencies(M, K, 8)
    w = np.linspace(0.3 * om[0], 0.5 * (om[4] + om[5]), 97)
    red = reduced_response(M, C, K, f.astype(complex), w, tol=1e-8)
    err = relative_errors(red.Z, exact(M, C, K, f.astype(complex), w))
    assert red.converged and err.max() <= 1e-8
    red = reduced_response(M, C, K, f.astype(complex), np.r_[w, om[2]], tol=1e-8)
    assert red.singular[-1] and not red.singular[:-1].any() and red.converged


def test_benchmark_runs_at_a_tiny_size():
    """benchmarks/bench_reduced.py at 12 x 12 (a smoke test, not timed): every side runs,
    resonant's exact and reduced sides agree with the reference solves."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import bench_reduced

    row = bench_reduced.run_case(12, n_f=60, direct_subset=20)
    assert row["direct"]["error"] <= 1e-10 and row["auto"]["error"] <= 1e-6
    assert row["modal"]["error"] < 1.0      # 50 of 144 modes: close, not exact
    lines = bench_reduced.table([row])
    assert len([line for line in lines if line.startswith("| 12x12")]) == 4


def test_deadline_is_respected(grid_cases):
    import time

    from resonant.deadline import AnalysisTimeout, Deadline

    M, C, K, f, w = grid_cases["rayleigh"]
    late = Deadline(1e-9)
    time.sleep(0.001)
    with pytest.raises(AnalysisTimeout):
        reduced_response(M, C, K, f.astype(complex), w, deadline=late)


def test_the_modes_below_a_cut_stop_at_the_deadline() -> None:
    """The Lanczos runs of the modal/Ritz basis check the deadline at every step (400
    modes of a 20,000-coordinate chain took 48 s past a 20 s limit before)."""
    import time

    from resonant.deadline import Deadline
    from resonant.errors import AnalysisError
    from resonant.modal import factor_stiffness, modes_below

    n = 2000
    K = sp.diags([2.0 * np.ones(n), -np.ones(n - 1), -np.ones(n - 1)], [0, 1, -1],
                 format="csc")
    M = sp.identity(n, format="csc")
    lu = factor_stiffness(K, M, 1.0)
    deadline = Deadline(1e-3)
    time.sleep(0.01)
    with pytest.raises(AnalysisError, match="modes below"):
        modes_below(K, M, lu, 1.0, 400, deadline)
    # omega_k = 2 sin(k pi / 4002) <= 0.01 for k <= 6
    assert modes_below(K, M, lu, 0.01, 400).shape[1] == 6


def _free_grid(side: int) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
    """``benchmarks/corpus.py``'s grid: side x side unit masses on springs 1e4, fixed at
    one edge, Rayleigh damping 0.1 M + 1e-5 K."""
    line = sp.diags([np.full(side - 1, -1.0), np.full(side, 2.0), np.full(side - 1, -1.0)],
                    [-1, 0, 1]).tolil()
    free = line.copy()
    free[0, 0] = free[side - 1, side - 1] = 1.0
    eye = sp.identity(side)
    K = (1e4 * (sp.kron(line.tocsr(), eye) + sp.kron(eye, free.tocsr()))).tocsr()
    M = sp.identity(side * side, format="csr")
    return M, (0.1 * M + 1e-5 * K).tocsr(), K


def test_a_wide_band_with_many_modes_is_not_taken_for_a_stall():
    """The 20 x 20 grid's transfer at its corner over 0 ... 14 times its first natural
    frequency (about 100 modes): the largest residual wanders from one frequency to the
    next while each expansion point settles its neighbourhood, the median falls; the
    enrichment goes on to the tolerance (1e-6) and meets it against exact solves.  (It
    stopped there, at 181 vectors, as a 'rounding floor', with the largest residual
    alone as its measure of progress; the condensed harmonic balance with raised
    harmonics then fell back to exact sparse solves.)"""
    M, C, K = _free_grid(20)
    w1 = float(np.sqrt(sla.eigsh(K.tocsc(), k=1, M=M.tocsc(), sigma=0.0,
                                 return_eigenvectors=False)[0]))
    B = np.zeros((400, 1), dtype=complex)
    B[399, 0] = 1.0
    w = np.linspace(0.0, 14 * w1, 400)
    rom = reduced_model(M, C, K, B, w)
    assert rom.converged, rom.reason
    assert rom.V.shape[1] < 400          # not the whole space (measured 285 vectors)
    for x in w[::37]:
        exact = sla.spsolve((K - x * x * M + 1j * x * C).tocsc(), B[:, 0])
        assert abs(rom.transfer(x, np.array([399]))[0, 0] - exact[399]) <= 1e-6 * abs(exact[399])
