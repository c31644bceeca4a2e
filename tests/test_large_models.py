"""Models with more than 64 parameters.

Such models used to fail in every command with ``Need at least 0 and at most 64
array objects`` (``np.broadcast`` in the compiled evaluation, now
``np.broadcast_shapes``).  Two chains, every number checked against an
independent numeric computation built here from the textbook formulas:

* a fixed-free spring-mass chain of 50 masses (102 parameters: m_i, k_i, F0,
  omega), cheap symbolically, through ``solve``, ``modes``, ``sweep`` and
  ``report``.  Reference: M = diag(m), K tridiagonal (Rao, Mechanical
  Vibrations, Sect. 6); stationary amplitude X = (K - omega^2 M)^-1 F.
* the 50-link pendulum chain of ``benchmarks/pendulum_chain.py`` (101
  parameters: g, m_i, l_i), whose symbolic matrices are dense with O(N) terms
  per entry (the heavy part, marked slow).  Reference: with absolute angles the
  linearized T = 1/2 sum_i m_i |sum_{j<=i} l_j th_j'|^2 and
  U = 1/2 g sum_i m_i sum_{j<=i} l_j th_j^2, hence
  M_ij = l_i l_j sum_{k>=max(i,j)} m_k and K = diag(g l_i sum_{k>=i} m_k)
  (Landau & Lifshitz, Mechanics, Sect. 5 and 23), solved with scipy.linalg.eigh.

Tolerances: relative 1e-9 on frequencies and amplitudes (both sides are double
precision dense eigen/linear solves of well-conditioned matrices; observed
differences are ~1e-13).
"""

from __future__ import annotations

import math
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from conftest import run_cli, run_json

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

from pendulum_chain import write_pendulum_chain  # noqa: E402

RTOL = 1e-9
N_SPRING = 50
N_PENDULUM = 50


# -- the spring-mass chain -------------------------------------------------------------------

