"""The reduced model's shortcuts for large models give the answer of the plain route.

* expansion points factorized two at a time, and the validation point factorized while
  the adjoints' moments are made (a helper thread, used from
  :data:`resonant.analyses.reduced.PARALLEL_FACTOR_SIZE` coordinates; lowered to 0 here):
  the same expansion points, validations, basis and reduced matrices as one at a time,
  to rounding (each factorization and solve is the same arithmetic in either thread);
* the residuals of several loads on one basis from one update of the residual's
  factorization (``replace_loads``, used for the adjoints of ``reduced_model``): the
  same norms as one load at a time, to rounding (1e-10 relative);
* ``reduced_model`` with adjoints: each adjoint's reported largest residual is the one
  computed directly, ||A(w) V y(w) - e_i|| / ||e_i|| with y the Galerkin solution,
  at every frequency of the band (1e-8 relative).
"""

from __future__ import annotations

import itertools
import sys
import threading
import traceback
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import bench_reduced  # noqa: E402

from resonant.analyses import reduced  # noqa: E402


def grid(nx: int, seed: int = 0):
    """(M, C, K) of the random nx x nx grid of benchmarks/bench_reduced.py: edges
    grounded, irregular springs and masses, C = 0.1 M + 1e-3 K (lowest natural frequency
    about 5 rad/s)."""
    M, C, K, _ = bench_reduced.grid_matrices(nx, seed)
    return M, C, K


