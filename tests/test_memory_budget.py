"""Memory bounded by design (resonant.memory): analyses whose arrays grow with the request
estimate them first and stream, chunk or refuse above the budget.

Each model here is chosen to make the naive size explode: a light coordinate (the
monodromy's step count), many spectral lines on many coordinates, a long history of a
large model.  The command runs in a subprocess under a 2 GiB address-space limit (the
interpreter, numpy and scipy take about half of it): before, these ended in
``internal error (MemoryError ...)`` after asking for 3 to 60 GiB.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

from resonant.errors import AnalysisError, ModelError

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from bench_memory_paths import LIGHT_MODEL  # noqa: E402

from limited_runner import run_resonant  # noqa: E402

ADDRESS_SPACE = 2 << 30


def run_limited(args: list[str], env: dict[str, str] | None = None, timeout: float = 240
                ) -> tuple[int, str, str]:
    """``resonant ARGS`` in a child process with at most ADDRESS_SPACE bytes of address
    space, one BLAS thread (tests/limited_runner.py)."""
    environment = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
                       MKL_NUM_THREADS="1", **(env or {}))
    proc = run_resonant(list(map(str, args)), memory=ADDRESS_SPACE, timeout=timeout,
                        env=environment)
    return proc.returncode, proc.stdout, proc.stderr


def rows(a: np.ndarray) -> str:
    return "[" + ", ".join("[" + ", ".join(f"{v:.17g}" for v in r) + "]" for r in a) + "]"


def chain(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    K = 1e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    K[-1, -1] = 1e4
    return np.eye(n), 0.01 * np.eye(n) + 1e-4 * K, K




def test_the_stability_of_a_stiff_light_coordinate_is_bounded(tmp_path: Path) -> None:
    """A light, heavily damped coordinate made the monodromy's step count (4 T |A|) and
    its stack of matrices huge (5.3 GiB with 17 harmonics, 9.5 GiB with 25, 60 GiB with 40): the steps now go a chunk at a
    time, and Hill's matrix is taken where it is the cheaper of the two."""
    path = tmp_path / "light.toml"
    path.write_text(LIGHT_MODEL)
    code, out, err = run_limited(["sweep", path, "--nonlinear", "--param", "w", "--from",
                                  "0.98", "--to", "1.02", "--harmonics", "17", "--points", "4"])
    assert code == 0, err
    assert "MemoryError" not in err and "peak of the stable branch" in out


def test_many_lines_on_many_coordinates_are_refused_before_the_work(tmp_path: Path) -> None:
    """``[random] lines = 1000000`` on a 100-coordinate chain: 2.98 GiB of kept responses,
    refused with the size and how to ask for less (exit 3) before the solves."""
    M, C, K = chain(100)
    load = ", ".join(["0"] * 99 + ["1"])
    path = tmp_path / "chain.toml"
    path.write_text(f"[matrices]\nM = {rows(M)}\nK = {rows(K)}\nC = {rows(C)}\n"
                    f"[random]\nband = [1, 100]\nlines = 1000000\n[random.psd.W]\n"
                    f"values = 1\nload = [{load}]\n")
    code, _, err = run_limited(["random", path])
    assert code == 3, err
    assert "GiB of memory, above the budget" in err and "fewer" in err


def test_the_budget_is_the_environment_s(tmp_path: Path) -> None:
    """``RESONANT_MEMORY`` sets the budget; a value that is no size is exit 2 naming it."""
    M, C, K = chain(3)
    path = tmp_path / "chain.toml"
    path.write_text(f"[parameters]\nomega = 1\n[matrices]\nM = {rows(M)}\nK = {rows(K)}\n"
                    f"C = {rows(C)}\n[[harmonic]]\nomega = \"omega\"\nF_C = [0, 0, 1]\n"
                    "F_S = [0, 0, 0]\n")
    code, _, err = run_limited(["sweep", path, "--param", "omega", "--from", "1", "--to",
                                "100", "--points", "100000"], env={"RESONANT_MEMORY": "1M"})
    assert code == 3 and "above the budget of 1 MiB" in err, err
    code, _, err = run_limited(["solve", path], env={"RESONANT_MEMORY": "lots"})
    assert code == 2 and "RESONANT_MEMORY" in err and "no memory size" in err, err


def test_a_long_history_keeps_only_what_was_asked(monkeypatch: pytest.MonkeyPatch) -> None:
    """A transient of 10^6 samples on a 40-coordinate chain held samples x states before
    it stepped (2.7 GiB at 3 10^6 samples and 60 coordinates): now it holds the histories
    asked for, and refuses what would pass the budget before it steps."""
    import resonant
    from resonant.analyses.transient import transient_response

    M, C, K = chain(40)
    model = resonant.loads(f"[matrices]\nM = {rows(M)}\nK = {rows(K)}\nC = {rows(C)}\n")
    u = np.zeros(1_000_000)
    u[:100] = 1.0
    monkeypatch.setenv("RESONANT_MEMORY", "64M")
    with pytest.raises(AnalysisError, match=r"1000000 samples x 40 coordinates"):
        transient_response(model.linearize(), "q40", u, 1e-5)
    short = transient_response(model.linearize(), "q40", u[:20_000], 1e-5, names=["q40"])
    assert list(short.history) == ["q40"] and short.history["q40"].shape == (20_000,)


