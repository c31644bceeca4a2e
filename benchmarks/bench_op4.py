"""Benchmark: OP4 files read by resonant's own reader against pyYeti's reader
(docs/performance-large.md, "Nastran OUTPUT4").

The files, written by pyYeti (not timed), one matrix each:

``bigmat_le``
    a sparse symmetric stiffness of 300,000 rows (a chain with second neighbours: five
    diagonals, 1.5 million entries), binary bigmat layout, little-endian, double;
``bigmat_be``
    the same, big-endian;
``nonbigmat``
    the chain with 60,000 rows (below 65,536 rows: Nastran's non-bigmat strings), binary;
``dense``
    a dense random 2000 x 2000 matrix, binary dense layout;
``ascii_bigmat``
    the chain with 100,000 rows, ASCII bigmat (16 digits);
``ascii_dense``
    a dense random 1000 x 1000 matrix, ASCII dense.

Sides, each in a fresh process, the read timed after the imports (``before_mib``: the
resident memory after the imports; ``peak_mib``: the process's peak), one BLAS thread:

``pyyeti``
    ``pyyeti.nastran.op4.read(path, ["kaa"], sparse=...)``: what a user calls (sparse for
    the sparse layouts, dense for the dense ones);
``resonant``
    ``resonant.model.op4_files.read_op4_matrix(path, "KAA", "K")`` with
    ``resonant.model.limits.MAX_MATRIX_DIMENSION`` raised to 300,000: the file read once,
    the directory checked against the limits, the values gathered in bulk, the CSR (or
    dense) matrix built and checked finite.

Both sides' matrices are compared (bit for bit) in a separate step, not timed.

Run: ``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/bench_op4.py [KIND ...]``;
``... bench_op4.py sweep``: a sweep on the model read from the 300,000-row file (M = I,
C = 1e-3 K, a force on q1; ``auto``, ``banded`` on a tenth of the frequencies, and the
reduced route forced), docs/performance-large.md; ``... bench_op4.py reduced``: ``resonant
sweep --method reduced`` against ``--method direct`` on the 200,000-row chain (the largest
the default limits read) in a band of its five lowest modes, through the command line,
each command timed whole (a fresh process: reading, checks, the sweep).

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

#: kind -> (rows, pyYeti write options, sparse read)
KINDS: dict[str, tuple[int, dict[str, Any], bool]] = {
    "bigmat_le": (300_000, {"binary": True, "sparse": "bigmat", "endian": "<"}, True),
    "bigmat_be": (300_000, {"binary": True, "sparse": "bigmat", "endian": ">"}, True),
    "nonbigmat": (60_000, {"binary": True, "sparse": "nonbigmat"}, True),
    "dense": (2000, {"binary": True, "sparse": "dense"}, False),
    "ascii_bigmat": (100_000, {"binary": False, "sparse": "bigmat"}, True),
    "ascii_dense": (1000, {"binary": False, "sparse": "dense"}, False),
}

#: side -> (imports, not timed; the timed read)
SIDES = {
    "pyyeti": ("from pyyeti.nastran import op4\n",
               "m = op4.read(PATH, ['kaa'], sparse=SPARSE)['kaa']\n"),
    "resonant": ("import scipy.sparse\n"  # imported with pyYeti; by resonant's models too
                 "import resonant.model.limits as limits\n"
                 "limits.MAX_MATRIX_DIMENSION = 300_000\n"
                 "from resonant.model.op4_files import read_op4_matrix\n",
                 "m = read_op4_matrix(PATH, 'KAA', 'K')\n"),
}


def chain(n: int) -> Any:
    """A symmetric positive definite stiffness with five diagonals (n rows)."""
    import scipy.sparse as sp

    main = np.full(n, 3.0)
    first = np.full(n - 1, -1.0)
    second = np.full(n - 2, -0.5)
    return sp.diags([second, first, main, first, second], [-2, -1, 0, 1, 2], format="csr")


def matrix(kind: str) -> Any:
    """The matrix written for ``kind``."""
    rows, _, sparse = KINDS[kind]
    if sparse:
        return chain(rows)
    return np.random.default_rng(1).standard_normal((rows, rows))


def _child(side: str, path: str, sparse: bool) -> dict[str, float]:
    """One read in a fresh process: its time and the process's peak memory (VmHWM, which
    a new program starts afresh, unlike ru_maxrss that Linux keeps across exec)."""
    imports, read = SIDES[side]
    report = ("import json, re\nstatus = open('/proc/self/status').read()\n"
              "peak = int(re.search(r'VmHWM:\\s+(\\d+)', status).group(1)) / 1024\n"
              "print(json.dumps({'seconds': elapsed, 'peak_mib': peak, "
              "'before_mib': before}))\n")
    code = (f"import re, time\nPATH = {path!r}\nSPARSE = {sparse!r}\n{imports}"
            "before = int(re.search(r'VmRSS:\\s+(\\d+)', open('/proc/self/status').read())"
            ".group(1)) / 1024\n"
            f"start = time.perf_counter()\n{read}elapsed = time.perf_counter() - start\n"
            f"{report}")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=1800)
    result: dict[str, float] = json.loads(out.stdout.strip().splitlines()[-1])
    return result


def _same(path: str, sparse: bool) -> bool:
    """Whether both readers give the same matrix, bit for bit."""
    from pyyeti.nastran import op4

    import resonant.model.limits as limits
    from resonant.model.op4_files import read_op4_matrix

    limits.MAX_MATRIX_DIMENSION = 300_000
    theirs = op4.read(path, ["kaa"], sparse=sparse)["kaa"]
    ours = read_op4_matrix(path, "KAA", "K")
    if sparse:
        return bool((abs(theirs.tocsr() - ours) > 0).nnz == 0)
    return bool(np.array_equal(theirs, ours))


def measure(kind: str, folder: str, repeats: int) -> dict[str, Any]:
    """Write one file, read it ``repeats`` times by each side, keep the best."""
    from pyyeti.nastran import op4

    rows, options, sparse = KINDS[kind]
    path = str(Path(folder) / f"{kind}.op4")
    start = time.perf_counter()
    op4.write(path, {"kaa": matrix(kind)}, **options)
    written = time.perf_counter() - start
    best: dict[str, dict[str, float]] = {}
    for _ in range(repeats):
        for side in SIDES:
            run = _child(side, path, sparse)
            if side not in best or run["seconds"] < best[side]["seconds"]:
                best[side] = run
    return {"kind": kind, "rows": rows, "file_mib": Path(path).stat().st_size / 2**20,
            "write_seconds": written, "same": _same(path, sparse),
            **{f"{side}_{k}": v for side, run in best.items() for k, v in run.items()},
            "time_ratio": best["resonant"]["seconds"] / best["pyyeti"]["seconds"]}


def sweep_on_large(folder: str) -> dict[str, Any]:
    """The sweep on the model of the 300,000-row file (in this process)."""
    import scipy.sparse as sp
    from pyyeti.nastran import op4

    import resonant
    import resonant.model.limits as limits
    from resonant.analyses.sweep import sweep

    limits.MAX_MATRIX_DIMENSION = 300_000
    base = Path(folder)
    op4.write(str(base / "chain.op4"), {"kaa": chain(300_000)}, binary=True, sparse="bigmat")
    sp.save_npz(base / "mass.npz", sp.identity(300_000, format="csr"))
    (base / "chain.toml").write_text(
        'title = "chain"\n[parameters]\nomega = 1.0\n[matrices]\nM = "mass.npz"\n'
        'K = "chain.op4:KAA"\nC = "1e-3*K"\n[[harmonic]]\nomega = "omega"\n'
        'F_C = { q1 = 1.0 }\n', encoding="utf-8")
    start = time.perf_counter()
    system = resonant.load(base / "chain.toml").linearize()
    report: dict[str, Any] = {"load_seconds": time.perf_counter() - start}
    omegas = np.linspace(1e-3, 2e-2, 200)
    results = {}
    for label, method, chosen in (("auto", "auto", omegas), ("banded", "banded", omegas[::10]),
                                  ("reduced", "reduced", omegas)):
        start = time.perf_counter()
        results[label] = sweep(system, "omega", chosen, names=["q1"], method=method)
        report[f"{label}_seconds"] = time.perf_counter() - start
        report[f"{label}_method"] = results[label].method
    exact = np.asarray(results["banded"].amplitudes["q1"])
    report["reduced_error_q1"] = float(np.max(np.abs(
        np.asarray(results["reduced"].amplitudes["q1"])[::10] - exact)) / np.max(exact))
    print(json.dumps(report), flush=True)
    return report


#: the reduced sweep's model: rows, band (rad/s), points
REDUCED = (200_000, 1e-6, 1.5e-4, 200)


def _timed_json(command: list[str]) -> tuple[float, dict[str, Any]]:
    """A command's wall time and its JSON output."""
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    return time.perf_counter() - start, json.loads(done.stdout)


