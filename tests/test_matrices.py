"""Matrix models: ``[matrices]`` inline, .npy, .npz (dense and scipy.sparse), .mtx.

The reference for every check is a direct dense computation with the same numbers
(exact up to rounding: tolerances 1e-12 relative) or the fixed-free chain closed form
omega_j = 2 sqrt(k/m) sin((2j-1) pi/(2(2n+1))) (Rao, Mechanical Vibrations, Sect. 6).
"""

from __future__ import annotations

import importlib
import json
import math
import sys

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

from conftest import EXAMPLES, run_cli, solve_json
from resonant.errors import ModelError
from resonant.system import LinearEOM, MatrixEOM

stationary_module = importlib.import_module("resonant.analyses.stationary")
from resonant.analyses.stationary import stationary
from resonant.api import load, loads

sys.path.insert(0, str(EXAMPLES))
from make_chain import chain_matrices, write_chain  # noqa: E402

M3 = np.diag([1.0, 2.0, 1.5])
K3 = np.array([[300.0, -100.0, 0.0], [-100.0, 250.0, -150.0], [0.0, -150.0, 150.0]])
C3 = 0.02 * K3 + 0.1 * M3
HARMONIC = '[[harmonic]]\nomega = "w"\nF_S = [0, 0, "F0"]\nF_C = [1, 0, 0]\n'
PARAMS = "[parameters]\nw = 7\nF0 = 2\n"


def direct(w=7.0, F0=2.0):
    X = np.linalg.solve(K3 - w**2 * M3 + 1j * w * C3, np.array([1.0, 0, 0]) -
                        1j * np.array([0, 0, F0]))
    return X.real, -X.imag


def rows(a):
    return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in r) + "]" for r in a) + "]"


def write(tmp_path, body: str, name="model.toml"):
    path = tmp_path / name
    path.write_text(PARAMS + "[matrices]\n" + body + HARMONIC)
    return path


def check_solution(path_or_model):
    model = load(path_or_model) if not hasattr(path_or_model, "matrices") else path_or_model
    solution = model.linearize().stationary()
    L, N = direct()
    np.testing.assert_allclose(solution.harmonics[0].L, L, rtol=1e-12)
    np.testing.assert_allclose(solution.harmonics[0].N, N, rtol=1e-12)
    np.testing.assert_allclose(solution.eom.M, M3, rtol=1e-15)
    np.testing.assert_allclose(solution.eom.C, C3, rtol=1e-15)
    return solution


def test_inline_matrices(tmp_path):
    path = write(tmp_path, f"M = {rows(M3)}\nK = {rows(K3)}\nC = {rows(C3)}\n")
    check_solution(path)


def test_inline_expressions_match_symbolic_path():
    """The numeric path (no sympy) equals evaluate() of the symbolic matrices (rel 1e-14)."""
    model = loads('[parameters]\nm = 2\nk = 100\nc = 0.5\nw = 3\n[matrices]\n'
                  'M = [["m", 0], [0, "m/2"]]\nK = [["2*k", "-k"], ["-k", "k"]]\n'
                  'C = [["c", 0], [0, "c"]]\n[[harmonic]]\nomega = "w"\nF_S = [0, 1]\n'
                  '[[harmonic]]\nomega = "-2*w"\nF_S = [1, 0]\nF_C = [0, "sqrt(k)"]\n')
    eom = model.linearize()
    assert isinstance(eom, MatrixEOM)
    fast, slow = eom.numeric(), _symbolic_route(eom).numeric()
    for key in ("M", "C", "K"):
        np.testing.assert_allclose(getattr(fast, key), getattr(slow, key), rtol=1e-14)
    for a, b in zip(fast.harmonics, slow.harmonics):
        assert a.omega == pytest.approx(b.omega, rel=1e-14)
        np.testing.assert_allclose(a.F_S, b.F_S, rtol=1e-14)
        np.testing.assert_allclose(a.F_C, b.F_C, rtol=1e-14)
    assert str(eom.M) == "Matrix([[m, 0], [0, m/2]])"  # the symbolic form is still there
    assert stationary(fast).amplitudes == pytest.approx(stationary(slow).amplitudes,
                                                        rel=1e-12)


class _SymbolicCopy(LinearEOM):
    """The matrix model's sympy matrices, evaluated by the compiled symbolic route."""

    def __init__(self, eom):
        super().__init__(eom.model, eom.coordinates, eom.M, eom.C, eom.K, eom.excitation,
                         eom.residual, {})
        object.__setattr__(self, "signal_functions", eom.signal_functions)


def _symbolic_route(eom):
    return _SymbolicCopy(eom)


def test_npy_files(tmp_path):
    for name, a in (("M", M3), ("K", K3), ("C", C3)):
        np.save(tmp_path / f"{name}.npy", a)
    check_solution(write(tmp_path, 'M = "M.npy"\nK = "K.npy"\nC = "C.npy"\n'))


def test_npz_named_single_and_sparse(tmp_path):
    np.savez(tmp_path / "all.npz", M=M3, K=K3, C=C3)
    np.savez(tmp_path / "only.npz", matrix=K3)
    sp.save_npz(tmp_path / "C_sparse.npz", sp.csr_matrix(C3))
    check_solution(write(tmp_path, 'M = "all.npz"\nK = "only.npz"\nC = "C_sparse.npz"\n'))