def test_the_budget_reads_sizes() -> None:
    from resonant.memory import budget

    for text, value in (("512M", 512 * 2**20), ("1.5GiB", 3 * 2**29), ("4g", 4 * 2**30),
                        ("2097152", 2**21)):
        os.environ["RESONANT_MEMORY"] = text
        try:
            assert budget() == value
        finally:
            del os.environ["RESONANT_MEMORY"]
    os.environ["RESONANT_MEMORY"] = "-1G"
    try:
        with pytest.raises(ModelError, match="RESONANT_MEMORY"):
            budget()
    finally:
        del os.environ["RESONANT_MEMORY"]


def sparse_chain_model(tmp_path: Path, n: int, sections: str) -> Path:
    """A Rayleigh-damped chain of ``n`` masses given as sparse .npz matrices, loaded at
    its last mass (a .npy vector), with the model's further ``sections``."""
    import scipy.sparse as sp

    K = sp.diags([2e4 * np.ones(n), -1e4 * np.ones(n - 1), -1e4 * np.ones(n - 1)],
                 [0, 1, -1], format="csr")
    M = sp.identity(n, format="csr")
    for name, matrix in (("K", K), ("M", M), ("C", 0.01 * M + 1e-4 * K)):
        sp.save_npz(tmp_path / f"{name}.npz", matrix.tocsr())
    load = np.zeros(n)
    load[-1] = 1.0
    np.save(tmp_path / "load.npy", load)
    path = tmp_path / "chain.toml"
    path.write_text('[matrices]\nM = "M.npz"\nK = "K.npz"\nC = "C.npz"\n' + sections)
    return path


def test_a_sparse_model_s_dense_analyses_and_many_lines_are_refused(tmp_path: Path) -> None:
    """A 3,000-coordinate sparse chain under a 64 MiB budget: the simulation and the largest
    shock responses made M, C and K dense (216 MiB) and the random response with 2 10^4 lines kept every coordinate at
    every frequency, in the reduced model's responses too (an internal MemoryError under
    the address-space limit); both are refused (exit 3) with the size, before the work."""
    path = sparse_chain_model(tmp_path, 3000, "[random]\nband = [0.1, 20]\nlines = 20000\n"
                                              '[random.psd.W]\nvalues = 1\nload = "load.npy"\n'
                                              '[shock]\nsignal = "q3000"\npulse = "half-sine"\n'
                                              "amplitude = 1\nduration = 0.01\nstep = 1e-4\n"
                                              "total = 1\n")
    env = {"RESONANT_MEMORY": "64M"}
    code, _, err = run_limited(["simulate", path, "--duration", "10"], env=env)
    assert code == 3 and "dense M, C and K of 3000 coordinates" in err, err
    code, _, err = run_limited(["random", path], env=env)
    assert code == 3 and "x 3000 coordinates" in err and "above the budget" in err, err
    code, _, err = run_limited(["srs", path, "--largest"], env=env)
    assert code == 3 and "3000 x 3000 sparse matrix" in err, err


def test_the_random_quadrature_s_error_estimate_is_chunked() -> None:
    """The Simpson/Richardson estimate of every pair of lines made six arrays of the whole
    grid's densities at once (a 3,168-DOF chain's ``random --json`` peaked at 2.3 GB with
    0.4 GB of densities): it now takes the pairs a chunk at a time, its temporaries bounded
    by ``resonant.memory.CHUNK_BYTES`` (32 MiB) whatever the grid."""
    import tracemalloc

    from resonant.analyses.random_response import _Quadrature, _refine
    from resonant.deadline import NO_DEADLINE

    responses = 400

    def evaluate(f: np.ndarray) -> np.ndarray:   # smooth densities: no refinement round
        return np.outer(1 / (1 + f), np.ones(responses))

    quad = _Quadrature(evaluate, np.linspace(1, 100, 40_001), responses)
    densities = quad.S.nbytes   # 256 MB of grid and middles
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        m0, relative, converged = _refine(quad, 1e-6, NO_DEADLINE)
        extra = tracemalloc.get_traced_memory()[1] - before
    finally:
        tracemalloc.stop()
    assert converged
    assert m0 == pytest.approx(np.log(101 / 2), rel=1e-9)   # the integral of 1/(1 + f)
    assert extra < 0.25 * densities, (extra, densities)
