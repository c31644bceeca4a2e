"""Benchmark 2 (frequency sweep) and 4 (memory) against hand-written solves.

Three families of models, all loaded at the free end by Q = cos(w t) e_n:

``chain``
    fixed-free spring-mass chain, masses 1, springs 1e4, Rayleigh damping
    C = 0.1 M + 1e-4 K (tridiagonal);
``nonprop``
    the same with one extra damper (c = 10) between DOF 1 and 2, so the
    damping is not proportional (still tridiagonal);
``dense``
    a fully coupled model: K = chain K + a dense positive semidefinite
    coupling, M = I + a dense one, C = 0.1 M + 1e-4 K + the extra damper
    (not proportional, so no modal shortcut exists: every frequency needs
    a dense complex LU).

Frequencies: ``n_f`` log-spaced from 0.1 x the first to 1.5 x the highest
undamped natural frequency.  resonant's side is
``resonant.analyses.sweep.sweep(model, "w", omegas)`` on a ``[matrices]`` model file
whose M, C, K are ``.mtx`` (chains) or ``.npy`` (dense) files in a temporary
directory and whose harmonic has ``omega = "w"``.  The complex response
z = L - i N is rebuilt from the returned amplitude X and phase delta
(L = X sin delta, N = X cos delta) and compared, per frequency, normwise:
max_j |z_j - z_ref,j| / max_j |z_ref,j|, then the maximum over frequencies.

Examples
--------
>>> M, C, K = chain_matrices(3, "chain")
>>> K.toarray().tolist()
[[20000.0, -10000.0, 0.0], [-10000.0, 20000.0, -10000.0], [0.0, -10000.0, 10000.0]]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import extrapolate, fit_power_law, median_time  # noqa: E402

SPRING = 1e4
EXTRA_DAMPER = 10.0
VARIANTS = ("chain", "nonprop", "dense")


def chain_matrices(n: int, variant: str = "chain", seed: int = 12345) -> tuple[Any, Any, Any]:
    """(M, C, K) of one benchmark model: scipy.sparse CSR for chains, ndarrays for dense."""
    import scipy.sparse as sp

    if variant not in VARIANTS:
        raise ValueError(f"unknown variant {variant!r}; use one of {VARIANTS}")
    main = np.full(n, 2 * SPRING)
    main[-1] = SPRING                       # the free end has one spring
    off = np.full(n - 1, -SPRING)
    K = sp.diags([off, main, off], [-1, 0, 1], format="csr")
    M = sp.identity(n, format="csr")
    damper = sp.csr_matrix((n, n))
    if variant in ("nonprop", "dense") and n >= 2:
        damper = sp.csr_matrix(([EXTRA_DAMPER, -EXTRA_DAMPER, -EXTRA_DAMPER, EXTRA_DAMPER],
                                ([0, 0, 1, 1], [0, 1, 0, 1])), shape=(n, n))
    if variant == "dense":
        rng = np.random.default_rng(seed)
        a = rng.standard_normal((n, n))
        b = rng.standard_normal((n, n))
        K = K.toarray() + 0.1 * SPRING * (a @ a.T) / n
        M = np.eye(n) + 0.1 * (b @ b.T) / n
        return M, 0.1 * M + 1e-4 * K + damper.toarray(), K
    return M, (0.1 * M + 1e-4 * K + damper).tocsr(), K


def natural_range(M: Any, K: Any, variant: str) -> tuple[float, float]:
    """The lowest and highest undamped natural frequency (rad/s)."""
    import scipy.linalg

    if variant == "dense":
        lam = scipy.linalg.eigh(K, M, eigvals_only=True)
    else:  # M = I and K tridiagonal
        lam = scipy.linalg.eigh_tridiagonal(K.diagonal(), K.diagonal(1), eigvals_only=True)
    return math.sqrt(lam[0]), math.sqrt(lam[-1])


def frequencies(M: Any, K: Any, variant: str, n_f: int) -> np.ndarray:
    w1, wmax = natural_range(M, K, variant)
    return np.geomspace(0.1 * w1, 1.5 * wmax, n_f)


def write_model(directory: Path, M: Any, C: Any, K: Any, variant: str) -> Path:
    """A ``[matrices]`` model file; the force acts at the last DOF, omega = parameter w."""
    import scipy.io

    n = M.shape[0]
    names = {}
    for key, a in (("M", M), ("C", C), ("K", K)):
        if variant == "dense":
            names[key] = f"{key}.npy"
            np.save(directory / names[key], a)
        else:
            names[key] = f"{key}.mtx"
            scipy.io.mmwrite(str(directory / names[key]), a)
    force = ", ".join(["0"] * (n - 1) + ["1"])
    path = directory / f"{variant}_{n}.toml"
    path.write_text(
        f'title = "{variant} benchmark model, n = {n}"\n\n[parameters]\nw = 1\n\n'
        f'[matrices]\nM = "{names["M"]}"\nC = "{names["C"]}"\nK = "{names["K"]}"\n\n'
        f'[[harmonic]]\nomega = "w"\nF_C = [{force}]\n', encoding="utf-8")
    return path


def complex_from_sweep(result: Any, n: int) -> np.ndarray:
    """z = L - i N, shape (n_f, n), from the sweep's amplitudes X and phases delta."""
    names = list(result.coordinates)[:n]
    X = np.stack([np.asarray(result.amplitudes[q]) for q in names], axis=1)
    delta = np.nan_to_num(np.stack([np.asarray(result.phases[q]) for q in names], axis=1))
    return X * np.sin(delta) - 1j * X * np.cos(delta)


