"""Matrix Market reader: resonant's safe reader against scipy's, per million entries.

Usage::

    python benchmarks/bench_mtx.py [--entries 1000000] [--rounds 7]

Writes random coordinate files (general, and symmetric) and a dense array file with
``scipy.io.mmwrite``, then reads each with resonant's reader
(``resonant.model.matrix_files``: banner and size line checked against the limits first,
every data line checked, a CSR matrix out) and with ``scipy.io.mmread(...).tocsr()`` (what a
user would call; scipy's C++ reader, multithreaded, which crashed on hostile files:
docs/fuzzing.md), alternating, ``--rounds`` times each.  Also resonant without pyarrow
(numpy's reader for the data lines).  Prints a markdown table: the best and the median
time, the ratio of the best times and the median of the per-round ratios (the machine may
be shared), the ratio of the least CPU times (all threads; less sensitive to the load of a
shared machine than the wall-clock time), and the load average.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from unittest import mock

import numpy as np
import scipy.io
import scipy.sparse as sp

from resonant.model import matrix_files


def write_cases(folder: Path, entries: int) -> dict[str, Path]:
    rng = np.random.default_rng(0)
    n = max(1000, entries // 5)
    general = sp.coo_matrix((rng.standard_normal(entries),
                             (rng.integers(0, n, entries), rng.integers(0, n, entries))),
                            shape=(n, n))
    lower = sp.tril(general).tocoo()
    symmetric = (lower + lower.T).tocoo()
    dense = rng.standard_normal((int(entries ** 0.5), int(entries ** 0.5)))
    cases = {"coordinate general": general, "coordinate symmetric": symmetric,
             "array (dense)": dense}
    paths = {}
    for i, (name, matrix) in enumerate(cases.items()):
        paths[name] = folder / f"case{i}.mtx"
        scipy.io.mmwrite(paths[name], matrix, symmetry="symmetric" if "symm" in name else None)
    return paths


def timed(read: Callable[[], object]) -> tuple[float, float]:
    """Wall-clock and CPU time (all threads) of one read."""
    start, cpu = time.perf_counter(), time.process_time()
    read()
    return time.perf_counter() - start, time.process_time() - cpu


def ours(path: Path) -> object:
    with open(path, "rb") as handle:
        return matrix_files._read_mtx(handle, path.stat().st_size)


def ours_without_pyarrow(path: Path) -> object:
    with mock.patch.object(matrix_files, "_mtx_with_arrow", lambda *args: None):
        return ours(path)


def theirs(path: Path) -> object:
    matrix = scipy.io.mmread(path)
    return matrix.tocsr() if sp.issparse(matrix) else matrix


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--entries", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    print(f"Matrix Market files of about {args.entries:,} stored entries, {args.rounds} "
          "rounds alternating (numpy only: 2 rounds); times best / median\n")
    print("| file | resonant | resonant without pyarrow | scipy mmread + tocsr | "
          "ratio, best | ratio, median of rounds | CPU-time ratio | without pyarrow, ratio | "
          "load |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name, path in write_cases(Path(folder), args.entries).items():
            ours(path), theirs(path)  # imports and first touches outside the timing
            fast, reference = [], []
            for _ in range(args.rounds):
                fast.append(timed(lambda path=path: ours(path)))
                reference.append(timed(lambda path=path: theirs(path)))
            plain = min(timed(lambda path=path: ours_without_pyarrow(path))[0]
                        for _ in range(2))
            walls, cpus = ([t[k] for t in fast] for k in (0, 1))
            walls_ref, cpus_ref = ([t[k] for t in reference] for k in (0, 1))
            ratios = [f / r for f, r in zip(walls, walls_ref, strict=True)]
            print(f"| {name} | {min(walls):.3f} / {statistics.median(walls):.3f} s | "
                  f"{plain:.3f} s | {min(walls_ref):.3f} / {statistics.median(walls_ref):.3f} s"
                  f" | {min(walls) / min(walls_ref):.2f}x | {statistics.median(ratios):.2f}x | "
                  f"{min(cpus) / min(cpus_ref):.2f}x | {plain / min(walls_ref):.2f}x | "
                  f"{os.getloadavg()[0]:.1f} |")

if __name__ == "__main__":
    main()
