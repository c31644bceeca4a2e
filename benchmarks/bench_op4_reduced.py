"""Benchmark: the reduced sweep of a large sparse model with one load and one output
against the exact direct sweep, as the number of frequencies grows
(docs/performance-large.md, "Reduced sweeps of large FE models").

Models (each written to files and loaded as a user's ``[matrices]`` model):

``chain``
    the five-diagonal chain of benchmarks/bench_op4.py, ``--rows`` rows (200,000), K from
    a binary bigmat OP4 file (written by pyYeti), M = I, C = 1e-3 K, a unit force on q1;
    the band 1e-6 to 1.5e-4 rad/s (times 200,000 / rows) holds its five lowest modes
    (damping ratios below 1e-7 at 200,000 rows, 1e-6 at 50,000); the direct method is
    ``banded`` (LAPACK gbsv, O(n) per frequency);
``solid``, ``plate``
    the 3-D cantilever block (trilinear hexahedra, dashpots on the free face) and the
    clamped Kirchhoff plate (Morley triangles) of benchmarks/corpus.py at ``--size``
    coordinates, Matrix Market files; the direct method is ``sparse`` (SuperLU per
    frequency).

For each model and each count of frequencies (``--points``, spread evenly over the band),
in one process after loading (not timed), one BLAS thread:

``reduced``
    ``sweep(system, "omega", omegas, names=[output], method="reduced")``;
``auto``
    the same with ``method="auto"`` (what it picks, and its time);
``direct``
    ``method="direct"`` on at most ``--direct-points`` of the frequencies (every k-th),
    its time scaled to all of them (a direct method's cost per frequency does not depend on
    the frequency); its responses are the reference of the reduced sweep's error there.

Wall and CPU seconds are printed (CPU: the process's, all threads; on the shared
machine the wall time of one run varies by 2-4x with the load, the CPU time less).

Run::

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/bench_op4_reduced.py \
        --models chain solid --points 200 2000

Examples
--------
>>> nested(np.linspace(0.0, 1.0, 2000), 20).size
20
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: the chain's rows and band (rad/s)
CHAIN = (200_000, 1e-6, 1.5e-4)


def nested(omegas: np.ndarray, most: int) -> np.ndarray:
    """At most ``most`` of the frequencies, every k-th."""
    return omegas[::max(1, -(-len(omegas) // most))]


def write_chain(folder: Path, rows: int) -> tuple[Path, str, tuple[float, float]]:
    """The OP4 chain model: its path, output name and band."""
    import scipy.sparse as sp
    from bench_op4 import chain

    from resonant.model.op4_files import numpy_print_options_kept, write_op4

    scale = CHAIN[0] / rows
    low, high = CHAIN[1] * scale, CHAIN[2] * scale
    with numpy_print_options_kept():
        write_op4(folder / "chain.op4", {"kaa": chain(rows)}, binary=True, sparse="bigmat")
    sp.save_npz(folder / "mass.npz", sp.identity(rows, format="csr"))
    model = folder / "chain.toml"
    model.write_text('title = "chain"\n[parameters]\nomega = 1.0\n[matrices]\n'
                     'M = "mass.npz"\nK = "chain.op4:KAA"\nC = "1e-3*K"\n[[harmonic]]\n'
                     'omega = "omega"\nF_C = { q1 = 1.0 }\n', encoding="utf-8")
    return model, "q1", (low, high)


def write_corpus(name: str, size: int, folder: Path) -> tuple[Path, str, tuple[float, float]]:
    """A corpus structure as Matrix Market files and a model: path, output, band."""
    from corpus import build, write_mtx

    structure = build(name, size)
    at = int(np.flatnonzero(structure.b)[0])
    return write_mtx(structure, folder), f"q{at + 1}", structure.band


def timed(system: Any, omegas: np.ndarray, output: str, method: str) -> dict[str, Any]:
    """One sweep: its wall and CPU seconds, the method used, the estimate, |q|."""
    from resonant.analyses.sweep import sweep

    wall, cpu = time.perf_counter(), time.process_time()
    result = sweep(system, "omega", omegas, names=[output], method=method)
    return {"wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu,
            "method": result.method, "estimated_error": result.estimated_error,
            "amplitude": np.asarray(result.amplitudes[output], dtype=float)}


def measure(model: Path, output: str, band: tuple[float, float], points: list[int],
            most: int) -> list[dict[str, Any]]:
    """The three sides at every count of frequencies."""
    import resonant

    system = resonant.load(model).linearize()
    n = len(system.coordinates)
    rows = []
    for count in points:
        omegas = np.linspace(band[0], band[1], count)
        reduced = timed(system, omegas, output, "reduced")
        auto = timed(system, omegas, output, "auto")
        chosen = nested(omegas, most)
        direct = timed(system, chosen, output, "direct")
        scale = len(omegas) / len(chosen)
        exact = direct["amplitude"]
        error = np.abs(nested(reduced["amplitude"], most) - exact) / np.abs(exact)
        rows.append({"model": model.stem, "n": n, "points": count,
                     "reduced_wall": reduced["wall"], "reduced_cpu": reduced["cpu"],
                     "reduced_estimate": reduced["estimated_error"],
                     "auto_wall": auto["wall"], "auto_cpu": auto["cpu"],
                     "auto_method": auto["method"],
                     "direct_method": direct["method"], "direct_points": len(chosen),
                     "direct_wall": direct["wall"] * scale, "direct_cpu": direct["cpu"] * scale,
                     "max_error": float(np.nanmax(error)),
                     "median_error": float(np.nanmedian(error))})
        print(json.dumps(rows[-1]), flush=True)
    return rows


def main(argv: list[str] | None = None) -> list[dict[str, Any]]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--models", nargs="+", default=["chain", "solid"])
    parser.add_argument("--points", nargs="+", type=int, default=[200, 1991])
    parser.add_argument("--size", type=int, default=50_000,
                        help="coordinates of the corpus models")
    parser.add_argument("--rows", type=int, default=CHAIN[0], help="rows of the chain")
    parser.add_argument("--direct-points", type=int, default=20,
                        help="the direct sweep solves at most this many frequencies")
    args = parser.parse_args(argv)
    rows: list[dict[str, Any]] = []
    for name in args.models:
        with tempfile.TemporaryDirectory() as scratch:
            folder = Path(scratch)
            model, output, band = (write_chain(folder, args.rows) if name == "chain"
                                   else write_corpus(name, args.size, folder))
            rows += measure(model, output, band, args.points, args.direct_points)
    return rows


if __name__ == "__main__":
    main()