def banded_solve(M: Any, C: Any, K: Any, omegas: np.ndarray) -> np.ndarray:
    """The best hand-written solve for a tridiagonal chain: LAPACK via solve_banded."""
    import scipy.linalg

    n = M.shape[0]
    diags = {}
    for key, a in (("M", M), ("C", C), ("K", K)):
        diags[key] = (a.diagonal(1), a.diagonal(0), a.diagonal(-1))
    rhs = np.zeros(n, dtype=complex)
    rhs[-1] = 1.0
    out = np.empty((len(omegas), n), dtype=complex)
    ab = np.zeros((3, n), dtype=complex)
    for i, w in enumerate(omegas):
        for row, (m, c, k) in enumerate(zip(diags["M"], diags["C"], diags["K"])):
            sl = slice(1, None) if row == 0 else (slice(None) if row == 1 else slice(None, -1))
            ab[row, sl] = k - w * w * m + 1j * w * c
        out[i] = scipy.linalg.solve_banded((1, 1), ab, rhs, overwrite_ab=False,
                                           check_finite=False)
    return out


def dense_loop(M: Any, C: Any, K: Any, omegas: np.ndarray) -> np.ndarray:
    """The naive alternative: one numpy dense complex solve per frequency."""
    Md, Cd, Kd = (a.toarray() if hasattr(a, "toarray") else np.asarray(a) for a in (M, C, K))
    rhs = np.zeros(Md.shape[0], dtype=complex)
    rhs[-1] = 1.0
    return np.array([np.linalg.solve(Kd - w * w * Md + 1j * w * Cd, rhs) for w in omegas])


