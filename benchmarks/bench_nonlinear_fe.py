"""Nonlinear frequency response of large matrix models with local nonlinear elements.

    python benchmarks/bench_nonlinear_fe.py [--sizes 1000,3000,10000] [--points 100]

A fixed-free chain of n masses 1/n on springs n (a discretized rod: its first natural
frequency pi/2 whatever n, Rayleigh damping C = 0.02 M + 0.002 K) with a cubic spring
at its free end and a stop (gap) at its middle: m = 2 nonlinear coordinates.  For each
n, ``condensed_sweep`` follows the periodic response over omega = 1.0 ... 2.4 (across
the first resonance, through its folds) with H = 7 and the stability of every point, in this process after the model is loaded; reported: the
whole time, the share of the reduced model of the linear part (its build, including the
factorizations), the branch points and the time per point.  The goal: a 10,000-DOF
model's 200-point branch with stability in <= 10 s, and the time beyond the reduced
model's build flat in n at fixed m.

pyHarm (``pip install pyHarm-os``) forms the full n(2H+1) system; it is compared in
benchmarks/bench_nonlinear.py on small models, where it can run.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "src"))


def write_rod(directory: Path, n: int) -> Path:
    """The chain's matrices (.npz) and model file."""
    import numpy as np
    import scipy.sparse as sp

    directory.mkdir(parents=True, exist_ok=True)
    main = np.full(n, 2.0 * n)
    main[-1] = n
    K = sp.diags([np.full(n - 1, -1.0 * n), main, np.full(n - 1, -1.0 * n)], [-1, 0, 1],
                 format="csr")
    M = sp.identity(n, format="csr") / n
    for name, matrix in (("M", M), ("K", K), ("C", (0.02 * M + 0.002 * K).tocsr())):
        sp.save_npz(directory / f"{name}.npz", matrix)
    force = ", ".join(["0"] * (n - 1) + ["0.01"])
    path = directory / f"rod{n}.toml"
    path.write_text(
        f'title = "Rod of {n} masses, cubic spring at the end, stop at the middle"\n'
        "[parameters]\nomega = 1\n"
        '[matrices]\nM = "M.npz"\nC = "C.npz"\nK = "K.npz"\n'
        f'[[harmonic]]\nomega = "omega"\nF_C = [{force}]\n'
        f'[[nonlinear]]\nname = "spring"\ncoordinates = ["q{n}"]\nforce = "2*q{n}^3"\n'
        f'[[nonlinear]]\nname = "stop"\ncoordinates = ["q{n // 2}"]\nkind = "gap"\n'
        "gap = 0.2\nstiffness = 0.5\n", encoding="utf-8")
    return path


def measure(n: int, points: int, directory: Path) -> dict:
    """One size: load, follow the branch, time it."""
    import resonant
    from resonant.analyses import condensed

    path = write_rod(directory / f"n{n}", n)
    model = resonant.load(path)
    system = model.linearize()
    built: dict[str, float] = {}
    original = condensed.linear_part

    def timed_linear_part(*args, **kwargs):  # the reduced model's share of the time
        part = original(*args, **kwargs)
        built["seconds"], built["size"] = part.seconds, part.size
        return part

    condensed.linear_part = timed_linear_part
    try:
        start = time.perf_counter()
        result = condensed.condensed_sweep(system, "omega", 1.0, 2.4, points=points,
                                           linear=False)
        seconds = time.perf_counter() - start
    finally:
        condensed.linear_part = original
    return {"n": n, "seconds": seconds, "reduced_model_seconds": built["seconds"],
            "reduced_size": built["size"], "branch_points": len(result.values),
            "unstable_points": int((~result.stable).sum()),
            "folds": sum(s.kind == "fold" for s in result.special_points),
            "per_point_ms": 1e3 * (seconds - built["seconds"]) / len(result.values),
            "warnings": list(result.warnings)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,3000,10000",
                        help="comma-separated numbers of coordinates (even)")
    parser.add_argument("--points", type=int, default=100,
                        help="about this many continuation steps across the range")
    parser.add_argument("--json", action="store_true", help="print JSON")
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    with tempfile.TemporaryDirectory() as tmp:
        rows = [measure(n, args.points, Path(tmp)) for n in sizes]
    if args.json:
        print(json.dumps(rows, indent=1))
        return 0
    print(f"{'n':>8} {'total s':>8} {'ROM s':>7} {'ROM size':>8} {'points':>7} "
          f"{'unstable':>8} {'folds':>5} {'ms/point':>8}")
    for r in rows:
        print(f"{r['n']:>8} {r['seconds']:>8.2f} {r['reduced_model_seconds']:>7.2f} "
              f"{r['reduced_size']:>8} {r['branch_points']:>7} {r['unstable_points']:>8} "
              f"{r['folds']:>5} {r['per_point_ms']:>8.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
