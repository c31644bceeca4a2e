"""Every corpus structure (benchmarks/corpus.py) through the large-model linear paths.

    python benchmarks/bench_corpus.py [--size 10000] [--points 1000] [--only grid,plate]
                                      [--loop-points K]

Per structure: the method ``auto`` chooses and its time; a hand-written scipy loop of
SuperLU (its default COLAMD ordering, partial pivoting: what a user would write) and
its time; the ratio; the exact ``sparse`` method against a hand-written loop of the
*same* factorization (the symmetric scaling and options of
resonant.analyses.reduced.ScaledLU); where the exact method would be ``banded``, that
method against a hand-written loop of LAPACK's gtsv/gbsv on band storage (reverse
Cuthill-McKee order where narrower); up to 2,000 coordinates the ``dense`` method against
numpy.linalg.solve in a loop; the reduced model's estimated error against its
true error (measured against the LU loop's responses).  Prints a Markdown table.

With ``--loop-points K`` (for the largest sizes, where a loop over every frequency would
take hours) the hand-written loops run at K of the frequencies spread over the band: their
times are scaled to all of them (marked ``*``) and the true error is measured there.
"""

from __future__ import annotations

import argparse
import math
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


#: the dense method is timed (against numpy.linalg.solve in a loop) up to this size
DENSE_SIZE = 2000


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


def band_loop(s, w):
    """The hand-written loop of the ``banded`` method's factorization: LAPACK gtsv
    (tridiagonal) or gbsv on band storage, the solution stored as the LU loop's."""
    from scipy.linalg import lapack

    from scipy.sparse.csgraph import reverse_cuthill_mckee

    start = time.perf_counter()
    pattern = (abs(s.K) + abs(s.M) + abs(s.C)).tocsr()
    order = reverse_cuthill_mckee(pattern + pattern.T, symmetric_mode=True)
    if sum(bandwidths(pattern[order][:, order])) >= sum(bandwidths(pattern)):
        order = np.arange(s.n)
    lower, upper = bandwidths(pattern[order][:, order])
    rows = 2 * lower + upper + 1

    def storage(a):
        a = a.tocsr()[order][:, order].tocoo()
        ab = np.zeros((rows, s.n))
        np.add.at(ab, (lower + upper + a.row - a.col, a.col), a.data)
        return ab

    Kb, Mb, Cb = storage(s.K), storage(s.M), storage(s.C)
    b = s.b[order].astype(complex)
    back = np.argsort(order)
    Z = np.empty((len(w), s.n), dtype=complex)
    for i, wi in enumerate(w):
        ab = Kb - wi * wi * Mb + 1j * wi * Cb
        if lower == upper == 1:
            Z[i] = lapack.zgtsv(ab[3, :-1], ab[2], ab[1, 1:], b)[3][back]
        else:
            Z[i] = lapack.zgbsv(lower, upper, ab, b, overwrite_ab=1)[2][back]
    return Z, time.perf_counter() - start


def dense_loop(s, w):
    """The hand-written loop of the ``dense`` method's factorization: LAPACK's LU of the
    dense complex matrix per frequency (numpy.linalg.solve)."""
    K, M, C = s.K.toarray(), s.M.toarray(), s.C.toarray()
    Z = np.empty((len(w), s.n), dtype=complex)
    start = time.perf_counter()
    for i, wi in enumerate(w):
        Z[i] = np.linalg.solve(K - wi * wi * M + 1j * wi * C, s.b)
    return Z, time.perf_counter() - start


def bandwidths(a):
    """(sub-, superdiagonals) of a sparse matrix."""
    a = a.tocoo()
    return int((a.row - a.col).max()), int((a.col - a.row).max())


def run_case(name: str, size: int, points: int, loop_points: int | None = None) -> dict:
    s = corpus.build(name, size)
    w = np.linspace(*s.band, points)
    batch = batch_of(s, w)
    start = time.perf_counter()
    auto = kernel.solve_harmonic(batch, batch.harmonics[0], "auto")
    t_auto = time.perf_counter() - start
    some = np.unique(np.linspace(0, points - 1, loop_points or points).round().astype(int))
    scale = points / some.size
    ref, t_loop = lu_loop(s, w[some], same=False)
    _, t_same = lu_loop(s, w[some], same=True)
    t_sparse = t_banded = t_band_loop = math.nan
    if scale == 1:  # the exact methods over the whole band (skipped when scaled)
        start = time.perf_counter()
        kernel.solve_harmonic(batch, batch.harmonics[0], "sparse")
        t_sparse = time.perf_counter() - start
        if kernel.choose_direct(batch, w) == "banded":
            start = time.perf_counter()
            kernel.solve_harmonic(batch, batch.harmonics[0], "banded")
            t_banded = time.perf_counter() - start
            _, t_band_loop = band_loop(s, w)
    t_dense = t_dense_loop = math.nan
    if scale == 1 and s.n <= DENSE_SIZE:
        start = time.perf_counter()
        kernel.solve_harmonic(batch, batch.harmonics[0], "dense")
        t_dense = time.perf_counter() - start
        _, t_dense_loop = dense_loop(s, w)
    red = reduced_response(s.M, s.C, s.K, s.b, w)
    Z = red.Z[some]
    true = np.linalg.norm(Z - ref, axis=1) / np.linalg.norm(ref, axis=1)
    return {"name": name, "n": s.n, "points": points, "method": auto.method,
            "auto": t_auto, "loop": t_loop * scale, "ratio": t_auto / (t_loop * scale),
            "sparse": t_sparse, "same": t_same * scale,
            "sparse_ratio": t_sparse / (t_same * scale), "scaled": scale != 1,
            "banded": t_banded, "band_loop": t_band_loop,
            "banded_ratio": t_banded / t_band_loop,
            "dense": t_dense, "dense_loop": t_dense_loop, "dense_ratio": t_dense / t_dense_loop,
            "estimated": red.estimated_error, "true": float(np.nanmax(true)),
            "converged": red.converged}


def table(rows: list[dict]) -> str:
    lines = ["| structure | n | method (auto) | auto s | LU loop s | auto / loop | sparse s | "
             "same-LU loop s | sparse / same | banded s | band loop s | banded / loop | "
             "dense s | dense loop s | dense / loop | reduced estimated | reduced true |",
             "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
             "---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows:
        star = "*" if r.get("scaled") else ""
        lines.append(f"| {r['name']} | {r['n']} | {r['method']} | {r['auto']:.3g} | "
                     f"{r['loop']:.3g}{star} | {r['ratio']:.3g}{star} | {r['sparse']:.3g} | "
                     f"{r['same']:.3g}{star} | {r['sparse_ratio']:.2f} | "
                     f"{r['banded']:.3g} | {r['band_loop']:.3g} | {r['banded_ratio']:.2f} | "
                     f"{r['dense']:.3g} | {r['dense_loop']:.3g} | {r['dense_ratio']:.2f} | "
                     f"{r['estimated']:.2g} | {r['true']:.2g} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=10_000)
    parser.add_argument("--points", type=int, default=1000)
    parser.add_argument("--only", default="", help="comma-separated structure names")
    parser.add_argument("--loop-points", type=int, default=None,
                        help="time the hand-written loops at this many frequencies only")
    args = parser.parse_args(argv)
    names = [n for n in args.only.split(",") if n] or list(corpus.BUILDERS)
    rows = []
    for name in names:
        rows.append(run_case(name, args.size, args.points, args.loop_points))
        print(table(rows[-1:]).splitlines()[-1], file=sys.stderr, flush=True)
    print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
