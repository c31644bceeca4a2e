"""Matrix Market reader: resonant's safe reader against scipy's, per million entries.

Usage::

    python benchmarks/bench_mtx.py [--entries 1000000]

Writes random coordinate files (general, and symmetric) and a dense array file with
``scipy.io.mmwrite``, then reads each with resonant's reader
(``resonant.model.matrix_files``: banner and size line checked against the limits first,
every data line checked, a CSR matrix out) and with ``scipy.io.mmread(...).tocsr()`` (what a
user would call; scipy's C++ reader, multithreaded, which crashed on hostile files:
docs/fuzzing.md), alternating, best of 5 each.  Also the numpy-only path (pandas not
used).  Prints a markdown table with the ratios.
"""

from __future__ import annotations

import argparse
import tempfile
import time
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


def best(read, repeats: int = 5) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        read()
        times.append(time.perf_counter() - start)
    return min(times)


def ours(path: Path) -> object:
    with open(path, "rb") as handle:
        return matrix_files._read_mtx(handle, path.stat().st_size)


def theirs(path: Path) -> object:
    matrix = scipy.io.mmread(path)
    return matrix.tocsr() if sp.issparse(matrix) else matrix


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--entries", type=int, default=1_000_000)
    entries = parser.parse_args().entries
    print(f"Matrix Market files of about {entries:,} stored entries, best of 5\n")
    print("| file | resonant | resonant, numpy only | scipy mmread + tocsr | ratio | "
          "ratio, numpy only |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name, path in write_cases(Path(folder), entries).items():
            ours(path)  # pandas imported once, outside the timing
            fast, reference = best(lambda: ours(path)), best(lambda: theirs(path))
            with mock.patch.object(matrix_files, "_mtx_numbers_with_pandas",
                                   lambda *args: None):
                plain = best(lambda: ours(path), 2)
            print(f"| {name} | {fast:.3f} s | {plain:.3f} s | {reference:.3f} s | "
                  f"{fast / reference:.2f}x | {plain / reference:.2f}x |")


if __name__ == "__main__":
    main()