def dense_loop_timed(M: Any, C: Any, K: Any, omegas: np.ndarray, budget: float
                     ) -> tuple[np.ndarray, np.ndarray, float]:
    """The dense loop over as many frequencies as fit in ``budget`` seconds (at least 3).

    The frequencies are visited in a spread-out order (every k-th first), so
    a loop cut short still samples the whole range; its cost per frequency
    does not depend on the frequency.  Returns (indices, z, seconds per frequency).
    """
    n_f = len(omegas)
    order = list(dict.fromkeys(i for stride in (max(1, n_f // 8), max(1, n_f // 64), 1)
                               for i in range(0, n_f, stride)))
    Md, Cd, Kd = (a.toarray() if hasattr(a, "toarray") else np.asarray(a) for a in (M, C, K))
    rhs = np.zeros(Md.shape[0], dtype=complex)
    rhs[-1] = 1.0
    done, rows = [], []
    start = time.perf_counter()
    for i in order:
        w = omegas[i]
        rows.append(np.linalg.solve(Kd - w * w * Md + 1j * w * Cd, rhs))
        done.append(i)
        if len(done) >= 3 and time.perf_counter() - start > budget:
            break
    elapsed = time.perf_counter() - start
    idx = np.array(done)
    sort = np.argsort(idx)
    return idx[sort], np.array(rows)[sort], elapsed / len(done)


def agreement(z: np.ndarray, ref: np.ndarray) -> float:
    """max over frequencies of max_j |z_j - ref_j| / max_j |ref_j|."""
    scale = np.max(np.abs(ref), axis=1)
    return float(np.max(np.max(np.abs(z - ref), axis=1) / scale))


def matmul_flop_rate(size: int = 2000, repeats: int = 3) -> float:
    """The machine's dense float64 matmul rate (FLOP/s), median of repeats."""
    rng = np.random.default_rng(0)
    a, b = rng.standard_normal((size, size)), rng.standard_normal((size, size))
    a @ b  # warm up the BLAS threads
    t, _, _ = median_time(lambda: a @ b, repeats=repeats, min_repeats_time=1e9)
    return 2.0 * size ** 3 / t


def lu_flops(n: int, n_f: int) -> float:
    """Nominal real FLOPs of a complex dense sweep: one zgetrf (8/3 n^3) + solve per frequency."""
    return n_f * (8.0 / 3.0 * n ** 3 + 8.0 * n ** 2)


def resonant_sweep(path: Path, omegas: np.ndarray, repeats: int
                   ) -> tuple[float | None, np.ndarray | None, str]:
    """(median time, z, method or the reason it is not available)."""
    try:
        import resonant.analyses.sweep as rsweep
        from resonant.api import load
    except ImportError as exc:
        return None, None, f"not available ({exc})"
    model = load(path)
    n = model.matrices.M.shape[0] if hasattr(model.matrices.M, "shape") else len(
        model.coordinates)
    # Every DOF, as the issue asks (by default a large model reports only the loaded ones).
    names = list(model.coordinates)
    t, result, _ = median_time(
        lambda: rsweep.sweep(model.linearize(), "w", omegas, names=names, progress=False), repeats=repeats)
    return t, complex_from_sweep(result, n), result.method


def run_case(variant: str, n: int, n_f: int, *, repeats: int = 3, dense_budget: float = 30.0,
             dense_fit: tuple[float, float] | None = None, workdir: Path | None = None
             ) -> dict[str, Any]:
    """One (variant, n, n_f) case: every side timed, agreement checked."""
    M, C, K = chain_matrices(n, variant)
    omegas = frequencies(M, K, variant, n_f)
    row: dict[str, Any] = {"variant": variant, "n": n, "n_f": n_f}
    with tempfile.TemporaryDirectory(dir=workdir) as tmp:
        path = write_model(Path(tmp), M, C, K, variant)
        try:
            t_res, z_res, method = resonant_sweep(path, omegas, repeats)
        except Exception as exc:  # report, never crash the whole run
            t_res, z_res, method = None, None, f"failed: {type(exc).__name__}: {exc}"[:200]
    row.update(resonant=t_res, method=method)
    # (b) the best hand-written direct solve for the structure
    if variant == "dense":
        t_best, z_best, _ = median_time(lambda: dense_loop(M, C, K, omegas), repeats=repeats,
                                        min_repeats_time=dense_budget / 4)
        row.update(best=t_best, best_name="numpy.linalg.solve per frequency (LAPACK zgesv)")
        z_loop, t_loop, loop_subset = z_best, t_best, None
    else:
        t_best, z_best, _ = median_time(lambda: banded_solve(M, C, K, omegas), repeats=repeats)
        row.update(best=t_best, best_name="scipy.linalg.solve_banded per frequency")
        # (a) the per-frequency numpy dense loop, on a subset of frequencies when the
        # whole loop would not fit the budget (the cost is the same at every frequency)
        z_loop = t_loop = loop_subset = None
        if n <= 3000:
            idx, z_loop, per_freq = dense_loop_timed(M, C, K, omegas, dense_budget)
            t_loop = per_freq * n_f
            loop_subset = None if len(idx) == n_f else int(len(idx))
            row["loop_idx"] = idx
        elif dense_fit is not None:
            t_loop = extrapolate(dense_fit, n) * n_f
            loop_subset = 0  # power-law extrapolation in n, nothing run
    row.update(loop=t_loop, loop_subset=loop_subset,
               loop_per_freq=None if t_loop is None else t_loop / n_f)
    if z_res is not None:
        row["agreement_best"] = agreement(z_res, z_best)
        if z_loop is not None and variant != "dense":
            row["agreement_loop"] = agreement(z_res[row["loop_idx"]], z_loop)
    if z_loop is not None and variant != "dense":
        row["agreement_best_vs_loop"] = agreement(z_best[row["loop_idx"]], z_loop)
    row.pop("loop_idx", None)
    if variant == "dense":
        row["flops"] = lu_flops(n, n_f)
    return row


def dense_loop_fit(rows: list[dict[str, Any]]) -> tuple[float, float] | None:
    """Power law of the dense loop's time per frequency against n (measured rows only)."""
    pts = [(r["n"], r["loop_per_freq"]) for r in rows
           if r.get("loop_per_freq") and r.get("loop_subset") != 0 and r["n"] >= 300]
    if len(pts) < 2:
        pts = [(r["n"], r["loop_per_freq"]) for r in rows
               if r.get("loop_per_freq") and r.get("loop_subset") != 0]
    if len(pts) < 2:
        return None
    return fit_power_law([p[0] for p in pts], [p[1] for p in pts])


def memory_child(n: int, n_f: int, variant: str, do_sweep: bool) -> None:
    """Child process of the memory benchmark: build, load and (optionally) sweep."""
    import resonant.analyses.sweep as rsweep
    from resonant.api import load

    M, C, K = chain_matrices(n, variant)
    omegas = frequencies(M, K, variant, n_f)
    with tempfile.TemporaryDirectory() as tmp:
        model = load(write_model(Path(tmp), M, C, K, variant))
        result = rsweep.sweep(model.linearize(), "w", omegas, names=list(model.coordinates),
                              progress=False) if do_sweep else None
        reported = len(result.amplitudes) if result is not None else 0
    import resource

    print(json.dumps({"method": getattr(result, "method", None), "reported": reported,
                      "self_maxrss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
                      / 1024.0}))


#: a small launcher: runs the command, then prints getrusage(RUSAGE_CHILDREN).ru_maxrss.
#: The benchmark's own (large) process must not be the parent: a child's high-water mark
#: can include the image of the process it was forked from.
_LAUNCHER = ("import resource, subprocess, sys\n"
             "proc = subprocess.run(sys.argv[1:], capture_output=True, text=True)\n"
             "sys.stderr.write(proc.stderr)\n"
             "print(proc.stdout.strip().splitlines()[-1] if proc.returncode == 0 else '')\n"
             "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
             "sys.exit(proc.returncode)\n")


def peak_rss(n: int, n_f: int, variant: str = "chain", do_sweep: bool = True
             ) -> tuple[float, dict[str, Any]]:
    """Peak RSS (MB) of a fresh process that runs the sweep, and the child's report.

    A minimal launcher process starts the child and reads
    ``resource.getrusage(RUSAGE_CHILDREN).ru_maxrss``.
    """
    import subprocess

    from common import environment

    cmd = [sys.executable, "-c", _LAUNCHER, sys.executable, __file__, "--memory-child",
           str(n), str(n_f), variant] + ([] if do_sweep else ["--no-sweep"])
    proc = subprocess.run(cmd, capture_output=True, text=True, env=environment())
    if proc.returncode != 0:
        raise RuntimeError(f"memory child failed:\n{proc.stderr[-2000:]}")
    report_line, maxrss = proc.stdout.strip().splitlines()[-2:]
    return int(maxrss) / 1024.0, json.loads(report_line)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--memory-child", nargs=3, metavar=("N", "N_F", "VARIANT"))
    parser.add_argument("--no-sweep", action="store_true")
    parser.add_argument("--case", nargs=3, metavar=("VARIANT", "N", "N_F"))
    args = parser.parse_args()
    if args.memory_child:
        n, n_f, variant = args.memory_child
        memory_child(int(n), int(n_f), variant, not args.no_sweep)
    elif args.case:
        variant, n, n_f = args.case
        print(run_case(variant, int(n), int(n_f)))