def test_mtx_files(tmp_path):
    scipy.io.mmwrite(str(tmp_path / "K.mtx"), sp.coo_matrix(K3))
    scipy.io.mmwrite(str(tmp_path / "M.mtx"), M3)  # dense Matrix Market ("array")
    np.save(tmp_path / "C.npy", C3)
    model = load(write(tmp_path, 'M = "M.mtx"\nK = "K.mtx"\nC = "C.npy"\n'))
    assert sp.issparse(model.linearize().numeric().K)
    check_solution(model)


@pytest.mark.parametrize("body, key, text", [
    ("M = [[1, 0], [0, 1]]\nK = [[1, 0, 0], [0, 1]]\n", "K", "square"),
    ("M = [[1, 0], [0, 1]]\nK = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n", "", "same size"),
    ('M = "missing.npy"\nK = [[1]]\n', "M", "cannot read"),
    ('M = "bad.npy"\nK = [[1]]\n', "M", "cannot read"),
    ('M = "rect.npy"\nK = [[1]]\n', "M", "square"),
    ('M = "text.npy"\nK = [[1]]\n', "M", ""),
    ('M = [[1]]\nK = "K.txt"\n', "K", "array of rows"),
    ('M = [[1]]\nK = [["k"]]\n', "K", "k"),
    ("M = [[1]]\n", "K", "missing"),
    ('M = [[1]]\nK = [[1]]\nX = [[1]]\n', "X", "unknown key"),
])
def test_matrix_errors_name_the_key(tmp_path, body, key, text):
    (tmp_path / "bad.npy").write_bytes(b"this is not numpy")
    np.save(tmp_path / "rect.npy", np.ones((2, 3)))
    np.save(tmp_path / "text.npy", np.array([["a"]]))
    path = tmp_path / "m.toml"
    path.write_text("[matrices]\n" + body)
    with pytest.raises(ModelError) as info:
        load(path)
    message = str(info.value)
    assert text in message
    if key:
        assert f"[matrices] {key}" in message
    code, _, err = run_cli(["solve", path])
    assert code == 2 and "Traceback" not in err


def test_harmonic_size_mismatch(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text('[matrices]\nM = [[1, 0], [0, 1]]\nK = [[2, 0], [0, 2]]\n'
                    '[[harmonic]]\nomega = 1\nF_S = [1, 2, 3]\n')
    with pytest.raises(ModelError, match="F_S"):
        load(path)


def test_large_chain_solve_is_fast_and_exact(tmp_path, monkeypatch):
    """1000-mass chain from files: `resonant solve` (sparse path) equals the dense
    stationary() (amplitudes rel 1e-9, natural frequencies vs the closed form rel 1e-9).

    Fast: the proportional damping gives the eigenvalues from the undamped ones; the dense
    2000 x 2000 state eigenproblem (minutes here) must not run -- checked by making it fail
    rather than by a wall-clock bound, which a loaded CI machine can break."""
    def state_eigenproblem(*args, **kwargs):
        raise AssertionError("the dense 2n x 2n state eigenproblem was solved")

    monkeypatch.setattr(stationary_module, "point_state_eigenvalues", state_eigenproblem)
    path = write_chain(tmp_path, 1000)
    model = load(path)
    fast = model.linearize().stationary()
    j = np.arange(1, 1001)
    exact = 200 * np.sin((2 * j - 1) * math.pi / (2 * 2001))
    np.testing.assert_allclose(fast.natural_frequencies, exact, rtol=1e-9)
    M, C, K = (a.toarray() for a in chain_matrices(1000))
    X = np.linalg.solve(K - 2500 * M + 50j * C, -1j * np.eye(1000)[-1])
    np.testing.assert_allclose(fast.harmonics[0].L, X.real, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(fast.harmonics[0].N, -X.imag, rtol=1e-9, atol=1e-15)
    assert fast.stability == "asymptotically stable"


def test_large_stationary_equals_stationary_on_medium_chain(tmp_path):
    """The sparse path and stationary() agree (n = 150, below the switch-over)."""
    eom = load(write_chain(tmp_path, 150)).linearize()
    slow = stationary(eom)
    saved = stationary_module.LARGE
    stationary_module.LARGE = 0  # the sparse path for this medium model too
    try:
        fast = stationary(eom)
    finally:
        stationary_module.LARGE = saved
    np.testing.assert_allclose(fast.natural_frequencies, slow.natural_frequencies, rtol=1e-9)
    for key, value in slow.amplitudes.items():
        assert fast.amplitudes[key] == pytest.approx(value, rel=1e-9)
    np.testing.assert_allclose(np.sort_complex(fast.eigenvalues),
                               np.sort_complex(slow.eigenvalues), rtol=1e-8, atol=1e-9)
    assert fast.stability == slow.stability


def test_cli_solve_matrix_model(tmp_path):
    path = write(tmp_path, f"M = {rows(M3)}\nK = {rows(K3)}\nC = {rows(C3)}\n")
    data = solve_json(path)
    L, N = direct()
    np.testing.assert_allclose(data["harmonics"][0]["L"], L, rtol=1e-12)
    assert "symbolic" not in data and data["coordinates"] == ["q1", "q2", "q3"]
    json.dumps(data)


def test_make_chain_script(tmp_path):
    from make_chain import main

    assert main([str(tmp_path), "--n", "12"]) == 0
    model = load(tmp_path / "chain12.toml")
    assert len(model.coordinates) == 12