def reduced_on_large(folder: str) -> dict[str, Any]:
    """``resonant sweep`` reduced and direct on the 200,000-row chain (fresh processes)."""
    import scipy.sparse as sp
    from pyyeti.nastran import op4

    rows, low, high, points = REDUCED
    base = Path(folder)
    op4.write(str(base / "chain.op4"), {"kaa": chain(rows)}, binary=True, sparse="bigmat")
    sp.save_npz(base / "mass.npz", sp.identity(rows, format="csr"))
    model = base / "chain.toml"
    model.write_text('title = "chain"\n[parameters]\nomega = 1.0\n[matrices]\n'
                     'M = "mass.npz"\nK = "chain.op4:KAA"\nC = "1e-3*K"\n[[harmonic]]\n'
                     'omega = "omega"\nF_C = { q1 = 1.0 }\n', encoding="utf-8")
    program = [sys.executable, "-m", "resonant"]
    sweep = [*program, "sweep", str(model), "--param", "omega", "--from", str(low), "--to",
             str(high), "--points", str(points), "--only", "q1", "--json", "--timeout", "0"]
    report: dict[str, Any] = {"rows": rows, "band": [low, high], "points": points}
    results = {}
    for method in ("reduced", "direct"):
        seconds, results[method] = _timed_json([*sweep, "--method", method])
        report[f"{method}_seconds"] = seconds
        report[f"{method}_method"] = results[method]["method"]
    report["estimated_error"] = results["reduced"]["estimated_error"]
    seconds, found = _timed_json([*program, "modes", str(model), "--count", "8", "--json",
                                  "--timeout", "0"])
    natural = np.array(found["natural_frequencies"])
    report["modes_seconds"] = seconds
    report["modes_in_band"] = int(np.count_nonzero((natural >= low) & (natural <= high)))
    omega = np.array(results["reduced"]["values"])
    a, b = (np.array(results[m]["amplitudes"]["q1"], dtype=float) for m in ("reduced", "direct"))
    error = np.abs(a - b) / np.abs(b)
    away = np.min(np.abs(omega[:, None] / natural[None, :] - 1), axis=1) > 0.01
    report["points_away"] = int(away.sum())
    report["error_away"] = float(error[away].max())
    report["error_all"] = float(error.max())
    print(json.dumps(report), flush=True)
    return report


def main(kinds: list[str] | None = None, repeats: int = 3) -> list[dict[str, Any]]:
    """Measure each kind; print one JSON line per kind and return them."""
    reports = []
    for kind in kinds or list(KINDS):
        with tempfile.TemporaryDirectory() as folder:
            report = measure(kind, folder, repeats)
        print(json.dumps(report), flush=True)
        reports.append(report)
    return reports


if __name__ == "__main__":
    if sys.argv[1:] == ["sweep"]:
        with tempfile.TemporaryDirectory() as scratch:
            sweep_on_large(scratch)
    elif sys.argv[1:] == ["reduced"]:
        with tempfile.TemporaryDirectory() as scratch:
            reduced_on_large(scratch)
    else:
        main(sys.argv[1:] or None)
