"""Every corpus structure (benchmarks/corpus.py) through the large-model linear paths.

    python benchmarks/bench_corpus.py [--size 10000] [--points 1000] [--only grid,plate]

Per structure: the method ``auto`` chooses and its time; a hand-written scipy loop of
SuperLU (its default COLAMD ordering, partial pivoting: what a user would write) and
its time; the ratio; the exact ``sparse`` method against a hand-written loop of the
*same* factorization (the symmetric scaling and options of
resonant.analyses.reduced.ScaledLU); the reduced model's estimated error against its
true error (measured against the LU loop's responses).  Prints a Markdown table.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import corpus  # noqa: E402

from resonant.analyses import kernel  # noqa: E402
from resonant.analyses.reduced import (  # noqa: E402
    ScaledLU,
    reduced_response,
    sparse_lu_options,
    symmetric_scale,
)
from resonant.system import NumericEOM, NumericHarmonic  # noqa: E402


def batch_of(s, w):
    eom = NumericEOM(tuple(f"q{i + 1}" for i in range(s.n)), s.M, s.C, s.K,
                     (NumericHarmonic(1.0, np.zeros(s.n), s.b.real.copy()),))
    return eom.batch("omega", w)


def lu_loop(s, w, same: bool):
    """The hand-written loop: splu per frequency (``same``: the kernel's factorization)."""
    from scipy.sparse.linalg import splu

    K, M, C = s.K.tocsc(), s.M.tocsc(), s.C.tocsc()
    options = sparse_lu_options(abs(K) + abs(M) + abs(C)) if same else {}
    Z = np.empty((len(w), s.n), dtype=complex)
    start = time.perf_counter()
    for i, wi in enumerate(w):
        A = (K - wi * wi * M + 1j * wi * C).tocsc()
        if same:
            d = symmetric_scale(np.abs(K.diagonal()) + wi * wi * np.abs(M.diagonal())
                                + wi * np.abs(C.diagonal()))
            Z[i] = ScaledLU(A, d, **options).solve(s.b)
        else:
            Z[i] = splu(A).solve(s.b)
    return Z, time.perf_counter() - start


def run_case(name: str, size: int, points: int) -> dict:
    s = corpus.build(name, size)
    w = np.linspace(*s.band, points)
    batch = batch_of(s, w)
    start = time.perf_counter()
    auto = kernel.solve_harmonic(batch, batch.harmonics[0], "auto")
    t_auto = time.perf_counter() - start
    ref, t_loop = lu_loop(s, w, same=False)
    start = time.perf_counter()
    kernel.solve_harmonic(batch, batch.harmonics[0], "sparse")
    t_sparse = time.perf_counter() - start
    _, t_same = lu_loop(s, w, same=True)
    red = reduced_response(s.M, s.C, s.K, s.b, w)
    true = np.linalg.norm(red.Z - ref, axis=1) / np.linalg.norm(ref, axis=1)
    return {"name": name, "n": s.n, "points": points, "method": auto.method,
            "auto": t_auto, "loop": t_loop, "ratio": t_auto / t_loop,
            "sparse": t_sparse, "same": t_same, "sparse_ratio": t_sparse / t_same,
            "estimated": red.estimated_error, "true": float(np.nanmax(true)),
            "converged": red.converged}


def table(rows: list[dict]) -> str:
    lines = ["| structure | n | method (auto) | auto s | LU loop s | auto / loop | sparse s | "
             "same-LU loop s | sparse / same | reduced estimated | reduced true |",
             "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows:
        lines.append(f"| {r['name']} | {r['n']} | {r['method']} | {r['auto']:.3g} | "
                     f"{r['loop']:.3g} | {r['ratio']:.3g} | {r['sparse']:.3g} | "
                     f"{r['same']:.3g} | {r['sparse_ratio']:.2f} | {r['estimated']:.2g} | "
                     f"{r['true']:.2g} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=10_000)
    parser.add_argument("--points", type=int, default=1000)
    parser.add_argument("--only", default="", help="comma-separated structure names")
    args = parser.parse_args(argv)
    names = [n for n in args.only.split(",") if n] or list(corpus.BUILDERS)
    rows = []
    for name in names:
        rows.append(run_case(name, args.size, args.points))
        print(table(rows[-1:]).splitlines()[-1], file=sys.stderr, flush=True)
    print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
