"""What the forward-error estimate costs: a sweep with it against the same sweep without.

``python benchmarks/bench_forward_error.py [--repeats 5] [--busy] [--quick]``

Every exact harmonic solve of the kernel estimates its relative forward error
(:mod:`resonant.analyses.forward_error`).  This times
``resonant.analyses.sweep.sweep(system, "w", omegas, method=...)`` twice in one run, with
the estimate (the kernel's default) and without it (the sweep's kernel called with
``forward_error=False``), alternating, one BLAS thread (threadpoolctl), and reports the
median of the ratios of pairs run back to back, per input kind:

* ``chain``: fixed-free spring-mass chains of n = 1,000 and 10,000 masses (the models of
  ``bench_sweep.py``, Rayleigh damping; tridiagonal: the banded method), 200 frequencies
  from 0.1 x the first to 1.5 x the highest natural frequency;
* ``beam``: the clamped-free Euler-Bernoulli beam of tests/test_forward_error.py, 1,000
  hand-assembled Hermite elements (n = 2,000, 1 % stiffness-proportional damping at the
  first mode), 200 frequencies up to
  its 20th natural frequency, by the banded and by the sparse method;
* ``dense``: the dense models of ``bench_sweep.py`` (non-proportional damping) of n = 100
  and 400, 200 frequencies;
* ``2-DOF``: the reference model ``examples/cart_pendulum.toml`` (its closed-form solve),
  2,000 frequencies.

``--busy`` repeats the whole table with one core kept busy by a second process
(``python -c "while True: pass"``, ended afterwards).

Examples
--------
>>> M, C, K, w = beam(4, 5)
>>> M.shape, len(w)
((8, 8), 5)
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_sweep import chain_matrices, frequencies  # noqa: E402
from common import ROOT  # noqa: E402

sys.path.insert(0, str(ROOT / "tests"))
import resonant.analyses.sweep as sweep_module  # noqa: E402
from resonant.analyses import kernel  # noqa: E402
from resonant.api import load  # noqa: E402
from resonant.system import NumericEOM, NumericHarmonic  # noqa: E402
from test_forward_error import cantilever  # noqa: E402  (the beam the tests check)


def beam(elements: int, points: int) -> tuple[Any, Any, Any, np.ndarray]:
    """(M, C, K, omegas) of the clamped-free beam of tests/test_forward_error.py (unit EI,
    rho A and length, Hermite elements, 1 % stiffness-proportional damping at the first
    mode), ``points`` frequencies from half the first natural frequency to the (up to)
    20th."""
    import scipy.linalg

    K, M, C, first = cantilever(elements)
    n = K.shape[0]
    top = min(20, n - 2)
    lam = scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True,
                            subset_by_index=[0, top - 1]) if n <= 400 else _lowest(K, M, top)
    return M, C, K, np.linspace(0.5 * first, float(np.sqrt(lam[-1])), points)


def _lowest(K: Any, M: Any, count: int) -> np.ndarray:
    import scipy.sparse.linalg as sla

    return np.sort(sla.eigsh(K.tocsc(), k=count, M=M.tocsc(), sigma=0,
                             v0=np.ones(K.shape[0]), return_eigenvectors=False))


def matrix_system(M: Any, C: Any, K: Any) -> NumericEOM:
    """The system M q'' + C q' + K q = cos(omega t) e_n (the force at the last coordinate)."""
    n = M.shape[0]
    F = np.zeros(n)
    F[-1] = 1.0
    return NumericEOM(tuple(f"q{i}" for i in range(n)), M, C, K,
                      (NumericHarmonic(1.0, F, np.zeros(n)),))


@contextlib.contextmanager
def estimate(on: bool) -> Iterator[None]:
    """The sweep's kernel with the forward-error estimate (``on``) or without it."""
    if on:
        yield
        return
    sweep_module.solve_harmonic = functools.partial(kernel.solve_harmonic,  # type: ignore
                                                    forward_error=False)
    try:
        yield
    finally:
        sweep_module.solve_harmonic = kernel.solve_harmonic


