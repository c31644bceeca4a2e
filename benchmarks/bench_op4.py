"""Benchmark: a 300,000-row binary OP4 file read by resonant against pyYeti's own reader
(docs/performance.md, "FE files").

The file: a generated sparse symmetric stiffness of 300,000 rows (a chain with second
neighbours: five diagonals, 1.5 million entries) in Nastran's binary bigmat layout,
written by pyYeti (not timed), about 20 MB.

Sides, each in a fresh process (its peak resident set size measured), one BLAS thread:

``pyyeti``
    ``pyyeti.nastran.op4.read(path, ["kaa"], sparse=True)``: what a user calls;
``resonant``
    ``resonant.model.op4_files.read_op4_matrix(path, "KAA", "K")`` with
    ``resonant.model.limits.MAX_MATRIX_DIMENSION`` raised to 300,000: the directory pass
    (names and sizes from the headers, checked against the limits), the read through
    pyYeti (sparse above ``MAX_DENSE_ENTRIES``), the CSR conversion and the finiteness
    check.

Run: ``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/bench_op4.py``.

Examples
--------
>>> chain(5).toarray()[0].tolist()
[3.0, -1.0, -0.5, 0.0, 0.0]
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

ROWS = 300_000

SIDES = {
    "pyyeti": ("from pyyeti.nastran import op4\n"
               "m = op4.read(PATH, ['kaa'], sparse=True)['kaa']\n"),
    "resonant": ("import resonant.model.limits as limits\n"
                 "limits.MAX_MATRIX_DIMENSION = 300_000\n"
                 "from resonant.model.op4_files import read_op4_matrix\n"
                 "m = read_op4_matrix(PATH, 'KAA', 'K')\n"),
}


def chain(n: int) -> Any:
    """A symmetric positive definite stiffness with five diagonals (n rows)."""
    import scipy.sparse as sp

    main = np.full(n, 3.0)
    first = np.full(n - 1, -1.0)
    second = np.full(n - 2, -0.5)
    return sp.diags([second, first, main, first, second], [-2, -1, 0, 1, 2], format="csr")


def _child(side: str, path: str) -> dict[str, float]:
    report = ("import json\nprint(json.dumps({'seconds': elapsed, 'nnz': int(m.nnz), "
              "'peak_mib': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))\n")
    code = (f"import resource, time\nPATH = {path!r}\nstart = time.perf_counter()\n"
            f"{SIDES[side]}elapsed = time.perf_counter() - start\n{report}")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=1800)
    result: dict[str, float] = json.loads(out.stdout.strip().splitlines()[-1])
    return result


def main(repeats: int = 3) -> dict[str, Any]:
    """Write the file, read it ``repeats`` times by each side, print and return the best."""
    from pyyeti.nastran import op4

    with tempfile.TemporaryDirectory() as folder:
        path = str(Path(folder) / "large.op4")
        start = time.perf_counter()
        op4.write(path, {"kaa": chain(ROWS)}, binary=True, sparse="bigmat")
        written = time.perf_counter() - start
        size = Path(path).stat().st_size
        best: dict[str, dict[str, float]] = {}
        for _ in range(repeats):
            for side in SIDES:
                run = _child(side, path)
                if side not in best or run["seconds"] < best[side]["seconds"]:
                    best[side] = run
    ratio = best["resonant"]["seconds"] / best["pyyeti"]["seconds"]
    report = {"rows": ROWS, "file_mib": size / 2**20, "write_seconds": written,
              **{f"{side}_{k}": v for side, run in best.items() for k, v in run.items()},
              "time_ratio": ratio}
    print(json.dumps(report, indent=1))
    return report


if __name__ == "__main__":
    main()
