"""Complex modes of large non-proportionally damped models by sparse
shift-invert, without dense 2n x 2n matrices (it used to raise above 1,500 DOF).

Reference: the dense eigenvalues of the state matrix [[0, I], [-M^-1 K, -M^-1 C]]
(numpy), on a 500-DOF chain with Rayleigh damping plus one extra damper between DOF 1
and 2 (not proportional).  Tolerance: relative 1e-8 on the 20 eigenvalues of lowest
damped frequency |Im s|.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.io
import scipy.linalg
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import run_cli
from resonant.analyses.modes import modes
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
    s = lowest_state_eigenvalues(M, C, K, 10).eigenvalues
    n = 500
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K.toarray(), -C.toarray()]])
    dense = np.linalg.eigvals(A)
    dense = dense[np.argsort(np.abs(dense.imag))][:20]
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


# -- a cantilever plate under a strong Kelvin-Voigt layer ------------------------------------
#
# Its 225 layer modes are overdamped, their slow roots a cluster near -1/beta = -400 s^-1,
# below (in |s|) every structural mode from the fourth on: a search by |s| from 0 finds the
# first three and then only the cluster.  Reference: every eigenvalue of the state matrix
# by scipy.linalg.eigvals (dense, 900 x 900); the kernel's lowest complex modes by damped
# frequency must agree to a relative 1e-9 in s (frequencies and damping ratios), where
# they agree to about 1e-12.

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from damped_layer import kelvin_voigt_plate  # noqa: E402


def _dense_state_eigenvalues(M, C, K):
    """All eigenvalues of the state matrix [[0, I], [-M^-1 K, -M^-1 C]] (M is diagonal)."""
    n = M.shape[0]
    inverse = 1.0 / M.diagonal()[:, None]
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-inverse * K.toarray(), -inverse * C.toarray()]])
    return scipy.linalg.eigvals(A)


@pytest.fixture(scope="module")
def layered_plate():
    plate = kelvin_voigt_plate(15)
    return plate, _dense_state_eigenvalues(plate.M, plate.C, plate.K)


def _structural(dense, count):
    """The ``count`` underdamped eigenvalues (Im s > 0) of lowest Im s."""
    upper = dense[dense.imag > 1e-8 * np.abs(dense)]
    return upper[np.argsort(upper.imag)][:count]


def test_the_layer_puts_overdamped_modes_below_the_structural_ones(layered_plate):
    plate, dense = layered_plate
    tenth = _structural(dense, 10)[-1]
    real = dense[np.abs(dense.imag) <= 1e-8 * np.abs(dense)]
    assert np.sum(np.abs(real) < abs(tenth)) >= 200        # what made the old search fail


def test_lowest_complex_modes_by_damped_frequency_match_the_dense_pencil(layered_plate):
    plate, dense = layered_plate
    search = lowest_state_eigenvalues(plate.M, plate.C, plate.K, 10)
    expected = _structural(dense, 10)
    found = search.eigenvalues[search.eigenvalues.imag > 0]
    assert search.complete and found.size == 10
    found = found[np.argsort(found.imag)]
    np.testing.assert_allclose(found, expected, rtol=1e-9)
    np.testing.assert_allclose(-found.real / abs(found), -expected.real / abs(expected),
                               rtol=1e-8)
    # every mode of the reference with a damping ratio below the reach was found
    assert search.reach > float(np.max(-expected.real / abs(expected)))


def test_modes_command_lists_the_structural_modes(layered_plate, tmp_path):
    plate, dense = layered_plate
    for name in "MCK":
        scipy.io.mmwrite(str(tmp_path / f"{name}.mtx"), getattr(plate, name))
    model = tmp_path / "plate.toml"
    model.write_text('[matrices]\nM = "M.mtx"\nC = "C.mtx"\nK = "K.mtx"\n')
    status, out, err = run_cli(["modes", str(model), "--count", "6"])
    assert status == 0, err
    expected = _structural(dense, 6)
    listed = [line.split() for line in out.splitlines()[out.splitlines().index(
        next(line for line in out.splitlines() if line.strip().startswith("Re s"))) + 1:]]
    rows = [tuple(float(v) for v in row) for row in listed if len(row) == 3
            and all(_number(v) for v in row)]
    assert len(rows) == 6
    np.testing.assert_allclose(sorted(r[1] for r in rows), expected.imag, rtol=1e-5)
    status, out, _ = run_cli(["modes", str(model), "--count", "6", "--json"])
    data = json.loads(out)
    np.testing.assert_allclose(sorted(data["damping_ratios"]),
                               sorted(-expected.real / abs(expected)), rtol=1e-8)


def _number(text):
    try:
        float(text)
    except ValueError:
        return False
    return True


def test_dense_modes_count_the_overdamped_apart(layered_plate, tmp_path):
    plate, dense = layered_plate
    for name in "MCK":
        np.save(tmp_path / f"{name}.npy", getattr(plate, name).toarray())
    (tmp_path / "plate.toml").write_text('[matrices]\nM = "M.npy"\nC = "C.npy"\nK = "K.npy"\n')
    system = load(tmp_path / "plate.toml").linearize()
    full = modes(system)
    # each layer mode: a slow root near -1/beta and a fast one far to the left
    assert full.method == "dense" and full.overdamped.size == 450
    text = full.summary()
    assert "and 450 overdamped modes" in text
    shown = [line for line in text.splitlines() if line.strip()[:1] in "-0123456789"
             and len(line.split()) == 3]
    assert len(shown) == 20
    limited = modes(system, count=4)
    expected = _structural(dense, 4)
    np.testing.assert_allclose(np.sort(limited.damped_frequencies), expected.imag, rtol=1e-9)


@settings(max_examples=10, deadline=None)
@given(side=st.integers(4, 7), beta=st.floats(1e-3, 1e-2), mu=st.floats(0.02, 0.2),
       count=st.integers(2, 6))
def test_sparse_search_and_dense_pencil_agree_on_random_layers(side, beta, mu, count):
    """Two routes, one answer: the kernel's search along the imaginary axis and every
    eigenvalue of the dense state matrix, on plates of 32 to 98 coordinates whose layer
    damping and mass vary.  Each mode found is an eigenvalue (relative 1e-8), and every
    complex mode up to the highest found whose damping ratio is within the search's reach
    is found (a nearly critically damped pair far from the axis may lie beyond it)."""
    plate = kelvin_voigt_plate(side, beta=beta, mu=mu)
    search = lowest_state_eigenvalues(plate.M, plate.C, plate.K, count)
    dense = _dense_state_eigenvalues(plate.M, plate.C, plate.K)
    found = search.eigenvalues[search.eigenvalues.imag > 0]
    assert found.size == count
    for value in found:
        assert np.min(np.abs(dense - value)) <= 1e-8 * abs(value)
    upper = _structural(dense, dense.size)
    within = upper[(-upper.real / abs(upper) <= search.reach) &
                   (upper.imag <= found.imag.max() * (1 + 1e-9))]
    for value in within:
        assert np.min(np.abs(found - value)) <= 1e-8 * abs(value)


def test_the_benchmark_runs_at_a_tiny_size(capsys):
    import bench_complex_modes

    assert bench_complex_modes.main(["--side", "5", "--count", "4", "--repeats", "1",
                                     "--band", "80", "400", "--slices", "3"]) == 0
    row = capsys.readouterr().out.splitlines()[-1].split("|")
    assert row[1].strip() == "50" and float(row[6]) < 1e-8     # agrees with eigs by hand