def cases(quick: bool) -> list[tuple[str, Any, str, np.ndarray]]:
    """(name, system, method, frequencies) of every input kind."""
    points = 20 if quick else 200
    out = []
    for n in ((100,) if quick else (1000, 10000)):
        M, C, K = chain_matrices(n, "chain")
        out.append((f"chain n = {n:,}", matrix_system(M, C, K), "banded",
                    frequencies(M, K, "chain", points)))
    M, C, K, w = beam(50 if quick else 1000, points)
    for method in ("banded", "sparse"):
        out.append((f"beam n = {M.shape[0]:,}", matrix_system(M, C, K), method, w))
    for n in ((20,) if quick else (100, 400)):
        M, C, K = chain_matrices(n, "dense")
        out.append((f"dense n = {n}", matrix_system(M, C, K), "dense",
                    frequencies(M, K, "dense", points)))
    pendulum = load(ROOT / "examples" / "cart_pendulum.toml").linearize()
    out.append(("2-DOF cart_pendulum", pendulum, "auto",
                np.linspace(1.0, 40.0, 10 * points)))
    return out


def timed(system: Any, method: str, w: np.ndarray, on: bool) -> tuple[float, Any]:
    with estimate(on):
        start = time.perf_counter()
        result = sweep_module.sweep(system, "omega", w, method=method, progress=False)
        return time.perf_counter() - start, result


def measure(system: Any, method: str, w: np.ndarray, repeats: int) -> dict[str, Any]:
    """Medians with and without the estimate, in pairs run back to back (after one
    warm-up each): the ratio is the median of the pairs' ratios (a shared machine's load
    changes between pairs more than within one), repeats scaled to at least 2 s a side."""
    times: dict[bool, list[float]] = {True: [], False: []}
    first = [timed(system, method, w, on)[0] for on in (True, False)]
    pairs = max(repeats, min(25, int(2.0 / max(min(first), 1e-3))))
    for _ in range(pairs):
        for on in (False, True):
            times[on].append(timed(system, method, w, on)[0])
    ratios = [a / b for a, b in zip(times[True], times[False])]
    return {"with": statistics.median(times[True]), "without": statistics.median(times[False]),
            "ratio": statistics.median(ratios), "fastest": min(times[True]) / min(times[False]),
            "pairs": pairs, "estimated": estimated(system, method, w)}


def estimated(system: Any, method: str, w: np.ndarray) -> int:
    """How many points of the sweep get the estimate (the kernel's NaN: left out)."""
    batch = system.batch("omega", w)
    counts = [int(np.isfinite(kernel.solve_harmonic(batch, h, method).forward_error).sum())
              for h in batch.harmonics]
    return max(counts)


def table(repeats: int, quick: bool) -> list[str]:
    lines = ["| input | method | frequencies | estimated | without (s) | with (s) | ratio "
             "(median of pairs) | ratio of the fastest | pairs |",
             "|:---|:---|---:|---:|---:|---:|---:|---:|---:|"]
    print("\n".join(lines), flush=True)
    for name, system, method, w in cases(quick):
        row = measure(system, method, w, repeats)
        lines.append(f"| {name} | {method} | {len(w):,} | {row['estimated']} | "
                     f"{row['without']:.4f} | {row['with']:.4f} | {row['ratio']:.3f} | "
                     f"{row['fastest']:.3f} | {row['pairs']} |")
        print(lines[-1], flush=True)
    return lines


@contextlib.contextmanager
def busy_core() -> Iterator[None]:
    """One core kept busy by a second process while the block runs."""
    child = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.5)
        yield
    finally:
        child.kill()
        child.wait()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="pairs at least")
    parser.add_argument("--busy", action="store_true", help="also with one core busy")
    parser.add_argument("--quick", action="store_true", help="tiny sizes")
    args = parser.parse_args(argv)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(1):
        print("quiet machine:", flush=True)
        table(args.repeats, args.quick)
        if args.busy:
            print("\none core busy:", flush=True)
            with busy_core():
                table(args.repeats, args.quick)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
