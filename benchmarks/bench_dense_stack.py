"""The dense sweep's stack of dynamic matrices: how many it builds at once.

``python benchmarks/bench_dense_stack.py [--sizes 100 300 1000] [--repeats 5] [--busy]``

The dense method builds K - w^2 M + i w C for a chunk of frequencies and solves the chunk
with one batched LAPACK call; building the stack is memory-bound, so its size decides
whether it stays in a core's cache.  This times ``resonant.analyses.sweep.sweep`` of the
dense models of ``bench_sweep.py`` (fully coupled random M and K, non-proportional
damping; 200 frequencies, 40 at n = 1,000) with the stack limited to each of the sizes
given (``resonant.analyses.kernel.DENSE_STACK_BYTES``) against the hand-written loop of
one ``numpy.linalg.solve`` per frequency, alternating in one run, one BLAS thread
(threadpoolctl); the ratios are of the fastest of ``--repeats`` runs.  The results are
the same to the last bit whatever the stack's size (checked).  ``--busy`` keeps one core
busy with a second process meanwhile (ended afterwards).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_sweep import chain_matrices, dense_loop, frequencies, write_model  # noqa: E402


def run(n: int, stacks: list[int], repeats: int) -> tuple[float, dict[int, float]]:
    """(the loop's time, stack MiB -> resonant's time over the loop's)."""
    import resonant.analyses.kernel as kernel
    from resonant.analyses.sweep import sweep
    from resonant.api import load

    M, C, K = chain_matrices(n, "dense")
    w = frequencies(M, K, "dense", 200 if n < 1000 else 40)
    with tempfile.TemporaryDirectory() as directory:
        model = load(write_model(Path(directory), M, C, K, "dense"))
    system, names = model.linearize(), list(model.coordinates)
    times: dict[str, list[float]] = {"loop": []}
    results = {}
    for _ in range(repeats):
        start = time.perf_counter()
        dense_loop(M, C, K, w)
        times["loop"].append(time.perf_counter() - start)
        for mib in stacks:
            kernel.DENSE_STACK_BYTES = mib * 2**20
            start = time.perf_counter()
            result = sweep(system, "w", w, names=names, progress=False)
            times.setdefault(str(mib), []).append(time.perf_counter() - start)
            results[mib] = np.array([result.amplitudes[k] for k in names])
    first = results[stacks[0]]
    if not all(np.array_equal(first, r) for r in results.values()):
        raise SystemExit(f"n = {n}: the stack's size changed the results")
    loop = min(times["loop"])
    return loop, {mib: min(times[str(mib)]) / loop for mib in stacks}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 300, 1000])
    parser.add_argument("--stacks", type=int, nargs="+", default=[64, 2],
                        help="stack sizes to compare, MiB")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--busy", action="store_true")
    args = parser.parse_args(argv)
    from threadpoolctl import threadpool_limits

    busy = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if args.busy else None
    try:
        print("| n | zgesv loop (s) | " + " | ".join(f"stack {m} MiB / loop" for m in args.stacks)
              + " |")
        print("|---:|---:|" + "---:|" * len(args.stacks))
        with threadpool_limits(1):
            for n in args.sizes:
                loop, ratios = run(n, args.stacks, args.repeats)
                print(f"| {n} | {loop:.3f} | " + " | ".join(f"{ratios[m]:.2f}x"
                                                         for m in args.stacks) + " |",
                      flush=True)
    finally:
        if busy is not None:
            busy.terminate()
            busy.wait()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