@pytest.fixture(scope="module")
def case():
    M, C, K = grid(24)
    n = M.shape[0]
    B = np.zeros((n, 2), dtype=complex)
    B[:, 0] = -(M @ np.ones(n))           # a base acceleration
    B[n // 3, 1] = 1.0                    # a point force
    keep = np.array([5, n // 2, n - 30])
    unit = np.zeros((n, len(keep)), dtype=complex)
    unit[keep, np.arange(len(keep))] = 1.0
    w = np.linspace(20.0, 160.0, 400)
    return M, C, K, B, unit, w


def test_parallel_factorizations_give_the_serial_model(case, monkeypatch):
    M, C, K, B, unit, w = case
    serial = reduced.reduced_model(M, C, K, B, w, tol=1e-6, adjoints=unit)
    threads: list[str] = []
    plain = reduced._factor_near

    def spy(*args, **kwargs):
        threads.append(threading.current_thread().name)
        return plain(*args, **kwargs)

    callers: list[str] = []
    moments = reduced._adjoint_moments

    def spy_moments(*args, **kwargs):
        callers.append(traceback.extract_stack()[-2].name)
        return moments(*args, **kwargs)

    monkeypatch.setattr(reduced, "PARALLEL_FACTOR_SIZE", 0)
    monkeypatch.setattr(reduced, "_factor_near", spy)
    monkeypatch.setattr(reduced, "_adjoint_moments", spy_moments)
    parallel = reduced.reduced_model(M, C, K, B, w, tol=1e-6, adjoints=unit)
    assert any(name.startswith("resonant-lu") for name in threads)   # the helper was used
    assert callers[0] == "side"   # the adjoints' moments made during the first validation
    assert parallel.expansion == serial.expansion
    assert len(parallel.checks) == len(serial.checks)
    for (s1, e1), (s2, e2) in zip(parallel.checks, serial.checks):
        assert s1 == s2
        assert e1 == pytest.approx(e2, rel=1e-6, abs=1e-13)
    assert parallel.V.shape == serial.V.shape
    # same span: the projection of one basis onto the other keeps its norm
    overlap = np.linalg.svd(parallel.V.T @ serial.V, compute_uv=False)
    assert np.all(overlap > 1 - 1e-9)
    Z1, _ = parallel.responses(w, np.arange(M.shape[0]))
    Z2, _ = serial.responses(w, np.arange(M.shape[0]))
    assert np.abs(Z1 - Z2).max() <= 1e-10 * np.abs(Z2).max()
    assert parallel.estimated_error == pytest.approx(serial.estimated_error, rel=1e-6)
    assert parallel.adjoint_residuals == pytest.approx(serial.adjoint_residuals, rel=1e-8)


def test_residuals_of_several_loads_at_once(case):
    M, C, K, B, unit, w = case
    rom = reduced.reduced_model(M, C, K, B[:, :1], w, tol=1e-6)
    ops = reduced._Operators(M, C, K)
    projection = reduced._Projection(ops)
    residual = reduced._Residual(ops, B[:, 0])
    residual.extend(projection.update(np.array(rom.V)), rom.V.shape[1])
    Kr, Mr, Cr = projection.reduced
    loads = np.column_stack([unit, B[:, 1], 1j * B[:, 0]])
    Ys = [reduced._Reduced(Kr, Mr, Cr, rom.V.T @ loads[:, j]).solve(w)
          for j in range(loads.shape[1])]
    one_by_one = []
    for j in range(loads.shape[1]):
        residual.replace_load(loads[:, j])
        one_by_one.append(residual.norms(w, Ys[j]))
    residual.replace_loads(loads)
    for j in range(loads.shape[1]):
        together = residual.norms(w, Ys[j], which=j)
        np.testing.assert_allclose(together, one_by_one[j], rtol=1e-10,
                                   atol=1e-14 * np.linalg.norm(loads[:, j]))


def test_adjoint_residuals_are_the_computed_residuals(case):
    M, C, K, B, unit, w = case
    rom = reduced.reduced_model(M, C, K, B, w, tol=1e-6, adjoints=unit)
    V = np.array(rom.V)
    for j in range(unit.shape[1]):
        e = unit[:, j]
        Y = reduced._Reduced(np.array(rom.Kr), np.array(rom.Mr), np.array(rom.Cr),
                             V.T @ e).solve(w)
        worst = 0.0
        for x, y in zip(w, Y):
            z = V @ y
            r = K @ z - x * x * (M @ z) + 1j * x * (C @ z) - e
            worst = max(worst, float(np.linalg.norm(r)))
        assert rom.adjoint_residuals[j] == pytest.approx(worst, rel=1e-8, abs=1e-13)


@pytest.mark.parametrize("method", ["reduced", "auto"])
def test_random_response_with_factorizations_ahead(tmp_path, monkeypatch, method):
    """The first expansion points factorized in a helper thread during the cost probe
    (``auto``) or before the reduced model (``reduced``): the same result."""
    from resonant.analyses.random_response import random_response
    from resonant.model import loads
    from resonant.system import linear_system

    nx = 20
    M, C, K = grid(nx, seed=2)
    K = K * 400.0   # natural frequencies about 100-1300 rad/s, in the band
    C = 0.5 * M + 2e-5 * K
    for key, a in (("M", M), ("C", C), ("K", K)):
        sp.save_npz(tmp_path / f"{key}.npz", a.tocsr())
    text = ('[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
            '[random]\nband = [5, 300]\ntolerance = 1e-4\n[random.psd.a]\n'
            f'unit = "(m/s^2)^2/Hz"\nbase = [{", ".join(["1"] * nx * nx)}]\n'
            'values = [[5, 1.0], [50, 2.0], [300, 0.5]]\n')
    system = linear_system(loads(text, source=str(tmp_path / "grid.toml"), base_dir=tmp_path))
    names = [system.coordinates[i] for i in (nx * nx // 2 + nx // 2, 3 * nx + 4)]
    plain = random_response(system, names=names, method=method)
    made: list[str] = []
    factor = reduced._Operators.factor

    def spy(self, s, partial=False):
        made.append(threading.current_thread().name)
        return factor(self, s, partial)

    monkeypatch.setattr(reduced, "PARALLEL_FACTOR_SIZE", 0)
    monkeypatch.setattr(reduced._Operators, "factor", spy)
    ahead = random_response(system, names=names, method=method)
    assert any(name.startswith("resonant-lu") for name in made)
    assert ahead.method == plain.method
    for q in names:
        assert ahead.rms[q] == pytest.approx(plain.rms[q], rel=1e-10)
        assert ahead.error[q] == pytest.approx(plain.error[q], rel=1e-6, abs=1e-12)


def test_helper_thread_factors_are_freed_in_their_thread(case, monkeypatch):
    """SuperLU (scipy 1.17) gives a factor's memory back only when the factor is freed in
    the thread that made it (a 40,000-row grid kept 40 MB per factorization freed
    elsewhere; 8 reduced models of a 22,500-row grid grew the process by 0.9 GB): every
    factorization made by the helper thread, the ones made ahead for ``auto`` included,
    is freed in that thread once the model is built."""
    M, C, K, B, unit, w = case
    made: dict[int, str] = {}
    freed: dict[int, str] = {}

    tags = itertools.count()

    class Tracked(reduced.ScaledLU):
        # a tag of its own, not id(): a freed factor's id is taken by the next object
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self.tag = next(tags)
            made[self.tag] = threading.current_thread().name

        def __del__(self):
            freed[self.tag] = threading.current_thread().name

    monkeypatch.setattr(reduced, "PARALLEL_FACTOR_SIZE", 0)
    monkeypatch.setattr(reduced, "ScaledLU", Tracked)
    ahead = reduced.FactorizationsAhead(M, C, K, w)
    probe = dict(ahead.futures)
    reduced.reduced_model(M, C, K, B, w, tol=1e-6, adjoints=unit, factorizations=probe)
    probe.clear()
    ahead.stop()
    for _ in range(200):   # the helper threads free them after their last task
        if len(freed) == len(made):
            break
        threading.Event().wait(0.01)
    helper = {key for key, name in made.items() if name.startswith("resonant-lu")}
    assert helper, made   # the helper threads made some
    assert freed.keys() == made.keys()
    assert all(freed[key] == made[key] for key in helper), (made, freed)
