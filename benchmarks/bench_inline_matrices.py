"""Large inline matrices: `resonant check` of a model with inline 800 x 800 M, C, K.

Usage::

    python benchmarks/bench_inline_matrices.py [--size 800]

Writes a model of three inline n x n matrices of number literals (3.9 MB at n = 800, under
the 5 MB file limit) into a temporary folder and measures, each in a fresh process (wall
time and peak resident memory): `resonant check` on it (the number-only fast path), the
same with the fast path switched off (every entry through the expression parser, as
before), and `resonant check` of the same model with its matrices in `.npy` files (what a
user would pick instead).  Prints a markdown table.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SLOW = ("import sys; import resonant.model.inline_matrices as m; "
        "m.INLINE_EXPRESSION_SIZE = 10**9; from resonant.cli import main; "
        "sys.exit(main(sys.argv[1:]))")
FAST = "import sys; from resonant.cli import main; sys.exit(main(sys.argv[1:]))"


def matrices(n: int) -> dict[str, np.ndarray]:
    K = 2000 * np.eye(n) - 1000 * (np.eye(n, k=1) + np.eye(n, k=-1))
    return {"M": np.eye(n), "C": 2 * np.eye(n), "K": K}


def inline_text(mats: dict[str, np.ndarray]) -> str:
    def rows(a: np.ndarray) -> str:
        return "[" + ",\n".join("[" + ",".join(f"{v:g}" for v in row) + "]" for row in a) + "]"
    return "[matrices]\n" + "".join(f"{k} = {rows(a)}\n" for k, a in mats.items())


def measure(code: str, path: Path) -> tuple[float, float]:
    """Wall time (s) and peak RSS (MB) of ``resonant check path`` in a child process."""
    launcher = ("import resource, subprocess, sys, time; t = time.perf_counter(); "
                "r = subprocess.run(sys.argv[1:], capture_output=True); "
                "assert r.returncode == 0, r.stderr; "
                "print(time.perf_counter() - t, "
                "resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024)")
    out = subprocess.run([sys.executable, "-c", launcher, sys.executable, "-c", code,
                          "check", str(path)], capture_output=True, text=True, check=True,
                         cwd=ROOT, env={"PYTHONPATH": str(ROOT / "src")})
    seconds, megabytes = out.stdout.split()
    return float(seconds), float(megabytes)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=800)
    n = parser.parse_args().size
    mats = matrices(n)
    with tempfile.TemporaryDirectory() as folder:
        inline = Path(folder) / "inline.toml"
        inline.write_text(inline_text(mats))
        files = Path(folder) / "files.toml"
        for key, array in mats.items():
            np.save(Path(folder) / f"{key}.npy", array)
        files.write_text("[matrices]\n" + "".join(f'{k} = "{k}.npy"\n' for k in mats))
        rows = [("inline, number-only fast path", measure(FAST, inline)),
                ("inline, every entry parsed (fast path off)", measure(SLOW, inline)),
                (".npy files (what a user would pick instead)", measure(FAST, files))]
        size = inline.stat().st_size / 1e6
    print(f"`resonant check`, {n} x {n} M, C, K ({size:.1f} MB model file)\n")
    print("| how the matrices are given | wall time | peak memory |")
    print("|---|---|---|")
    for name, (seconds, megabytes) in rows:
        print(f"| {name} | {seconds:.2f} s | {megabytes:.0f} MB |")
    fast, slow = rows[0][1][0], rows[1][1][0]
    print(f"\nfast path {slow / fast:.1f}x faster than parsing every entry; "
          f"{fast / rows[2][1][0]:.2f}x the time of .npy files")


if __name__ == "__main__":
    main()