def spring_values(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Irregular masses and stiffnesses, so no accidental symmetry hides an error."""
    m = np.array([1.0 + 0.1 * (i % 7) for i in range(1, n + 1)])
    k = np.array([1000.0 + 50.0 * (i % 5) for i in range(1, n + 1)])
    return m, k


def spring_chain_toml(n: int, F0: float = 10.0, omega: float = 3.0) -> str:
    m, k = spring_values(n)
    lines = ["title = \"spring-mass chain\"", "", "[parameters]"]
    lines += [f"m{i} = {float(m[i - 1])!r}" for i in range(1, n + 1)]
    lines += [f"k{i} = {float(k[i - 1])!r}" for i in range(1, n + 1)]
    lines += [f"F0 = {F0!r}", f"omega = {omega!r}", "", "[coordinates]"]
    lines += [f'x{i} = "mass {i}"' for i in range(1, n + 1)]
    lines += ["", "[signals]", 'F = "F0*sin(omega*t)"', "", "[energy]"]
    lines.append('T = "' + " + ".join(f"m{i}*x{i}'^2/2" for i in range(1, n + 1)) + '"')
    springs = ["k1*x1^2/2"] + [f"k{i}*(x{i} - x{i - 1})^2/2" for i in range(2, n + 1)]
    lines.append('U = "' + " + ".join(springs) + '"')
    lines += ["", "[[force]]", 'name = "F on the last mass"', 'vector = ["F"]',
              f'point = ["x{n}"]', ""]
    return "\n".join(lines)


def spring_matrices(n: int) -> tuple[np.ndarray, np.ndarray]:
    m, k = spring_values(n)
    K = np.zeros((n, n))
    for i in range(n):  # spring i joins mass i-1 (or the wall) and mass i
        K[i, i] += k[i]
        if i > 0:
            K[i - 1, i - 1] += k[i]
            K[i, i - 1] -= k[i]
            K[i - 1, i] -= k[i]
    return np.diag(m), K


def reference_frequencies(M: np.ndarray, K: np.ndarray) -> np.ndarray:
    return np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True))


def reference_amplitudes(M: np.ndarray, K: np.ndarray, omega: float, F0: float) -> np.ndarray:
    f = np.zeros(len(M))
    f[-1] = F0
    return np.abs(np.linalg.solve(K - omega**2 * M, f))


@pytest.fixture(scope="module")
def spring_chain(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("large") / "spring_chain.toml"
    path.write_text(spring_chain_toml(N_SPRING), encoding="utf-8")
    return path


def test_spring_chain_has_more_than_64_parameters(spring_chain):
    import resonant

    assert len(resonant.load(spring_chain).parameters) == 2 * N_SPRING + 2 > 64


def test_spring_chain_solve(spring_chain):
    data = run_json("solve", spring_chain, "--timeout", "600")
    assert len(data["parameters"]) == 2 * N_SPRING + 2
    M, K = spring_matrices(N_SPRING)
    np.testing.assert_allclose(data["natural_frequencies"], reference_frequencies(M, K),
                               rtol=RTOL)
    amplitudes = [data["amplitudes"][f"x{i}"] for i in range(1, N_SPRING + 1)]
    assert all(math.isfinite(a) for a in amplitudes)
    np.testing.assert_allclose(amplitudes, reference_amplitudes(M, K, 3.0, 10.0), rtol=RTOL)


def test_spring_chain_modes(spring_chain):
    data = run_json("modes", spring_chain, "--timeout", "600")
    M, K = spring_matrices(N_SPRING)
    np.testing.assert_allclose(data["natural_frequencies"], reference_frequencies(M, K),
                               rtol=RTOL)
    assert np.all(np.isfinite(np.asarray(data["mode_shapes"], dtype=float)))


def test_spring_chain_sweep(spring_chain):
    data = run_json("sweep", spring_chain, "--param", "omega", "--from", "1", "--to", "5",
                    "--points", "5", "--only", f"x1,x{N_SPRING}", "--timeout", "600")
    assert all(math.isfinite(a) for seq in data["amplitudes"].values() for a in seq)
    M, K = spring_matrices(N_SPRING)
    omegas = np.linspace(1.0, 5.0, 5)
    expected = np.array([reference_amplitudes(M, K, w, 10.0)[-1] for w in omegas])
    np.testing.assert_allclose(data["values"], omegas, rtol=1e-12)
    np.testing.assert_allclose(data["amplitudes"][f"x{N_SPRING}"], expected, rtol=RTOL)
    np.testing.assert_allclose(data["natural_frequencies"], reference_frequencies(M, K),
                               rtol=RTOL)


@pytest.mark.slow  # the report's step-by-step derivation of 50 coordinates: ~8 s CPU
def test_spring_chain_report(spring_chain, tmp_path):
    out = tmp_path / "x.html"
    status, stdout, stderr = run_cli(["report", spring_chain, "-o", out, "--no-plots",
                                      "--timeout", "600"])
    assert status == 0, stderr
    text = out.read_text(encoding="utf-8")
    assert "<html" in text.lower() and len(text) > 1000
    assert "nan" not in stderr.lower()


# -- the pendulum chain (benchmarks/pendulum_chain.py) ---------------------------------------

def pendulum_values(n: int) -> tuple[float, np.ndarray, np.ndarray]:
    """The values pendulum_chain_toml writes (re-derived here, checked below)."""
    m = np.array([1.0 + 0.1 * (i % 7) for i in range(1, n + 1)])
    l = np.array([0.5 + 0.05 * (i % 5) for i in range(1, n + 1)])  # noqa: E741
    return 9.81, m, l


def pendulum_matrices(n: int) -> tuple[np.ndarray, np.ndarray]:
    g, m, l = pendulum_values(n)  # noqa: E741
    tail = np.cumsum(m[::-1])[::-1]  # tail[k] = sum_{j>=k} m_j
    idx = np.arange(n)
    M = np.outer(l, l) * tail[np.maximum.outer(idx, idx)]
    K = np.diag(g * l * tail)
    return M, K


def test_pendulum_reference_is_the_double_pendulum():
    """The reference formulas at N = 2 against the textbook double pendulum
    (Landau & Lifshitz Sect. 5 Problem 1, linearized): M = [[(m1+m2) l1^2, m2 l1 l2],
    [m2 l1 l2, m2 l2^2]], K = diag((m1+m2) g l1, m2 g l2)."""
    g, (m1, m2), (l1, l2) = pendulum_values(2)
    M, K = pendulum_matrices(2)
    np.testing.assert_allclose(M, [[(m1 + m2) * l1**2, m2 * l1 * l2],
                                   [m2 * l1 * l2, m2 * l2**2]], rtol=1e-15)
    np.testing.assert_allclose(K, np.diag([(m1 + m2) * g * l1, m2 * g * l2]), rtol=1e-15)


@pytest.mark.slow  # dense symbolic M with O(N) terms per entry: ~10 s CPU
def test_pendulum_chain_modes(tmp_path):
    path = write_pendulum_chain(N_PENDULUM, tmp_path)
    data = run_json("modes", path, "--timeout", "600")
    params = tomllib.loads(path.read_text(encoding="utf-8"))["parameters"]
    assert len(params) == 2 * N_PENDULUM + 1 > 100
    g, m, l = pendulum_values(N_PENDULUM)  # noqa: E741
    assert [float(params[f"m{i}"]) for i in range(1, N_PENDULUM + 1)] == pytest.approx(m)
    assert [float(params[f"l{i}"]) for i in range(1, N_PENDULUM + 1)] == pytest.approx(l)
    expected = reference_frequencies(*pendulum_matrices(N_PENDULUM))
    got = np.asarray(data["natural_frequencies"], dtype=float)
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, expected, rtol=RTOL)
    assert np.all(np.isfinite(np.asarray(data["mode_shapes"], dtype=float)))

